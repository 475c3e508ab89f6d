#include "spheremap/surface/ses.hpp"

#include <algorithm>
#include <cmath>
#include <cstring>
#include <limits>
#include <numbers>
#include <type_traits>

#include <fmt/format.h>

#include "atom_grid.hpp"
#include "circle_cover.hpp"
#include "../util/parallel.hpp"
#include "../util/stage_timer.hpp"
#include "spheremap/error.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/surface/contour.hpp"
#include "spheremap/surface/distance_transform.hpp"
#include "spheremap/surface/nearest_atoms.hpp"

namespace spheremap {
namespace {
using detail::AtomGrid;

// floor and ceil for |x| < 2^52 without a libm call (no SSE4.1 rounding in a default build).
inline std::int64_t floor_int(double x) {
  const auto t = static_cast<std::int64_t>(x);
  return static_cast<double>(t) > x ? t - 1 : t;
}
inline std::int64_t ceil_int(double x) {
  const auto t = static_cast<std::int64_t>(x);
  return static_cast<double>(t) < x ? t + 1 : t;
}

// Field values while the field is built: probe-centre samples hold 0 (their squared distance), samples
// inside the SAS +infinity; outside samples not (yet) reached from the border hold kUnreached.
constexpr double kUnreached = 1;

// Marks inside-the-SAS samples +infinity; every other sample holds kUnreached.
template <typename T>
void mark_accessible_surface(Grid3<T>& field, const std::vector<Atom>& atoms, double probe, int threads) {
  const double h = field.spacing;
  const T inside = std::numeric_limits<T>::infinity();
  // Plane k belongs to chunk k % threads: every sample is written by one thread only.
  detail::parallel_chunks(threads, threads, [&](std::int64_t chunk, int) {
    for (const auto& a : atoms) {
      const double reach = a.radius + probe, reach2 = reach * reach;
      const auto first = [&](int d) { return std::max<std::int64_t>(0, ceil_int((a.position[d] - reach - field.origin[d]) / h)); };
      const auto last = [&](int d) { return std::min<std::int64_t>(field.size[d] - 1, floor_int((a.position[d] + reach - field.origin[d]) / h)); };
      const std::int64_t i_first = first(0), i_last = last(0);
      std::int64_t k = first(2);
      k += ((chunk - k) % threads + threads) % threads;
      for (; k <= last(2); k += threads)
        for (std::int64_t j = first(1); j <= last(1); ++j) {
          const Vec3 row = field.point(0, j, k);
          const double dy = row[1] - a.position[1], dz = row[2] - a.position[2], rest = reach2 - (dy * dy + dz * dz);
          if (rest < -1e-9 * reach2) continue;
          const double half = std::sqrt(std::max(0.0, rest));
          const std::int64_t i0 = std::max(i_first, ceil_int((a.position[0] - half - field.origin[0]) / h) - 1);
          const std::int64_t i1 = std::min(i_last, floor_int((a.position[0] + half - field.origin[0]) / h) + 1);
          T* values = field.values.data() + field.index(0, j, k);
          // The test is monotone in |x - centre| even as rounded, so the samples that pass form an
          // interval: found from both ends of the estimate, then filled.
          auto inside_sphere = [&](std::int64_t i) { return squared_distance(field.point(i, j, k), a.position) < reach2; };
          std::int64_t lo = i0, hi = i1;
          while (lo <= i1 && !inside_sphere(lo)) ++lo;
          if (lo > i1) continue;
          while (!inside_sphere(hi)) --hi;
          std::fill(values + lo, values + hi + 1, inside);
        }
    }
  });
}

// Labels of outside samples (not inside the SAS) while reachability is decided: reached from the grid
// border through the lattice (0), or in pocket p = 1, 2, ... (value p + 1): a 6-connected set of outside
// samples that the lattice does not join to the border. Float holds these integers exactly up to 2^24.
constexpr std::int64_t kMaximumPockets = (std::int64_t{1} << 23) - 2;

// The reachability label of a sample value during the build: 0 (reached), p (pocket p), or -1 (inside
// the SAS, or a pocket beyond kMaximumPockets).
template <typename T>
inline std::int64_t label_of(T value) {
  if (value == T(0)) return 0;
  if (!(value < std::numeric_limits<T>::infinity())) return -1;
  return static_cast<std::int64_t>(value) - 1;
}

// Union-find on integer nodes, smaller root wins (deterministic).
class Components {
 public:
  explicit Components(std::size_t n) : parent_(n) {
    for (std::size_t v = 0; v < n; ++v) parent_[v] = static_cast<std::int64_t>(v);
  }
  std::int64_t find(std::int64_t v) {
    while (parent_[static_cast<std::size_t>(v)] != v) {
      auto& p = parent_[static_cast<std::size_t>(v)];
      p = parent_[static_cast<std::size_t>(p)];
      v = p;
    }
    return v;
  }
  void join(std::int64_t a, std::int64_t b) {
    a = find(a), b = find(b);
    if (a != b) parent_[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  }

 private:
  std::vector<std::int64_t> parent_;
};

// A run of samples along axis 0 that are all in pocket `label`: [first, first + length).
struct PocketRun {
  std::int64_t first;
  std::int32_t length;
  std::int32_t label;
};

struct Pockets {
  std::int64_t count = 0;
  std::vector<PocketRun> runs;  // every sample labelled as a pocket, in sample order
};

// Outside samples connected to the grid border through the lattice become 0; every other 6-connected set
// of outside samples (a pocket as far as the lattice can tell) gets its own label, pockets numbered in
// the order of their first sample (see kMaximumPockets; beyond that many, pockets are +infinity: never
// carved). Returns the pockets and where their samples are (so that resolving them later touches only
// those samples, not the whole grid).
//
// By runs: the outside samples of each row form runs, found plane by plane in parallel; runs that touch
// (the same row in adjacent planes, or adjacent rows of a plane, with overlapping spans) are joined by
// union-find (smaller root wins); each set's labels are then written back plane by plane. The sets and
// their first samples do not depend on the order of the joins, so neither do the labels.
template <typename T>
Pockets flood_and_label_pockets(Grid3<T>& field, int threads) {
  const auto [nx, ny, nz] = field.size;
  const T unreached = static_cast<T>(kUnreached);
  const std::int64_t plane = nx * ny;
  struct Run {
    std::int32_t i0, i1;  // [i0, i1] along axis 0
  };
  // plane_runs[k]: the runs of plane k, row by row, each row's in increasing i; row_start[k * (ny + 1) + j]:
  // index of row j's first run in plane k.
  std::vector<std::vector<Run>> plane_runs(static_cast<std::size_t>(nz));
  std::vector<std::int64_t> row_start(static_cast<std::size_t>(nz * (ny + 1)));
  detail::parallel_chunks(nz, threads, [&](std::int64_t k, int) {
    auto& runs = plane_runs[static_cast<std::size_t>(k)];
    std::int64_t* starts = row_start.data() + k * (ny + 1);
    for (std::int64_t j = 0; j < ny; ++j) {
      starts[j] = static_cast<std::int64_t>(runs.size());
      const T* values = field.values.data() + k * plane + j * nx;
      for (std::int64_t i = 0; i < nx;) {
        if (values[i] != unreached) {
          ++i;
          continue;
        }
        const std::int64_t i0 = i;
        while (i < nx && values[i] == unreached) ++i;
        runs.push_back({static_cast<std::int32_t>(i0), static_cast<std::int32_t>(i - 1)});
      }
    }
    starts[ny] = static_cast<std::int64_t>(runs.size());
  });
  std::vector<std::int64_t> plane_first(static_cast<std::size_t>(nz) + 1, 0);  // global index of each plane's first run
  for (std::int64_t k = 0; k < nz; ++k) plane_first[static_cast<std::size_t>(k) + 1] = plane_first[static_cast<std::size_t>(k)] + static_cast<std::int64_t>(plane_runs[static_cast<std::size_t>(k)].size());
  const std::int64_t total = plane_first.back();
  if (total == 0) return {};
  Components sets(static_cast<std::size_t>(total));
  // Joins the runs of row (j, k) with those of row (j', k') they overlap (both lists increasing in i).
  auto join_rows = [&](std::int64_t k, std::int64_t j, std::int64_t k2, std::int64_t j2) {
    const auto& a = plane_runs[static_cast<std::size_t>(k)];
    const auto& b = plane_runs[static_cast<std::size_t>(k2)];
    std::int64_t x = row_start[static_cast<std::size_t>(k * (ny + 1) + j)], x_end = row_start[static_cast<std::size_t>(k * (ny + 1) + j + 1)];
    std::int64_t y = row_start[static_cast<std::size_t>(k2 * (ny + 1) + j2)], y_end = row_start[static_cast<std::size_t>(k2 * (ny + 1) + j2 + 1)];
    while (x < x_end && y < y_end) {
      const Run& r = a[static_cast<std::size_t>(x)];
      const Run& q = b[static_cast<std::size_t>(y)];
      if (r.i0 <= q.i1 && q.i0 <= r.i1) sets.join(plane_first[static_cast<std::size_t>(k)] + x, plane_first[static_cast<std::size_t>(k2)] + y);
      if (r.i1 < q.i1) ++x;
      else ++y;
    }
  };
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j) {
      if (j > 0) join_rows(k, j, k, j - 1);
      if (k > 0) join_rows(k, j, k - 1, j);
    }
  // Per set (at its root): whether it reaches the border, and its first sample.
  std::vector<std::uint8_t> border(static_cast<std::size_t>(total), 0);
  std::vector<std::int64_t> first_sample(static_cast<std::size_t>(total), std::numeric_limits<std::int64_t>::max());
  std::vector<std::int64_t> root_of(static_cast<std::size_t>(total));
  for (std::int64_t k = 0; k < nz; ++k) {
    const auto& runs = plane_runs[static_cast<std::size_t>(k)];
    for (std::int64_t j = 0; j < ny; ++j)
      for (auto x = row_start[static_cast<std::size_t>(k * (ny + 1) + j)]; x < row_start[static_cast<std::size_t>(k * (ny + 1) + j + 1)]; ++x) {
        const Run& r = runs[static_cast<std::size_t>(x)];
        const std::int64_t run = plane_first[static_cast<std::size_t>(k)] + x, root = sets.find(run);
        root_of[static_cast<std::size_t>(run)] = root;
        border[static_cast<std::size_t>(root)] |= k == 0 || k == nz - 1 || j == 0 || j == ny - 1 || r.i0 == 0 || r.i1 == nx - 1;
        first_sample[static_cast<std::size_t>(root)] = std::min(first_sample[static_cast<std::size_t>(root)], k * plane + j * nx + r.i0);
      }
  }
  // Pockets numbered by first sample.
  std::vector<std::pair<std::int64_t, std::int64_t>> pocket_roots;  // first sample, root
  for (std::int64_t run = 0; run < total; ++run)
    if (root_of[static_cast<std::size_t>(run)] == run && !border[static_cast<std::size_t>(run)]) pocket_roots.push_back({first_sample[static_cast<std::size_t>(run)], run});
  std::sort(pocket_roots.begin(), pocket_roots.end());
  std::vector<T> value_of_root(static_cast<std::size_t>(total), T(0));
  for (std::size_t p = 0; p < pocket_roots.size(); ++p)
    value_of_root[static_cast<std::size_t>(pocket_roots[p].second)] =
        static_cast<std::int64_t>(p) < kMaximumPockets ? static_cast<T>(p + 2) : std::numeric_limits<T>::infinity();
  std::vector<std::vector<PocketRun>> plane_pockets(static_cast<std::size_t>(nz));
  detail::parallel_chunks(nz, threads, [&](std::int64_t k, int) {
    const auto& runs = plane_runs[static_cast<std::size_t>(k)];
    for (std::int64_t j = 0; j < ny; ++j) {
      T* values = field.values.data() + k * plane + j * nx;
      for (auto x = row_start[static_cast<std::size_t>(k * (ny + 1) + j)]; x < row_start[static_cast<std::size_t>(k * (ny + 1) + j + 1)]; ++x) {
        const Run& r = runs[static_cast<std::size_t>(x)];
        const T value = value_of_root[static_cast<std::size_t>(root_of[static_cast<std::size_t>(plane_first[static_cast<std::size_t>(k)] + x)])];
        std::fill(values + r.i0, values + r.i1 + 1, value);
        if (const std::int64_t label = label_of(value); label > 0)
          plane_pockets[static_cast<std::size_t>(k)].push_back({k * plane + j * nx + r.i0, r.i1 - r.i0 + 1, static_cast<std::int32_t>(label)});
      }
    }
  });
  Pockets pockets;
  pockets.count = std::min<std::int64_t>(static_cast<std::int64_t>(pocket_roots.size()), kMaximumPockets);
  for (auto& part : plane_pockets) pockets.runs.insert(pockets.runs.end(), part.begin(), part.end());
  return pockets;
}


// A vertex of the SAS (a probe position touching three atoms): the atoms, ascending, and the side of the
// plane of their centres it lies on (the two such positions are mirror images through that plane).
struct VertexKey {
  std::array<std::int32_t, 3> atoms;
  std::int32_t side;
  auto operator<=>(const VertexKey&) const = default;
};


using detail::certainly_covered;
using detail::CoverScratch;
using detail::CoverTerm;

// Probe centres on the SAS surface (see solvent_excluded_field), in grid coordinates; decides on the way
// which pockets of `field` (labelled by flood_and_label_pockets) a probe reaches from outside, and
// resolves them: 0 (probe centres) or +infinity.
//
// A probe rolling on the SAS from outside (as MSMS does) goes along its edges, the exposed arcs of the
// circles where two enlarged spheres meet, from arc to arc through the vertices where three meet. The
// lattice misses passages narrower than a step, but exposed arcs thread them (an open window between
// three enlarged spheres is crossed by the whole arcs of their three circles, none of which the third
// sphere covers). So
// the exposed arcs are computed exactly (angular intervals of each circle left uncovered by the other
// spheres), joined at their shared vertices, and joined to the outside or a pocket when one of their
// samples sees an outside sample of it among the 27 around its nearest sample along a segment outside
// every enlarged sphere. Pockets and arcs joined to the outside carve; the others do not (with
// carve_cavities, everything joined to an outside sample carves).
template <typename T>
std::vector<Vec3> surface_probe_centres(Grid3<T>& field, const std::vector<Atom>& atoms, double probe, const Pockets& pockets,
                                        bool carve_cavities, int threads, detail::StageTimer& clock) {
  const double h = field.spacing;
  const auto [nx, ny, nz] = field.size;
  const auto count = static_cast<std::int32_t>(atoms.size());
  double largest_reach = 0;
  std::vector<double> reach(atoms.size()), reach2(atoms.size());
  for (std::size_t a = 0; a < atoms.size(); ++a) {
    reach[a] = atoms[a].radius + probe;
    reach2[a] = reach[a] * reach[a];
    largest_reach = std::max(largest_reach, reach[a]);
  }
  // Overlapping enlarged spheres, by atom (ascending): only these can cover a point of an atom's sphere.
  const AtomGrid grid(atoms, largest_reach);
  constexpr std::int32_t kAtomsPerChunk = 64;
  const std::int64_t chunks = (count + kAtomsPerChunk - 1) / kAtomsPerChunk;
  std::vector<std::vector<std::int32_t>> chunk_neighbours(static_cast<std::size_t>(chunks));
  std::vector<std::int64_t> neighbour_start(atoms.size() + 1, 0);
  detail::parallel_chunks(chunks, threads, [&](std::int64_t chunk, int) {
    auto& out = chunk_neighbours[static_cast<std::size_t>(chunk)];
    std::vector<std::int32_t> found;
    for (std::int32_t i = static_cast<std::int32_t>(chunk) * kAtomsPerChunk; i < std::min(count, static_cast<std::int32_t>(chunk + 1) * kAtomsPerChunk); ++i) {
      found.clear();
      grid.near(atoms[i].position, reach[i] + largest_reach, [&](std::int32_t j) {
        if (j != i && norm(atoms[j].position - atoms[i].position) < reach[i] + reach[j]) found.push_back(j);
      });
      std::sort(found.begin(), found.end());
      out.insert(out.end(), found.begin(), found.end());
      neighbour_start[static_cast<std::size_t>(i) + 1] = static_cast<std::int64_t>(found.size());
    }
  });
  for (std::size_t a = 0; a < atoms.size(); ++a) neighbour_start[a + 1] += neighbour_start[a];
  std::vector<std::int32_t> neighbours;
  neighbours.reserve(static_cast<std::size_t>(neighbour_start.back()));
  for (auto& part : chunk_neighbours) neighbours.insert(neighbours.end(), part.begin(), part.end()), std::vector<std::int32_t>().swap(part);

  clock.lap("neighbours");
  // Whether the segment from p to q (Å) stays outside every enlarged sphere (it may touch them: p and q
  // may lie on the SAS).
  auto segment_free = [&](const Vec3& p, const Vec3& q) {
    const Vec3 d = q - p;
    const double length2 = dot(d, d);
    bool free = true;
    grid.near(0.5 * (p + q), 0.5 * std::sqrt(length2) + largest_reach, [&](std::int32_t k) {
      if (!free) return;
      const Vec3 w = p - atoms[k].position;
      const double t = length2 > 0 ? std::clamp(-dot(w, d) / length2, 0.0, 1.0) : 0.0;
      const Vec3 nearest = w + t * d;
      free = dot(nearest, nearest) >= reach2[k] * (1 - 1e-9);
    });
    return free;
  };
  auto to_grid = [&](const Vec3& p) { return Vec3{(p[0] - field.origin[0]) / h, (p[1] - field.origin[1]) / h, (p[2] - field.origin[2]) / h}; };
  auto value_at = [&](std::int64_t a, std::int64_t b, std::int64_t c) { return field.values[static_cast<std::size_t>(field.index(a, b, c))]; };
  // Calls visit(label, i, j, k) for the outside samples among the 27 around the nearest sample of `unit`.
  auto around = [&](const Vec3& unit, auto&& visit) {
    const auto ci = static_cast<std::int64_t>(std::llround(unit[0]));
    const auto cj = static_cast<std::int64_t>(std::llround(unit[1]));
    const auto ck = static_cast<std::int64_t>(std::llround(unit[2]));
    for (std::int64_t c = std::max<std::int64_t>(0, ck - 1); c <= std::min(nz - 1, ck + 1); ++c)
      for (std::int64_t b = std::max<std::int64_t>(0, cj - 1); b <= std::min(ny - 1, cj + 1); ++b)
        for (std::int64_t a = std::max<std::int64_t>(0, ci - 1); a <= std::min(nx - 1, ci + 1); ++a) {
          const std::int64_t label = label_of(value_at(a, b, c));
          if (label >= 0 && visit(label, a, b, c)) return;
        }
  };

  // The exposed arcs, atom chunk by atom chunk (circles (i, j) with i < j, by i then j; arcs by angle).
  struct ChunkArcs {
    std::int64_t arcs = 0;
    std::vector<Vec3> samples, vertices;  // grid units; the vertices (touching three atoms) once each
    std::vector<std::int32_t> sample_arc, vertex_arc;  // local arc index
    std::vector<std::pair<VertexKey, std::int32_t>> ends;  // local arc
    std::vector<std::pair<std::int32_t, std::int64_t>> links;  // local arc, label (0 outside, p pocket)
    std::vector<std::int32_t> circled, exposed;  // atoms with a circle; atoms with an exposed arc
  };
  std::vector<ChunkArcs> chunk_arcs(static_cast<std::size_t>(chunks));
  // A vertex of the SAS: its three atoms (ascending) and the side of their centres' plane it lies on.
  auto vertex_key = [&](std::int32_t a, std::int32_t b, std::int32_t c, const Vec3& point) {
    VertexKey key{a, b, c, 0};
    std::sort(key.atoms.begin(), key.atoms.end());
    const Vec3& o = atoms[key.atoms[0]].position;
    key.side = dot(cross(atoms[key.atoms[1]].position - o, atoms[key.atoms[2]].position - o), point - o) > 0;
    return key;
  };
  constexpr double kTurn = 2 * std::numbers::pi;
  std::vector<std::vector<std::int32_t>> neighbour_marks(static_cast<std::size_t>(std::max(threads, 1)));
  detail::parallel_chunks(chunks, threads, [&](std::int64_t chunk, int worker) {
    ChunkArcs& out = chunk_arcs[static_cast<std::size_t>(chunk)];
    struct Covering {
      double start, length;
      std::int32_t atom;
    };
    struct Gap {
      double from, to;
      std::int32_t from_atom, to_atom;
    };
    std::vector<Covering> coverings;
    std::vector<CoverTerm> terms;
    CoverScratch spans;
    std::vector<std::int32_t> common;
    std::vector<Gap> gaps;
    std::vector<std::int64_t> linked;
    // is_neighbour[k] == index: k is a neighbour of the atom `index` (the common neighbours of index and
    // j are then j's neighbours so marked: one pass over j's list, in its ascending order). One array per
    // worker: marks left by other atoms never equal `index`.
    auto& is_neighbour = neighbour_marks[static_cast<std::size_t>(worker)];
    if (is_neighbour.empty()) is_neighbour.assign(atoms.size(), -1);
    for (std::int32_t index = static_cast<std::int32_t>(chunk) * kAtomsPerChunk; index < std::min(count, static_cast<std::int32_t>(chunk + 1) * kAtomsPerChunk); ++index) {
      const auto& atom = atoms[index];
      const double reach_i = reach[index];
      std::int32_t burier = -1;
      for (auto m = neighbour_start[index]; m < neighbour_start[index + 1]; ++m) is_neighbour[static_cast<std::size_t>(neighbours[static_cast<std::size_t>(m)])] = index;
      for (auto m = neighbour_start[index]; m < neighbour_start[index + 1]; ++m) {
        const std::int32_t j = neighbours[static_cast<std::size_t>(m)];
        if (j <= index) continue;
        const double reach_j = reach[j];
        const Vec3 axis = atoms[j].position - atom.position;
        const double d = norm(axis);
        if (d >= reach_i + reach_j || d <= std::abs(reach_i - reach_j) || d == 0) continue;
        out.circled.push_back(index), out.circled.push_back(j);
        const double along = (d * d + reach_i * reach_i - reach_j * reach_j) / (2 * d);
        const double circle_radius = std::sqrt(std::max(0.0, reach_i * reach_i - along * along));
        const Vec3 unit_axis = (1 / d) * axis;
        const Vec3 centre = atom.position + along * unit_axis;
        const Vec3 helper = std::abs(unit_axis[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
        const Vec3 u = normalized(cross(unit_axis, helper));
        const Vec3 v = cross(unit_axis, u);
        // The angles covered by each other enlarged sphere k: |p(θ) - c_k|² < R_k² with
        // p(θ) = centre + ρ (cos θ u + sin θ v), i.e. 2ρ m cos(θ - φ) < room, where (a, b) = m (cos φ, sin φ)
        // are the coordinates of centre - c_k in the circle's plane; a whole circle inside k is skipped.
        // Most circles of a protein are buried: skip the circle when one enlarged sphere holds all of it
        // (its farthest point from that sphere's centre is inside); only then are the intervals computed.
        // Only a sphere overlapping both can cover a point of the circle: the neighbours common to
        // index and j (in ascending order), about half of index's.
        auto holds_circle = [&](std::int32_t other) {
          const Vec3 offset = atoms[other].position - centre;
          const double a = dot(offset, unit_axis), b2 = std::max(0.0, dot(offset, offset) - a * a);
          const double far = circle_radius + std::sqrt(b2);
          return a * a + far * far < reach2[other] * (1 - 1e-12);
        };
        // The sphere that held index's previous circle often holds this one too (neighbouring circles of
        // one atom): tried before the lists are merged. A sphere holding the circle overlaps both spheres,
        // so it is among the common neighbours: the decision is the one the loop below would make.
        if (burier >= 0 && burier != j && holds_circle(burier)) continue;
        common.resize(static_cast<std::size_t>(neighbour_start[j + 1] - neighbour_start[j]));
        std::size_t shared = 0;
        for (auto y = neighbour_start[j]; y < neighbour_start[j + 1]; ++y) {
          const std::int32_t q = neighbours[static_cast<std::size_t>(y)];
          common[shared] = q;
          shared += is_neighbour[static_cast<std::size_t>(q)] == index;
        }
        common.resize(shared);
        bool buried = false;
        for (std::size_t n = 0; n < common.size() && !buried; ++n)
          if (holds_circle(common[n])) buried = true, burier = common[n];
        if (buried) continue;
        terms.clear();
        bool whole = false;
        for (const std::int32_t k : common) {
          const Vec3 offset = centre - atoms[k].position;
          const double a = dot(offset, u), b = dot(offset, v), along_axis = dot(offset, unit_axis);
          const double room = reach2[k] - (a * a + b * b + along_axis * along_axis) - circle_radius * circle_radius;
          const double m = std::sqrt(a * a + b * b), spread = 2 * circle_radius * m;
          if (room >= spread) {
            whole = true;  // all of it (up to rounding: the test above missed it)
            break;
          }
          if (room > -spread) terms.push_back({a, b, room, spread, k});
        }
        // Most of the rest are covered by several spheres together: decided without trigonometry when
        // the union covers the circle with room to spare (certainly_covered); the angles are computed,
        // as before, only for the others.
        if (whole || certainly_covered(terms, spans)) continue;
        coverings.clear();
        for (const CoverTerm& t : terms) {
          const double half = std::acos(t.room / t.spread);  // exposed: |θ - φ| <= half
          double start = std::atan2(t.b, t.a) + half;
          start -= kTurn * std::floor(start / kTurn);
          coverings.push_back({start, 2 * (std::numbers::pi - half), t.atom});
        }
        if (coverings.size() == 1 && coverings.front().length >= kTurn) continue;
        auto point_at = [&](double angle) { return centre + circle_radius * (std::cos(angle) * u + std::sin(angle) * v); };
        // Exposed arcs: the gaps between the merged covered intervals, [from, to] with the atoms whose
        // spheres end there (-1: the whole circle is exposed).
        gaps.clear();
        if (coverings.empty()) {
          gaps.push_back({0, kTurn, -1, -1});
        } else {
          std::sort(coverings.begin(), coverings.end(), [](const Covering& x, const Covering& y) {
            return x.start < y.start || (x.start == y.start && x.atom < y.atom);
          });
          const double first = coverings.front().start;
          double reached = first + coverings.front().length;
          std::int32_t owner = coverings.front().atom;
          for (const auto& c : coverings)  // intervals wrapping past a full turn cover the start again
            if (c.start + c.length - kTurn > reached) reached = c.start + c.length - kTurn, owner = c.atom;
          for (std::size_t c = 1; c < coverings.size(); ++c) {
            const Covering& next = coverings[c];
            if (next.start > reached) {
              gaps.push_back({reached, next.start, owner, next.atom});
              reached = next.start + next.length, owner = next.atom;
            } else if (next.start + next.length > reached) {
              reached = next.start + next.length, owner = next.atom;
            }
          }
          if (reached < first + kTurn) gaps.push_back({reached, first + kTurn, owner, coverings.front().atom});
        }
        const auto steps = std::max<std::int64_t>(8, ceil_int(kTurn * circle_radius / (0.5 * h)));
        const double step_angle = kTurn / static_cast<double>(steps);
        if (!gaps.empty()) out.exposed.push_back(index), out.exposed.push_back(j);
        for (const Gap& gap : gaps) {
          const auto arc = static_cast<std::int32_t>(out.arcs++);
          linked.clear();
          if (gap.from_atom >= 0) {
            for (const auto& [angle, third] : {std::pair{gap.from, gap.from_atom}, std::pair{gap.to, gap.to_atom}}) {
              const Vec3 corner = point_at(angle);
              out.ends.push_back({vertex_key(index, j, third, corner), arc});
              if (third > j) out.vertices.push_back(to_grid(corner)), out.vertex_arc.push_back(arc);
            }
          }
          // Samples every half step strictly inside the arc (angles 2π s / steps, as on a whole circle).
          const std::int64_t s0 = gap.from_atom < 0 ? 0 : floor_int(gap.from / step_angle) + 1;
          for (std::int64_t s = s0; static_cast<double>(s) * step_angle < gap.to; ++s) {
            const double angle = kTurn * static_cast<double>(((s % steps) + steps) % steps) / static_cast<double>(steps);
            const Vec3 point = point_at(angle);
            const Vec3 unit = to_grid(point);
            out.samples.push_back(unit);
            out.sample_arc.push_back(arc);
            around(unit, [&](std::int64_t label, std::int64_t a, std::int64_t b, std::int64_t c) {
              if (std::find(linked.begin(), linked.end(), label) != linked.end()) return false;
              if (!segment_free(point, field.point(a, b, c))) return false;
              linked.push_back(label);
              out.links.push_back({arc, label});
              return false;
            });
          }
        }
      }
    }
  });
  clock.lap("arcs");
  // Whether the radial projections onto an atom's sphere need testing: not when the sphere meets another
  // in a circle and none of its circles has an exposed arc. Then nothing of it is exposed (an exposed
  // part short of the whole sphere is bounded by exposed arcs), and that is true of about a third of a
  // protein's atoms.
  std::vector<std::uint8_t> face(atoms.size(), 0);  // bit 1: some circle; bit 2: some exposed arc
  for (auto& part : chunk_arcs) {
    for (const std::int32_t a : part.circled) face[static_cast<std::size_t>(a)] |= 1;
    for (const std::int32_t a : part.exposed) face[static_cast<std::size_t>(a)] |= 2;
    std::vector<std::int32_t>().swap(part.circled), std::vector<std::int32_t>().swap(part.exposed);
  }
  // Components of outside, pockets and arcs: nodes 0 (outside), 1..pockets, then the arcs in order.
  std::vector<std::int64_t> arc_start(static_cast<std::size_t>(chunks) + 1, 0);
  for (std::int64_t c = 0; c < chunks; ++c) arc_start[static_cast<std::size_t>(c) + 1] = arc_start[static_cast<std::size_t>(c)] + chunk_arcs[static_cast<std::size_t>(c)].arcs;
  const std::int64_t first_arc = 1 + pockets.count;
  Components components(static_cast<std::size_t>(first_arc + arc_start.back()));
  std::vector<std::pair<VertexKey, std::int64_t>> ends;
  for (std::int64_t c = 0; c < chunks; ++c) {
    const auto& part = chunk_arcs[static_cast<std::size_t>(c)];
    const std::int64_t offset = first_arc + arc_start[static_cast<std::size_t>(c)];
    for (const auto& [arc, label] : part.links) components.join(offset + arc, label);
    for (const auto& [key, arc] : part.ends) ends.push_back({key, offset + arc});
  }
  std::sort(ends.begin(), ends.end());
  for (std::size_t e = 1; e < ends.size(); ++e)
    if (ends[e].first == ends[e - 1].first) components.join(ends[e].second, ends[e - 1].second);
  std::vector<std::uint8_t> carves(static_cast<std::size_t>(first_arc + arc_start.back()), 0);
  // With carve_cavities, every component holding an outside sample carves.
  std::vector<std::uint8_t> root_carves(carves.size(), 0);
  if (carve_cavities)
    for (std::int64_t label = 0; label < first_arc; ++label) root_carves[static_cast<std::size_t>(components.find(label))] = 1;
  for (std::size_t node = 0; node < carves.size(); ++node) {
    const std::int64_t root = components.find(static_cast<std::int64_t>(node));
    carves[node] = root == 0 || root_carves[static_cast<std::size_t>(root)];
  }
  // Pockets a probe reaches become probe centres; the others +infinity.
  for (const PocketRun& run : pockets.runs)
    std::fill_n(field.values.begin() + run.first, run.length,
                carves[static_cast<std::size_t>(run.label)] ? T(0) : std::numeric_limits<T>::infinity());

  clock.lap("pockets");
  // A point of the SAS counts as a probe centre when its arc carves; other points (radial projections,
  // on the faces) when a carving sample (0) is among the 27 around their nearest sample.
  auto connected = [&](const Vec3& unit) {
    const auto ci = static_cast<std::int64_t>(std::llround(unit[0]));
    const auto cj = static_cast<std::int64_t>(std::llround(unit[1]));
    const auto ck = static_cast<std::int64_t>(std::llround(unit[2]));
    for (std::int64_t c = std::max<std::int64_t>(0, ck - 1); c <= std::min(nz - 1, ck + 1); ++c)
      for (std::int64_t b = std::max<std::int64_t>(0, cj - 1); b <= std::min(ny - 1, cj + 1); ++b)
        for (std::int64_t a = std::max<std::int64_t>(0, ci - 1); a <= std::min(nx - 1, ci + 1); ++a)
          if (value_at(a, b, c) == T(0)) return true;
    return false;
  };
  std::vector<std::vector<Vec3>> chunk_centres(static_cast<std::size_t>(chunks));
  struct Coverer {
    Vec3 centre;
    double reach2;
  };
  detail::parallel_chunks(chunks, threads, [&](std::int64_t chunk, int) {
    auto& out = chunk_centres[static_cast<std::size_t>(chunk)];
    std::vector<Coverer> coverers;
    for (std::int32_t index = static_cast<std::int32_t>(chunk) * kAtomsPerChunk; index < std::min(count, static_cast<std::int32_t>(chunk + 1) * kAtomsPerChunk); ++index) {
      if (face[static_cast<std::size_t>(index)] == 1) continue;  // buried
      const auto& atom = atoms[index];
      // Whether p (on this atom's enlarged sphere) is strictly inside another one (only the overlapping
      // spheres can hold it). Which sphere holds p does not matter, so the list is kept in the order of
      // last use: neighbouring samples are mostly held by the sphere that held the one before.
      coverers.clear();
      for (auto m = neighbour_start[index]; m < neighbour_start[index + 1]; ++m) {
        const std::int32_t other = neighbours[static_cast<std::size_t>(m)];
        coverers.push_back({atoms[other].position, reach2[other]});
      }
      auto covered = [&](const Vec3& p) {
        for (auto c = coverers.begin(); c != coverers.end(); ++c)
          if (squared_distance(p, c->centre) < c->reach2) {
            std::rotate(coverers.begin(), c, c + 1);
            return true;
          }
        return false;
      };
      const double outer = reach[index], inner = outer - h;
      // In crevices narrower than a grid step no sample is outside the SAS, yet a probe fits: every
      // sample just inside an enlarged sphere (within one step) projects radially onto it, and the
      // projection is a probe centre when no other enlarged sphere covers it.
      const auto first = [&](int d) { return std::max<std::int64_t>(0, ceil_int((atom.position[d] - outer - field.origin[d]) / h)); };
      const auto last = [&](int d) { return std::min<std::int64_t>(field.size[d] - 1, floor_int((atom.position[d] + outer - field.origin[d]) / h)); };
      for (std::int64_t k = first(2); k <= last(2); ++k)
        for (std::int64_t j = first(1); j <= last(1); ++j) {
          const Vec3 row = field.point(0, j, k);
          const double dy = row[1] - atom.position[1], dz = row[2] - atom.position[2], across = dy * dy + dz * dz;
          const double rest = outer * outer - across;
          if (rest < -1e-9 * outer * outer) continue;
          const double half = std::sqrt(std::max(0.0, rest));
          const std::int64_t i0 = std::max(first(0), ceil_int((atom.position[0] - half - field.origin[0]) / h) - 1);
          const std::int64_t i1 = std::min(last(0), floor_int((atom.position[0] + half - field.origin[0]) / h) + 1);
          // Samples deeper than `inner` (with a one-sample margin) are skipped without a test.
          std::int64_t skip0 = i1 + 1, skip1 = i1;
          if (inner > 0 && inner * inner - across > 0) {
            const double core = std::sqrt(inner * inner - across);
            skip0 = ceil_int((atom.position[0] - core - field.origin[0]) / h) + 1;
            skip1 = floor_int((atom.position[0] + core - field.origin[0]) / h) - 1;
          }
          for (std::int64_t i = i0; i <= i1; ++i) {
            if (i >= skip0 && i <= skip1) {
              i = skip1;
              continue;
            }
            const Vec3 x = field.point(i, j, k);
            const double distance = norm(x - atom.position);
            if (distance >= outer || distance < inner || distance == 0) continue;
            const Vec3 centre = atom.position + (outer / distance) * (x - atom.position);
            if (covered(centre)) continue;
            const Vec3 unit = to_grid(centre);
            if (connected(unit)) out.push_back(unit);
          }
        }
    }
    // Probe centres touching two atoms lie on the circles where their enlarged spheres meet: these shape
    // the re-entrant (concave) parts of the surface (samples every half step, and the vertices where
    // three spheres meet).
    const auto& arcs = chunk_arcs[static_cast<std::size_t>(chunk)];
    const std::int64_t offset = first_arc + arc_start[static_cast<std::size_t>(chunk)];
    for (std::size_t s = 0; s < arcs.samples.size(); ++s)
      if (carves[static_cast<std::size_t>(offset + arcs.sample_arc[s])]) out.push_back(arcs.samples[s]);
    for (std::size_t s = 0; s < arcs.vertices.size(); ++s)
      if (carves[static_cast<std::size_t>(offset + arcs.vertex_arc[s])]) out.push_back(arcs.vertices[s]);
  });
  chunk_arcs.clear();
  clock.lap("projections");
  std::vector<std::int64_t> part_start(chunk_centres.size() + 1, 0);
  for (std::size_t c = 0; c < chunk_centres.size(); ++c) part_start[c + 1] = part_start[c] + static_cast<std::int64_t>(chunk_centres[c].size());
  const auto total = static_cast<std::size_t>(part_start.back());
  // In blocks of 8³ samples, block by block along a Morton curve, so that consecutive centres touch the same
  // part of the grid (the order does not change the field: lowering is a min).
  auto block_key = [](const Vec3& c) {
    // The low 10 bits of b, moved to every third bit.
    auto spread = [](std::uint64_t b) {
      b &= 0x3ff;
      b = (b | b << 16) & 0x30000ffu;
      b = (b | b << 8) & 0x300f00fu;
      b = (b | b << 4) & 0x30c30c3u;
      b = (b | b << 2) & 0x9249249u;
      return b;
    };
    std::uint64_t key = 0;
    for (int d = 0; d < 3; ++d) key |= spread(static_cast<std::uint64_t>(std::max(0.0, c[d]) / 8)) << d;
    return key;
  };
  // Each centre as (block key << 32 | its index), sorted as whole words: by key, ties in index order
  // (the chunks' order), with a least-significant-digit radix sort over the key's bits only. Linear and
  // sequential, where a comparison sort of a million centres took a tenth of a second on one thread.
  // Blocks of 8 samples need at most 10 bits per axis (grids up to 8192 samples a side; the memory
  // budget stops far sooner).
  std::vector<std::uint64_t> order(total), next(total);
  std::vector<std::uint64_t> part_largest(chunk_centres.size(), 0);
  detail::parallel_chunks(static_cast<std::int64_t>(chunk_centres.size()), threads, [&](std::int64_t part, int) {
    const auto& centres = chunk_centres[static_cast<std::size_t>(part)];
    const auto start = static_cast<std::size_t>(part_start[static_cast<std::size_t>(part)]);
    std::uint64_t largest = 0;
    for (std::size_t c = 0; c < centres.size(); ++c) {
      const std::uint64_t key = block_key(centres[c]);
      largest = std::max(largest, key);
      order[start + c] = key << 32 | static_cast<std::uint64_t>(start + c);
    }
    part_largest[static_cast<std::size_t>(part)] = largest;
  });
  std::uint64_t largest = 0;
  for (const auto l : part_largest) largest = std::max(largest, l);
  constexpr int kDigit = 11;
  std::vector<std::size_t> digit_start((std::size_t{1} << kDigit) + 1);
  for (int shift = 0; shift < 32 && (largest >> shift) != 0; shift += kDigit) {
    std::fill(digit_start.begin(), digit_start.end(), 0);
    const std::uint64_t mask = (std::uint64_t{1} << kDigit) - 1;
    for (const std::uint64_t c : order) ++digit_start[((c >> (32 + shift)) & mask) + 1];
    for (std::size_t d = 1; d < digit_start.size(); ++d) digit_start[d] += digit_start[d - 1];
    for (const std::uint64_t c : order) next[digit_start[(c >> (32 + shift)) & mask]++] = c;
    order.swap(next);
  }
  std::vector<Vec3> sorted(total);
  detail::parallel_chunks(threads, threads, [&](std::int64_t chunk, int) {
    const std::size_t from = total * static_cast<std::size_t>(chunk) / static_cast<std::size_t>(threads);
    const std::size_t to = total * static_cast<std::size_t>(chunk + 1) / static_cast<std::size_t>(threads);
    for (std::size_t c = from; c < to; ++c) {
      const auto index = static_cast<std::int64_t>(order[c] & 0xffffffffu);
      const auto part = static_cast<std::size_t>(std::upper_bound(part_start.begin(), part_start.end(), index) - part_start.begin() - 1);
      sorted[c] = chunk_centres[part][static_cast<std::size_t>(index - part_start[part])];
    }
  });
  return sorted;
}

// std::llround (half away from zero) without a libm call, for |x| < 2^52.
inline std::int64_t round_int(double x) {
  const auto t = static_cast<std::int64_t>(x);  // towards zero; x - t is exact
  const double rest = x - static_cast<double>(t);
  return rest >= 0.5 ? t + 1 : rest <= -0.5 ? t - 1 : t;
}

// Runs of this many samples along axis 0 (segment i / kSegment of row (j, k)) tell lower_near_centres
// which rows it may skip.
constexpr std::int64_t kSegment = 8;

// values[m] = min(values[m], across + (m + start)²) for m in [0, length): one row of a ball.
template <typename T>
inline void lower_row(T* values, std::int32_t length, T across, T start) {
  for (std::int32_t m = 0; m < length; ++m) {
    const T dx = static_cast<T>(m) + start;
    const T value = across + dx * dx;
    values[m] = value < values[m] ? value : values[m];
  }
}

// The same for a row whose `padded` samples (a multiple of 4, at most length + 3) may all be read and
// written: whole vectors with the samples past `length` masked out, rather than a vector loop with a
// tail for every row (rows are short: 5 to 19 samples), which cost more in loop control and branch
// misses than in arithmetic. The values are those of lower_row to the last bit.
#if defined(__GNUC__)
using Floats = float __attribute__((vector_size(16)));
using Ints = std::int32_t __attribute__((vector_size(16)));

// Vectors [0, vectors) of a padded row, unrolled.
template <int vectors>
inline void lower_vectors(float* values, Floats m, Floats end, Floats a, Floats s) {
  const Floats four = {4, 4, 4, 4};
  for (int q = 0; q < vectors; ++q, m += four) {
    Floats old;
    std::memcpy(&old, values + 4 * q, sizeof old);
    const Floats dx = m + s;
    const Floats value = a + dx * dx;
    const Ints take = (value < old) & (m < end);
    const Floats out = reinterpret_cast<Floats>((reinterpret_cast<Ints>(value) & take) | (reinterpret_cast<Ints>(old) & ~take));
    std::memcpy(values + 4 * q, &out, sizeof out);
  }
}
#endif

inline void lower_row_padded(float* values, std::int32_t padded, std::int32_t length, float across, float start) {
#if defined(__GNUC__)
  const Floats m = {0, 1, 2, 3};
  const auto last = static_cast<float>(length);
  const Floats end = {last, last, last, last}, a = {across, across, across, across}, s = {start, start, start, start};
  switch (padded / 4) {
    case 1: return lower_vectors<1>(values, m, end, a, s);
    case 2: return lower_vectors<2>(values, m, end, a, s);
    case 3: return lower_vectors<3>(values, m, end, a, s);
    case 4: return lower_vectors<4>(values, m, end, a, s);
    case 5: return lower_vectors<5>(values, m, end, a, s);
    default: break;
  }
  (void)padded;
#endif
  lower_row(values, length, across, start);
}
inline void lower_row_padded(double* values, std::int32_t, std::int32_t length, double across, double start) {
  lower_row(values, length, across, start);
}

// The same eight lanes at a time, for a row whose `padded` samples (a multiple of 8, at most length + 7)
// may all be read and written; inlined into a function compiled for AVX2 (lower_interior_avx2) this is
// one 256-bit operation per eight samples. The values are those of lower_row to the last bit.
#if defined(__GNUC__) && defined(__x86_64__)
#define SPHEREMAP_LOWER_AVX2 1
using Floats8 = float __attribute__((vector_size(32)));
using Ints8 = std::int32_t __attribute__((vector_size(32)));

template <int vectors>
[[gnu::always_inline]] inline void lower_vectors8(float* values, Floats8 m, Floats8 end, Floats8 a, Floats8 s) {
  const Floats8 eight = {8, 8, 8, 8, 8, 8, 8, 8};
  for (int q = 0; q < vectors; ++q, m += eight) {
    Floats8 old;
    std::memcpy(&old, values + 8 * q, sizeof old);
    const Floats8 dx = m + s;
    const Floats8 value = a + dx * dx;
    const Ints8 take = (value < old) & (m < end);
    const Floats8 out = reinterpret_cast<Floats8>((reinterpret_cast<Ints8>(value) & take) | (reinterpret_cast<Ints8>(old) & ~take));
    std::memcpy(values + 8 * q, &out, sizeof out);
  }
}

[[gnu::always_inline]] inline void lower_row_padded8(float* values, std::int32_t padded, std::int32_t length, float across, float start) {
  const Floats8 m = {0, 1, 2, 3, 4, 5, 6, 7};
  const auto last = static_cast<float>(length);
  const Floats8 end = {last, last, last, last, last, last, last, last};
  const Floats8 a = {across, across, across, across, across, across, across, across};
  const Floats8 s = {start, start, start, start, start, start, start, start};
  switch (padded / 8) {
    case 1: return lower_vectors8<1>(values, m, end, a, s);
    case 2: return lower_vectors8<2>(values, m, end, a, s);
    case 3: return lower_vectors8<3>(values, m, end, a, s);
    default: break;
  }
  lower_row(values, length, across, start);
}
#endif

// A row of the ball that lower_near_centres lowers around a centre's nearest sample.
struct BallRow {
  double dj, first;                  // dj; the offset of the row's first sample along axis 0 (-half)
  std::int64_t offset, segment_row;  // of the first sample in the field; of the row's segments
  std::int32_t half, padded, padded8, length;  // padded: to a multiple of 4; padded8: of 8
};

// Whether segment flags [i0 / kSegment, i1 / kSegment] of a row hold an open one. A row of at most
// 2 kSegment + 1 samples spans at most three segments (its first, its last and the one between); `wide`
// rows are checked segment by segment.
[[gnu::always_inline]] inline bool any_open(const std::uint8_t* flags, std::int64_t i0, std::int64_t i1, bool wide) {
  const auto g0 = static_cast<std::uint64_t>(i0) / kSegment, g1 = static_cast<std::uint64_t>(i1) / kSegment;
  std::uint8_t any = flags[g0] | flags[g1] | flags[(g0 + g1) / 2];
  if (wide)
    for (auto g = g0 + 1; g < g1; ++g) any |= flags[g];
  return any != 0;
}

// One centre away from the grid's border: its ball's rows in planes dk, dk + step, ... up to extent.
struct InteriorBall {
  float* centre_sample;                  // the centre's nearest sample
  const std::uint8_t* centre_segments;   // the flags of its row
  std::int64_t ci;                       // its index along axis 0
  double fx, fy, fz;                     // centre - nearest sample (grid units)
  const BallRow* rows;
  const std::size_t* plane_rows;
  std::int64_t extent;
  bool wide;
};

template <int kLanes>
[[gnu::always_inline]] inline void lower_interior(const InteriorBall& ball, std::int64_t dk, std::int64_t step) {
  for (; dk <= ball.extent; dk += step) {
    const double z = static_cast<double>(dk) - ball.fz, z2 = z * z;
    const BallRow* end = ball.rows + ball.plane_rows[static_cast<std::size_t>(dk + ball.extent + 1)];
    for (const BallRow* row = ball.rows + ball.plane_rows[static_cast<std::size_t>(dk + ball.extent)]; row != end; ++row) {
      if (!any_open(ball.centre_segments + row->segment_row, ball.ci - row->half, ball.ci + row->half, ball.wide)) continue;
      const double y = row->dj - ball.fy;
      const auto across = static_cast<float>(z2 + y * y), start = static_cast<float>(row->first - ball.fx);
#if defined(SPHEREMAP_LOWER_AVX2)
      if constexpr (kLanes == 8) {
        lower_row_padded8(ball.centre_sample + row->offset, row->padded8, row->length, across, start);
        continue;
      }
#endif
      lower_row_padded(ball.centre_sample + row->offset, row->padded, row->length, across, start);
    }
  }
}

void lower_interior_four_lanes(const InteriorBall& ball, std::int64_t dk, std::int64_t step) { lower_interior<4>(ball, dk, step); }
#if defined(SPHEREMAP_LOWER_AVX2)
[[gnu::target("avx2")]] void lower_interior_avx2(const InteriorBall& ball, std::int64_t dk, std::int64_t step) {
  lower_interior<8>(ball, dk, step);
}
#endif

// Lowers every sample within `radius` (grid units) of a centre (and some a little farther: any sample
// may take its exact distance to a valid centre) to its squared distance in grid units², except where
// every sample of the row's segments is at most `settled` (grid units²): such rows keep their values.
// Rows of a ball of radius `radius` + sqrt(3)/2 around the nearest sample hold every sample within
// `radius` of the centre; they come from one table, so the inner loop has no square root or rounding.
// Plane k belongs to chunk k % threads; min is exact and order-free, so the result is deterministic.
template <typename T>
void lower_near_centres(Grid3<T>& field, const std::vector<Vec3>& centres, double radius, double settled, int threads, bool use_avx2) {
  const auto [nx, ny, nz] = field.size;
  const double reach = radius + std::sqrt(3.0) / 2 + 1e-9;
  const auto extent = static_cast<std::int64_t>(std::ceil(reach));
  const std::int64_t plane = nx * ny, segments = (nx + kSegment - 1) / kSegment;
  // The rows of the ball, plane by plane (dk ascending, then dj): offsets from the nearest sample.
  std::vector<BallRow> rows;
  std::vector<std::size_t> plane_rows;  // rows of plane dk: [plane_rows[dk + extent], plane_rows[dk + extent + 1])
  for (std::int64_t dk = -extent; dk <= extent; ++dk) {
    plane_rows.push_back(rows.size());
    for (std::int64_t dj = -extent; dj <= extent; ++dj) {
      const double rest = reach * reach - static_cast<double>(dk * dk + dj * dj);
      if (rest < 0) continue;
      const auto half = static_cast<std::int32_t>(std::floor(std::sqrt(rest)));
      rows.push_back({static_cast<double>(dj), static_cast<double>(-half), dk * plane + dj * nx - half, (dk * ny + dj) * segments, half,
                      (2 * half + 1 + 3) / 4 * 4, (2 * half + 1 + 7) / 8 * 8, 2 * half + 1});
    }
  }
  plane_rows.push_back(rows.size());
  bool wide = false;
  for (const BallRow& row : rows) wide = wide || row.length > 2 * kSegment + 1;
  // open[segment]: some sample of the segment is above `settled`.
  std::vector<std::uint8_t> open(static_cast<std::size_t>(segments * ny * nz));
  const T limit = static_cast<T>(settled);
  // Sample by sample into bytes (a loop that vectorizes), then a segment's 8 bytes read as one word.
  static_assert(kSegment == sizeof(std::uint64_t));
  std::vector<std::vector<std::uint8_t>> above(static_cast<std::size_t>(threads), std::vector<std::uint8_t>(static_cast<std::size_t>(segments * kSegment), 0));
  detail::parallel_chunks(nz, threads, [&](std::int64_t k, int worker) {
    std::uint8_t* over = above[static_cast<std::size_t>(worker)].data();
    for (std::int64_t j = 0; j < ny; ++j) {
      const T* values = field.values.data() + k * plane + j * nx;
      std::uint8_t* flags = open.data() + (k * ny + j) * segments;
      for (std::int64_t i = 0; i < nx; ++i) over[i] = values[i] > limit;
      for (std::int64_t g = 0; g < segments; ++g) {
        std::uint64_t word;
        std::memcpy(&word, over + g * kSegment, sizeof word);
        flags[g] = word != 0;
      }
    }
  });
  // Interior balls of a float field go eight lanes at a time where the processor has AVX2.
  auto lower_interior_rows = lower_interior_four_lanes;
#if defined(SPHEREMAP_LOWER_AVX2)
  if (use_avx2 && __builtin_cpu_supports("avx2")) lower_interior_rows = lower_interior_avx2;
#else
  (void)use_avx2;
#endif
  detail::parallel_chunks(threads, threads, [&](std::int64_t chunk, int) {
    for (const auto& c : centres) {
      const std::int64_t ci = round_int(c[0]), cj = round_int(c[1]), ck = round_int(c[2]);
      const double fx = c[0] - static_cast<double>(ci), fy = c[1] - static_cast<double>(cj), fz = c[2] - static_cast<double>(ck);
      std::int64_t dk = -extent;
      dk += (((chunk - (ck + dk)) % threads) + threads) % threads;
      // Away from the border (the padded rows included), no row needs clipping.
      if (ci - extent >= 0 && cj - extent >= 0 && ck - extent >= 0 && ci + extent + 7 < nx && cj + extent < ny && ck + extent < nz) {
        T* centre_sample = field.values.data() + ck * plane + cj * nx + ci;
        const std::uint8_t* centre_segments = open.data() + (ck * ny + cj) * segments;
        if constexpr (std::is_same_v<T, float>) {
          lower_interior_rows({centre_sample, centre_segments, ci, fx, fy, fz, rows.data(), plane_rows.data(), extent, wide}, dk, threads);
          continue;
        }
        for (; dk <= extent; dk += threads) {
          const double z = static_cast<double>(dk) - fz, z2 = z * z;
          const BallRow* end = rows.data() + plane_rows[static_cast<std::size_t>(dk + extent + 1)];
          for (const BallRow* row = rows.data() + plane_rows[static_cast<std::size_t>(dk + extent)]; row != end; ++row) {
            if (!any_open(centre_segments + row->segment_row, ci - row->half, ci + row->half, wide)) continue;
            const double y = row->dj - fy;
            lower_row_padded(centre_sample + row->offset, row->padded, row->length, static_cast<T>(z2 + y * y), static_cast<T>(row->first - fx));
          }
        }
        continue;
      }
      for (; dk <= extent; dk += threads) {
        const std::int64_t k = ck + dk;
        if (k < 0 || k >= nz) continue;
        const double z = static_cast<double>(dk) - fz, z2 = z * z;
        for (auto r = plane_rows[static_cast<std::size_t>(dk + extent)]; r < plane_rows[static_cast<std::size_t>(dk + extent + 1)]; ++r) {
          const BallRow& row = rows[r];
          const std::int64_t j = cj + static_cast<std::int64_t>(row.dj);
          if (j < 0 || j >= ny) continue;
          const std::int64_t i0 = std::max<std::int64_t>(ci - row.half, 0), i1 = std::min<std::int64_t>(ci + row.half, nx - 1);
          if (i0 > i1 || !any_open(open.data() + (k * ny + j) * segments, i0, i1, wide)) continue;
          const double y = row.dj - fy;
          lower_row(field.values.data() + k * plane + j * nx + i0, static_cast<std::int32_t>(i1 - i0 + 1), static_cast<T>(z2 + y * y),
                    static_cast<T>(static_cast<double>(i0 - ci) - fx));
        }
      }
    }
  });
}

template <typename T>
Grid3<T> excluded_field(const std::vector<Atom>& atoms, const SurfaceOptions& options) {
  if (atoms.empty()) throw InputError("no atoms to build a surface from");
  const double h = options.grid, probe = options.probe;
  double largest_radius = 0;
  Vec3 lo = atoms.front().position, hi = lo;
  for (const auto& a : atoms) {
    if (!(a.radius > 0)) throw InputError(fmt::format("atom {} ({}) has radius {}; radii must be positive", a.serial, a.name, a.radius));
    largest_radius = std::max(largest_radius, a.radius);
    for (int d = 0; d < 3; ++d) lo[d] = std::min(lo[d], a.position[d]), hi[d] = std::max(hi[d], a.position[d]);
  }
  const double margin = largest_radius + probe + 3 * h;
  Grid3<T> field;
  field.spacing = h;
  for (int d = 0; d < 3; ++d) {
    field.origin[d] = lo[d] - margin;
    field.size[d] = ceil_int((hi[d] - lo[d] + 2 * margin) / h) + 1;
  }
  // The field is the only per-sample array (built in place); the surface probe centres (24 bytes each,
  // about 100 per atom at 0.25 Å) and the atom lists are small beside it.
  const double samples = static_cast<double>(field.size[0]) * static_cast<double>(field.size[1]) * static_cast<double>(field.size[2]);
  const double per_sample = static_cast<double>(sizeof(T)) + options.extra_bytes_per_sample;
  const double bytes = samples * per_sample;
  if (bytes > options.max_grid_bytes) {
    const double fitting = h * std::cbrt(bytes / options.max_grid_bytes) * 1.01;
    throw InputError(fmt::format("a {} x {} x {} grid at {} Å would need {:.1f} GB ({:g} bytes per sample; budget {:.1f} GB); use --grid {:.2f} or coarser",
                                 field.size[0], field.size[1], field.size[2], h, bytes / 1e9, per_sample, options.max_grid_bytes / 1e9,
                                 std::ceil(fitting * 100) / 100));
  }
  const int threads = detail::surface_threads(options.threads);
  detail::StageTimer clock("surface");
  detail::reserve_mapped(field.values, static_cast<std::size_t>(field.count()), threads);
  field.values.assign(static_cast<std::size_t>(field.count()), static_cast<T>(kUnreached));
  // Samples outside the SAS (outside every sphere of radius r + probe) are probe centres; only those a
  // probe reaches from outside count (as for MSMS's outer surface), unless cavities are carved too.
  mark_accessible_surface(field, atoms, probe, threads);
  clock.lap("accessible");
  const Pockets pockets = flood_and_label_pockets(field, threads);
  clock.lap("flood");
  // Which pockets a probe reaches through passages narrower than a step, and more probe centres, on the
  // SAS surface itself (found before the transform, while carving samples are exactly the zeros).
  const std::vector<Vec3> centres = surface_probe_centres(field, atoms, probe, pockets, options.carve_cavities, threads, clock);
  clock.lap("sort");
  squared_distance_transform_in_place(field, threads);
  clock.lap("transform");
  // Each surface centre lowers the samples within probe + sqrt(3) steps of it. That makes g exact (for
  // this set of centres) wherever |g| < sqrt(3) steps, which covers both ends of every lattice edge the
  // surface crosses (g changes by at most the edge length along it), so the contour is the same as with
  // an unbounded reach; deeper inside, the grid samples alone give g.
  // Samples within probe/h - sqrt(3) steps of a lattice centre need no lowering: they stay outside and
  // no edge the surface crosses reaches them (a neighbour along a lattice edge, at most sqrt(3) steps
  // away, is within probe/h of that centre, hence not inside). 0.01 of a step keeps rounding away from
  // that bound; zeros cannot be lowered anyway.
  const double free_reach = probe / h - std::sqrt(3.0) - 0.01;
  lower_near_centres(field, centres, probe / h + std::sqrt(3.0) * (1 + 1e-9), free_reach > 0 ? free_reach * free_reach : 0.0, threads,
                     options.use_avx2);
  clock.lap("lower");
  const std::int64_t plane = field.size[0] * field.size[1];
  // About half the samples are probe centres (0): runs of them take their value, -probe, without the
  // square root that bounds this loop (sqrt(0) h - probe is exactly -probe).
  constexpr std::int64_t kRun = 16;
  const auto at_centre = static_cast<T>(-probe);
  detail::parallel_chunks(field.size[2], threads, [&](std::int64_t k, int) {
    T* values = field.values.data() + k * plane;
    for (std::int64_t first = 0; first < plane; first += kRun) {
      T* run = values + first;
      const std::int64_t length = std::min(kRun, plane - first);
      bool zeros = true;
      for (std::int64_t s = 0; s < length; ++s) zeros &= run[s] == T(0);
      if (zeros) {
        std::fill_n(run, length, at_centre);
        continue;
      }
      for (std::int64_t s = 0; s < length; ++s) run[s] = static_cast<T>(std::sqrt(static_cast<double>(run[s])) * h - probe);
    }
  });
  clock.lap("root");
  return field;
}

template <typename T>
Mesh contour_with_atoms(const Grid3<T>& field, const std::vector<Atom>& atoms, const SurfaceOptions& options) {
  Mesh mesh = contour_isosurface(field, 0.0, options.threads, options.contour_minimum_fraction);
  add_nearest_atoms(mesh, atoms, options);
  return mesh;
}

}  // namespace

Grid3<double> solvent_excluded_field(const std::vector<Atom>& atoms, const SurfaceOptions& options) {
  return excluded_field<double>(atoms, options);
}

Grid3<float> solvent_excluded_field_float(const std::vector<Atom>& atoms, const SurfaceOptions& options) {
  return excluded_field<float>(atoms, options);
}

Mesh solvent_excluded_surface(const std::vector<Atom>& atoms, const SurfaceOptions& options) {
  Mesh mesh;
  {
    const Grid3<float> field = solvent_excluded_field_float(atoms, options);
    detail::StageTimer clock("surface");
    mesh = contour_isosurface(field, 0.0, options.threads, options.contour_minimum_fraction);
    clock.lap("contour");
  }
  detail::StageTimer clock("surface");
  add_nearest_atoms(mesh, atoms, options);
  clock.lap("provenance");
  return mesh;
}

Mesh surface_from_field(const Grid3<double>& field, const std::vector<Atom>& atoms, const SurfaceOptions& options) {
  return contour_with_atoms(field, atoms, options);
}

Mesh surface_from_field(const Grid3<float>& field, const std::vector<Atom>& atoms, const SurfaceOptions& options) {
  return contour_with_atoms(field, atoms, options);
}

}  // namespace spheremap
