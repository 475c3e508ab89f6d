#include "probe_centres.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <utility>

#include "../util/parallel.hpp"
#include "../util/rounding.hpp"
#include "../util/union_find.hpp"
#include "atom_grid.hpp"
#include "circle_cover.hpp"
#include "spheremap/geometry/vec.hpp"

namespace spheremap::detail {
namespace {

constexpr double kTurn = 2 * std::numbers::pi;
// Atoms are handled in chunks of this many (in index order), one chunk per task.
constexpr std::int32_t kAtomsPerChunk = 64;

// The atoms with their enlarged spheres (radius + probe), and which enlarged spheres overlap each one:
// only those can cover a point of its sphere.
struct SasAtoms {
  const std::vector<Atom>& atoms;
  std::vector<double> reach, reach2;
  double largest_reach = 0;
  AtomGrid grid;
  // The overlapping spheres of atom i, ascending: neighbours[neighbour_start[i] .. neighbour_start[i + 1]).
  std::vector<std::int64_t> neighbour_start;
  std::vector<std::int32_t> neighbours;

  SasAtoms(const std::vector<Atom>& atoms_in, double probe)
      : atoms(atoms_in),
        reach(atoms_in.size()),
        reach2(atoms_in.size()),
        largest_reach(largest(atoms_in, probe)),
        grid(atoms_in, largest_reach) {
    for (std::size_t a = 0; a < atoms.size(); ++a) {
      reach[a] = atoms[a].radius + probe;
      reach2[a] = reach[a] * reach[a];
    }
  }
  [[nodiscard]] std::int32_t count() const { return static_cast<std::int32_t>(atoms.size()); }
  [[nodiscard]] std::int64_t chunks() const { return (count() + kAtomsPerChunk - 1) / kAtomsPerChunk; }
  [[nodiscard]] std::int32_t chunk_first(std::int64_t chunk) const {
    return static_cast<std::int32_t>(chunk) * kAtomsPerChunk;
  }
  [[nodiscard]] std::int32_t chunk_end(std::int64_t chunk) const {
    return std::min(count(), static_cast<std::int32_t>(chunk + 1) * kAtomsPerChunk);
  }

 private:
  static double largest(const std::vector<Atom>& atoms, double probe) {
    double largest_reach = 0;
    for (const auto& a : atoms) largest_reach = std::max(largest_reach, a.radius + probe);
    return largest_reach;
  }
};

// Fills sas.neighbour_start and sas.neighbours.
void find_overlapping_spheres(SasAtoms& sas, int threads) {
  const auto& atoms = sas.atoms;
  std::vector<std::vector<std::int32_t>> chunk_neighbours(static_cast<std::size_t>(sas.chunks()));
  sas.neighbour_start.assign(atoms.size() + 1, 0);
  parallel_chunks(sas.chunks(), threads, [&](std::int64_t chunk, int) {
    auto& out = chunk_neighbours[static_cast<std::size_t>(chunk)];
    std::vector<std::int32_t> found;
    for (std::int32_t i = sas.chunk_first(chunk); i < sas.chunk_end(chunk); ++i) {
      found.clear();
      sas.grid.near(atoms[i].position, sas.reach[i] + sas.largest_reach, [&](std::int32_t j) {
        if (j != i && norm(atoms[j].position - atoms[i].position) < sas.reach[i] + sas.reach[j]) found.push_back(j);
      });
      std::sort(found.begin(), found.end());
      out.insert(out.end(), found.begin(), found.end());
      sas.neighbour_start[static_cast<std::size_t>(i) + 1] = static_cast<std::int64_t>(found.size());
    }
  });
  for (std::size_t a = 0; a < atoms.size(); ++a) sas.neighbour_start[a + 1] += sas.neighbour_start[a];
  sas.neighbours.reserve(static_cast<std::size_t>(sas.neighbour_start.back()));
  for (auto& part : chunk_neighbours)
    sas.neighbours.insert(sas.neighbours.end(), part.begin(), part.end()), std::vector<std::int32_t>().swap(part);
}

// Whether the segment from p to q (Å) stays outside every enlarged sphere (it may touch them: p and q
// may lie on the SAS).
bool segment_free(const SasAtoms& sas, const Vec3& p, const Vec3& q) {
  const Vec3 d = q - p;
  const double length2 = dot(d, d);
  bool free = true;
  sas.grid.near(0.5 * (p + q), 0.5 * std::sqrt(length2) + sas.largest_reach, [&](std::int32_t k) {
    if (!free) return;
    const Vec3 w = p - sas.atoms[k].position;
    const double t = length2 > 0 ? std::clamp(-dot(w, d) / length2, 0.0, 1.0) : 0.0;
    const Vec3 nearest = w + t * d;
    free = dot(nearest, nearest) >= sas.reach2[k] * (1 - 1e-9);
  });
  return free;
}

// A point in grid units (sample (i, j, k) at (i, j, k)).
template <typename T>
Vec3 to_grid(const Grid3<T>& field, const Vec3& p) {
  const double h = field.spacing;
  return {(p[0] - field.origin[0]) / h, (p[1] - field.origin[1]) / h, (p[2] - field.origin[2]) / h};
}

// Calls visit(i, j, k) for the samples among the 27 around the nearest sample of `unit` (grid units)
// until it returns true; returns whether it did.
template <typename T, typename Visit>
bool visit_27_around(const Grid3<T>& field, const Vec3& unit, Visit&& visit) {
  const auto [nx, ny, nz] = field.size;
  const auto ci = static_cast<std::int64_t>(std::llround(unit[0]));
  const auto cj = static_cast<std::int64_t>(std::llround(unit[1]));
  const auto ck = static_cast<std::int64_t>(std::llround(unit[2]));
  for (std::int64_t c = std::max<std::int64_t>(0, ck - 1); c <= std::min(nz - 1, ck + 1); ++c)
    for (std::int64_t b = std::max<std::int64_t>(0, cj - 1); b <= std::min(ny - 1, cj + 1); ++b)
      for (std::int64_t a = std::max<std::int64_t>(0, ci - 1); a <= std::min(nx - 1, ci + 1); ++a)
        if (visit(a, b, c)) return true;
  return false;
}

template <typename T>
T value_at(const Grid3<T>& field, std::int64_t i, std::int64_t j, std::int64_t k) {
  return field.values[static_cast<std::size_t>(field.index(i, j, k))];
}

// A vertex of the SAS (a probe position touching three atoms): the atoms, ascending, and the side of the
// plane of their centres it lies on (the two such positions are mirror images through that plane).
struct VertexKey {
  std::array<std::int32_t, 3> atoms;
  std::int32_t side;
  auto operator<=>(const VertexKey&) const = default;
};

VertexKey vertex_key(const std::vector<Atom>& atoms, std::int32_t a, std::int32_t b, std::int32_t c,
                     const Vec3& point) {
  VertexKey key{a, b, c, 0};
  std::sort(key.atoms.begin(), key.atoms.end());
  const Vec3& o = atoms[key.atoms[0]].position;
  key.side = dot(cross(atoms[key.atoms[1]].position - o, atoms[key.atoms[2]].position - o), point - o) > 0;
  return key;
}

// The exposed arcs of one chunk of atoms (circles (i, j) with i < j, by i then j; arcs by angle).
struct ChunkArcs {
  std::int64_t arcs = 0;
  std::vector<Vec3> samples, vertices;                   // grid units; the vertices (touching three atoms) once each
  std::vector<std::int32_t> sample_arc, vertex_arc;      // local arc index
  std::vector<std::pair<VertexKey, std::int32_t>> ends;  // local arc
  std::vector<std::pair<std::int32_t, std::int64_t>> links;  // local arc, label (0 outside, p pocket)
  std::vector<std::int32_t> circled, exposed;                // atoms with a circle; atoms with an exposed arc
};

// The circle where the enlarged spheres of two atoms meet: centre + radius (cos θ u + sin θ v).
struct Circle {
  Vec3 centre, unit_axis, u, v;
  double radius;
  [[nodiscard]] Vec3 point_at(double angle) const {
    return centre + radius * (std::cos(angle) * u + std::sin(angle) * v);
  }
};

// The exposed arcs of every circle of one chunk's atoms, with the scratch space of one worker.
template <typename T>
class ArcFinder {
 public:
  ArcFinder(const Grid3<T>& field, const SasAtoms& sas, std::vector<std::int32_t>& is_neighbour)
      : field_(field), sas_(sas), is_neighbour_(is_neighbour) {
    if (is_neighbour_.empty()) is_neighbour_.assign(sas.atoms.size(), -1);
  }

  // The circles of atom `index` with the atoms j > index whose spheres it meets.
  void atom(std::int32_t index, ChunkArcs& out) {
    const auto& atoms = sas_.atoms;
    const auto& neighbour_start = sas_.neighbour_start;
    const double reach_i = sas_.reach[index];
    // is_neighbour[k] == index: k is a neighbour of the atom `index` (the common neighbours of index and
    // j are then j's neighbours so marked: one pass over j's list, in its ascending order). One array per
    // worker: marks left by other atoms never equal `index`.
    for (auto m = neighbour_start[index]; m < neighbour_start[index + 1]; ++m)
      is_neighbour_[static_cast<std::size_t>(sas_.neighbours[static_cast<std::size_t>(m)])] = index;
    burier_ = -1;
    for (auto m = neighbour_start[index]; m < neighbour_start[index + 1]; ++m) {
      const std::int32_t j = sas_.neighbours[static_cast<std::size_t>(m)];
      if (j <= index) continue;
      const double reach_j = sas_.reach[j];
      const Vec3 axis = atoms[j].position - atoms[index].position;
      const double d = norm(axis);
      if (d >= reach_i + reach_j || d <= std::abs(reach_i - reach_j) || d == 0) continue;
      out.circled.push_back(index), out.circled.push_back(j);
      const double along = (d * d + reach_i * reach_i - reach_j * reach_j) / (2 * d);
      Circle circle;
      circle.radius = std::sqrt(std::max(0.0, reach_i * reach_i - along * along));
      circle.unit_axis = (1 / d) * axis;
      circle.centre = atoms[index].position + along * circle.unit_axis;
      const Vec3 helper = std::abs(circle.unit_axis[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
      circle.u = normalized(cross(circle.unit_axis, helper));
      circle.v = cross(circle.unit_axis, circle.u);
      if (!find_gaps(circle, index, j)) continue;
      if (!gaps_.empty()) out.exposed.push_back(index), out.exposed.push_back(j);
      sample_gaps(circle, index, j, out);
    }
  }

 private:
  struct Covering {
    double start, length;
    std::int32_t atom;
  };
  struct Gap {
    double from, to;
    std::int32_t from_atom, to_atom;  // the atoms whose spheres end there (-1: the whole circle is exposed)
  };

  // Whether a sphere holds all of the circle (its farthest point from that sphere's centre is inside).
  [[nodiscard]] bool holds_circle(const Circle& circle, std::int32_t other) const {
    const Vec3 offset = sas_.atoms[other].position - circle.centre;
    const double a = dot(offset, circle.unit_axis), b2 = std::max(0.0, dot(offset, offset) - a * a);
    const double far = circle.radius + std::sqrt(b2);
    return a * a + far * far < sas_.reach2[other] * (1 - 1e-12);
  }

  // The neighbours common to index and j (in ascending order): only a sphere overlapping both can cover a
  // point of their circle. About half of index's.
  void common_neighbours(std::int32_t index, std::int32_t j) {
    const auto& neighbour_start = sas_.neighbour_start;
    common_.resize(static_cast<std::size_t>(neighbour_start[j + 1] - neighbour_start[j]));
    std::size_t shared = 0;
    for (auto y = neighbour_start[j]; y < neighbour_start[j + 1]; ++y) {
      const std::int32_t q = sas_.neighbours[static_cast<std::size_t>(y)];
      common_[shared] = q;
      shared += is_neighbour_[static_cast<std::size_t>(q)] == index;
    }
    common_.resize(shared);
  }

  // The exposed arcs of the circle of index and j into gaps_; false when nothing of it is exposed.
  // The angles covered by each other enlarged sphere k: |p(θ) - c_k|² < R_k² with
  // p(θ) = centre + ρ (cos θ u + sin θ v), i.e. 2ρ m cos(θ - φ) < room, where (a, b) = m (cos φ, sin φ)
  // are the coordinates of centre - c_k in the circle's plane; a whole circle inside k is skipped.
  bool find_gaps(const Circle& circle, std::int32_t index, std::int32_t j) {
    // Most circles of a protein are buried: skip the circle when one enlarged sphere holds all of it; only
    // then are the intervals computed. The sphere that held index's previous circle often holds this one
    // too (neighbouring circles of one atom): tried before the lists are merged. A sphere holding the
    // circle overlaps both spheres, so it is among the common neighbours: the decision is the one the
    // loop below would make.
    if (burier_ >= 0 && burier_ != j && holds_circle(circle, burier_)) return false;
    common_neighbours(index, j);
    for (std::size_t n = 0; n < common_.size(); ++n)
      if (holds_circle(circle, common_[n])) {
        burier_ = common_[n];
        return false;
      }
    terms_.clear();
    for (const std::int32_t k : common_) {
      const Vec3 offset = circle.centre - sas_.atoms[k].position;
      const double a = dot(offset, circle.u), b = dot(offset, circle.v), along_axis = dot(offset, circle.unit_axis);
      const double room = sas_.reach2[k] - (a * a + b * b + along_axis * along_axis) - circle.radius * circle.radius;
      const double m = std::sqrt(a * a + b * b), spread = 2 * circle.radius * m;
      if (room >= spread) return false;  // all of it (up to rounding: the test above missed it)
      if (room > -spread) terms_.push_back({a, b, room, spread, k});
    }
    // Most of the rest are covered by several spheres together: decided without trigonometry when the
    // union covers the circle with room to spare (certainly_covered); the angles are computed only for
    // the others.
    if (certainly_covered(terms_, spans_)) return false;
    coverings_.clear();
    for (const CoverTerm& t : terms_) {
      const double half = std::acos(t.room / t.spread);  // exposed: |θ - φ| <= half
      double start = std::atan2(t.b, t.a) + half;
      start -= kTurn * std::floor(start / kTurn);
      coverings_.push_back({start, 2 * (std::numbers::pi - half), t.atom});
    }
    if (coverings_.size() == 1 && coverings_.front().length >= kTurn) return false;
    merge_coverings();
    return true;
  }

  // Exposed arcs: the gaps between the merged covered intervals, [from, to] with the atoms whose spheres
  // end there.
  void merge_coverings() {
    gaps_.clear();
    if (coverings_.empty()) {
      gaps_.push_back({0, kTurn, -1, -1});
      return;
    }
    std::sort(coverings_.begin(), coverings_.end(), [](const Covering& x, const Covering& y) {
      return x.start < y.start || (x.start == y.start && x.atom < y.atom);
    });
    const double first = coverings_.front().start;
    double reached = first + coverings_.front().length;
    std::int32_t owner = coverings_.front().atom;
    for (const auto& c : coverings_)  // intervals wrapping past a full turn cover the start again
      if (c.start + c.length - kTurn > reached) reached = c.start + c.length - kTurn, owner = c.atom;
    for (std::size_t c = 1; c < coverings_.size(); ++c) {
      const Covering& next = coverings_[c];
      if (next.start > reached) {
        gaps_.push_back({reached, next.start, owner, next.atom});
        reached = next.start + next.length, owner = next.atom;
      } else if (next.start + next.length > reached) {
        reached = next.start + next.length, owner = next.atom;
      }
    }
    if (reached < first + kTurn) gaps_.push_back({reached, first + kTurn, owner, coverings_.front().atom});
  }

  // Records each gap as an arc: its ends (vertices of the SAS), its samples every half step, and the
  // outside samples or pockets its samples see along free segments.
  void sample_gaps(const Circle& circle, std::int32_t index, std::int32_t j, ChunkArcs& out) {
    const auto steps = std::max<std::int64_t>(8, ceil_to_int(kTurn * circle.radius / (0.5 * field_.spacing)));
    const double step_angle = kTurn / static_cast<double>(steps);
    for (const Gap& gap : gaps_) {
      const auto arc = static_cast<std::int32_t>(out.arcs++);
      linked_.clear();
      if (gap.from_atom >= 0) {
        for (const auto& [angle, third] : {std::pair{gap.from, gap.from_atom}, std::pair{gap.to, gap.to_atom}}) {
          const Vec3 corner = circle.point_at(angle);
          out.ends.push_back({vertex_key(sas_.atoms, index, j, third, corner), arc});
          if (third > j) out.vertices.push_back(to_grid(field_, corner)), out.vertex_arc.push_back(arc);
        }
      }
      // Samples every half step strictly inside the arc (angles 2π s / steps, as on a whole circle).
      const std::int64_t s0 = gap.from_atom < 0 ? 0 : floor_to_int(gap.from / step_angle) + 1;
      for (std::int64_t s = s0; static_cast<double>(s) * step_angle < gap.to; ++s) {
        const double angle = kTurn * static_cast<double>(((s % steps) + steps) % steps) / static_cast<double>(steps);
        const Vec3 point = circle.point_at(angle);
        const Vec3 unit = to_grid(field_, point);
        out.samples.push_back(unit);
        out.sample_arc.push_back(arc);
        visit_27_around(field_, unit, [&](std::int64_t a, std::int64_t b, std::int64_t c) {
          const std::int64_t label = label_of(value_at(field_, a, b, c));
          if (label < 0 || std::find(linked_.begin(), linked_.end(), label) != linked_.end()) return false;
          if (!segment_free(sas_, point, field_.point(a, b, c))) return false;
          linked_.push_back(label);
          out.links.push_back({arc, label});
          return false;
        });
      }
    }
  }

  const Grid3<T>& field_;
  const SasAtoms& sas_;
  std::vector<std::int32_t>& is_neighbour_;
  std::int32_t burier_ = -1;  // the sphere that held the atom's previous circle
  std::vector<std::int32_t> common_;
  std::vector<CoverTerm> terms_;
  CoverScratch spans_;
  std::vector<Covering> coverings_;
  std::vector<Gap> gaps_;
  std::vector<std::int64_t> linked_;
};

template <typename T>
std::vector<ChunkArcs> exposed_arcs(const Grid3<T>& field, const SasAtoms& sas, int threads) {
  std::vector<ChunkArcs> chunk_arcs(static_cast<std::size_t>(sas.chunks()));
  std::vector<std::vector<std::int32_t>> neighbour_marks(static_cast<std::size_t>(std::max(threads, 1)));
  parallel_chunks(sas.chunks(), threads, [&](std::int64_t chunk, int worker) {
    ArcFinder<T> finder(field, sas, neighbour_marks[static_cast<std::size_t>(worker)]);
    for (std::int32_t index = sas.chunk_first(chunk); index < sas.chunk_end(chunk); ++index)
      finder.atom(index, chunk_arcs[static_cast<std::size_t>(chunk)]);
  });
  return chunk_arcs;
}

// Whether the radial projections onto an atom's sphere need testing: not when the sphere meets another
// in a circle and none of its circles has an exposed arc. Then nothing of it is exposed (an exposed part
// short of the whole sphere is bounded by exposed arcs), and that is true of about a third of a
// protein's atoms. Bit 1: some circle; bit 2: some exposed arc. Frees the chunks' atom lists.
std::vector<std::uint8_t> atom_faces(std::vector<ChunkArcs>& chunk_arcs, std::size_t atoms) {
  std::vector<std::uint8_t> face(atoms, 0);
  for (auto& part : chunk_arcs) {
    for (const std::int32_t a : part.circled) face[static_cast<std::size_t>(a)] |= 1;
    for (const std::int32_t a : part.exposed) face[static_cast<std::size_t>(a)] |= 2;
    std::vector<std::int32_t>().swap(part.circled), std::vector<std::int32_t>().swap(part.exposed);
  }
  return face;
}

// Which of outside, pockets and arcs carve: nodes 0 (outside), 1..pockets, then the arcs in order
// (the arcs of chunk c from first_arc + arc_start[c]).
struct Carving {
  std::int64_t first_arc = 0;
  std::vector<std::int64_t> arc_start;
  std::vector<std::uint8_t> carves;
};

// Joins arcs to what their samples see and to each other at shared vertices; the components holding
// the outside carve (with carve_cavities, every component holding an outside sample). Pockets a probe
// reaches become probe centres (0); the others +infinity.
template <typename T>
Carving resolve_pockets(Grid3<T>& field, const Pockets& pockets, const std::vector<ChunkArcs>& chunk_arcs,
                        bool carve_cavities) {
  const auto chunks = static_cast<std::int64_t>(chunk_arcs.size());
  Carving carving;
  carving.arc_start.assign(static_cast<std::size_t>(chunks) + 1, 0);
  for (std::int64_t c = 0; c < chunks; ++c)
    carving.arc_start[static_cast<std::size_t>(c) + 1] =
        carving.arc_start[static_cast<std::size_t>(c)] + chunk_arcs[static_cast<std::size_t>(c)].arcs;
  const std::int64_t first_arc = carving.first_arc = 1 + pockets.count;
  UnionFind<std::int64_t> components(static_cast<std::size_t>(first_arc + carving.arc_start.back()));
  std::vector<std::pair<VertexKey, std::int64_t>> ends;
  for (std::int64_t c = 0; c < chunks; ++c) {
    const auto& part = chunk_arcs[static_cast<std::size_t>(c)];
    const std::int64_t offset = first_arc + carving.arc_start[static_cast<std::size_t>(c)];
    for (const auto& [arc, label] : part.links) components.join(offset + arc, label);
    for (const auto& [key, arc] : part.ends) ends.push_back({key, offset + arc});
  }
  std::sort(ends.begin(), ends.end());
  for (std::size_t e = 1; e < ends.size(); ++e)
    if (ends[e].first == ends[e - 1].first) components.join(ends[e].second, ends[e - 1].second);
  auto& carves = carving.carves;
  carves.assign(static_cast<std::size_t>(first_arc + carving.arc_start.back()), 0);
  std::vector<std::uint8_t> root_carves(carves.size(), 0);
  if (carve_cavities)
    for (std::int64_t label = 0; label < first_arc; ++label)
      root_carves[static_cast<std::size_t>(components.find(label))] = 1;
  for (std::size_t node = 0; node < carves.size(); ++node) {
    const std::int64_t root = components.find(static_cast<std::int64_t>(node));
    carves[node] = root == 0 || root_carves[static_cast<std::size_t>(root)];
  }
  for (const PocketRun& run : pockets.runs)
    std::fill_n(field.values.begin() + run.first, run.length,
                carves[static_cast<std::size_t>(run.label)] ? T(0) : std::numeric_limits<T>::infinity());
  return carving;
}

// In crevices narrower than a grid step no sample is outside the SAS, yet a probe fits: every sample just
// inside atom `index`'s enlarged sphere (within one step) projects radially onto it, and the projection is
// a probe centre when no other enlarged sphere covers it and a carving sample (0) is among the 27 around
// its nearest sample. Appends those to `out` (grid units).
template <typename T>
class RadialProjections {
 public:
  RadialProjections(const Grid3<T>& field, const SasAtoms& sas) : field_(field), sas_(sas) {}

  void atom(std::int32_t index, std::vector<Vec3>& out) {
    const auto& atom = sas_.atoms[index];
    const double h = field_.spacing;
    // Whether p (on this atom's enlarged sphere) is strictly inside another one (only the overlapping
    // spheres can hold it). Which sphere holds p does not matter, so the list is kept in the order of
    // last use: neighbouring samples are mostly held by the sphere that held the one before.
    coverers_.clear();
    for (auto m = sas_.neighbour_start[index]; m < sas_.neighbour_start[index + 1]; ++m) {
      const std::int32_t other = sas_.neighbours[static_cast<std::size_t>(m)];
      coverers_.push_back({sas_.atoms[other].position, sas_.reach2[other]});
    }
    const double outer = sas_.reach[index], inner = outer - h;
    const auto first = [&](int d) {
      return std::max<std::int64_t>(0, ceil_to_int((atom.position[d] - outer - field_.origin[d]) / h));
    };
    const auto last = [&](int d) {
      return std::min<std::int64_t>(field_.size[d] - 1,
                                    floor_to_int((atom.position[d] + outer - field_.origin[d]) / h));
    };
    for (std::int64_t k = first(2); k <= last(2); ++k)
      for (std::int64_t j = first(1); j <= last(1); ++j) {
        const Vec3 row = field_.point(0, j, k);
        const double dy = row[1] - atom.position[1], dz = row[2] - atom.position[2], across = dy * dy + dz * dz;
        const double rest = outer * outer - across;
        if (rest < -1e-9 * outer * outer) continue;
        const double half = std::sqrt(std::max(0.0, rest));
        const std::int64_t i0 = std::max(first(0), ceil_to_int((atom.position[0] - half - field_.origin[0]) / h) - 1);
        const std::int64_t i1 = std::min(last(0), floor_to_int((atom.position[0] + half - field_.origin[0]) / h) + 1);
        // Samples deeper than `inner` (with a one-sample margin) are skipped without a test.
        std::int64_t skip0 = i1 + 1, skip1 = i1;
        if (inner > 0 && inner * inner - across > 0) {
          const double core = std::sqrt(inner * inner - across);
          skip0 = ceil_to_int((atom.position[0] - core - field_.origin[0]) / h) + 1;
          skip1 = floor_to_int((atom.position[0] + core - field_.origin[0]) / h) - 1;
        }
        for (std::int64_t i = i0; i <= i1; ++i) {
          if (i >= skip0 && i <= skip1) {
            i = skip1;
            continue;
          }
          const Vec3 x = field_.point(i, j, k);
          const double distance = norm(x - atom.position);
          if (distance >= outer || distance < inner || distance == 0) continue;
          const Vec3 centre = atom.position + (outer / distance) * (x - atom.position);
          if (covered(centre)) continue;
          const Vec3 unit = to_grid(field_, centre);
          if (visit_27_around(field_, unit, [&](std::int64_t a, std::int64_t b, std::int64_t c) {
                return value_at(field_, a, b, c) == T(0);
              }))
            out.push_back(unit);
        }
      }
  }

 private:
  struct Coverer {
    Vec3 centre;
    double reach2;
  };
  bool covered(const Vec3& p) {
    for (auto c = coverers_.begin(); c != coverers_.end(); ++c)
      if (squared_distance(p, c->centre) < c->reach2) {
        std::rotate(coverers_.begin(), c, c + 1);
        return true;
      }
    return false;
  }

  const Grid3<T>& field_;
  const SasAtoms& sas_;
  std::vector<Coverer> coverers_;
};

// The probe centres on the SAS, chunk by chunk: radial projections of the atoms with an exposed face,
// then the samples and vertices of the arcs that carve. Probe centres touching two atoms lie on the
// circles where their enlarged spheres meet: these shape the re-entrant (concave) parts of the surface.
template <typename T>
std::vector<std::vector<Vec3>> collect_centres(const Grid3<T>& field, const SasAtoms& sas,
                                               const std::vector<std::uint8_t>& face,
                                               const std::vector<ChunkArcs>& chunk_arcs, const Carving& carving,
                                               int threads) {
  std::vector<std::vector<Vec3>> chunk_centres(static_cast<std::size_t>(sas.chunks()));
  parallel_chunks(sas.chunks(), threads, [&](std::int64_t chunk, int) {
    auto& out = chunk_centres[static_cast<std::size_t>(chunk)];
    RadialProjections<T> projections(field, sas);
    for (std::int32_t index = sas.chunk_first(chunk); index < sas.chunk_end(chunk); ++index)
      if (face[static_cast<std::size_t>(index)] != 1) projections.atom(index, out);  // 1: buried
    const auto& arcs = chunk_arcs[static_cast<std::size_t>(chunk)];
    const std::int64_t offset = carving.first_arc + carving.arc_start[static_cast<std::size_t>(chunk)];
    for (std::size_t s = 0; s < arcs.samples.size(); ++s)
      if (carving.carves[static_cast<std::size_t>(offset + arcs.sample_arc[s])]) out.push_back(arcs.samples[s]);
    for (std::size_t s = 0; s < arcs.vertices.size(); ++s)
      if (carving.carves[static_cast<std::size_t>(offset + arcs.vertex_arc[s])]) out.push_back(arcs.vertices[s]);
  });
  return chunk_centres;
}

// The block of 8³ samples of a centre (grid units) along a Morton curve: the low 10 bits of each block
// coordinate, interleaved.
std::uint64_t block_key(const Vec3& c) {
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
}

// The centres of every chunk in blocks of 8³ samples, block by block along a Morton curve, so that
// consecutive centres touch the same part of the grid (the order does not change the field: lowering is
// a min). Each centre as (block key << 32 | its index), sorted as whole words: by key, ties in index
// order (the chunks' order), with a least-significant-digit radix sort over the key's bits only: linear
// and sequential. Blocks of 8 samples need at most 10 bits per axis (grids up to 8192 samples a side;
// the memory budget stops far sooner).
std::vector<Vec3> sort_by_block(const std::vector<std::vector<Vec3>>& chunk_centres, int threads) {
  std::vector<std::int64_t> part_start(chunk_centres.size() + 1, 0);
  for (std::size_t c = 0; c < chunk_centres.size(); ++c)
    part_start[c + 1] = part_start[c] + static_cast<std::int64_t>(chunk_centres[c].size());
  const auto total = static_cast<std::size_t>(part_start.back());
  std::vector<std::uint64_t> order(total), next(total);
  std::vector<std::uint64_t> part_largest(chunk_centres.size(), 0);
  parallel_chunks(static_cast<std::int64_t>(chunk_centres.size()), threads, [&](std::int64_t part, int) {
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
  parallel_chunks(threads, threads, [&](std::int64_t chunk, int) {
    const std::size_t from = total * static_cast<std::size_t>(chunk) / static_cast<std::size_t>(threads);
    const std::size_t to = total * static_cast<std::size_t>(chunk + 1) / static_cast<std::size_t>(threads);
    for (std::size_t c = from; c < to; ++c) {
      const auto index = static_cast<std::int64_t>(order[c] & 0xffffffffu);
      const auto part = static_cast<std::size_t>(std::upper_bound(part_start.begin(), part_start.end(), index) -
                                                 part_start.begin() - 1);
      sorted[c] = chunk_centres[part][static_cast<std::size_t>(index - part_start[part])];
    }
  });
  return sorted;
}

}  // namespace

template <typename T>
std::vector<Vec3> surface_probe_centres(Grid3<T>& field, const std::vector<Atom>& atoms, double probe,
                                        const Pockets& pockets, bool carve_cavities, int threads, StageTimer& clock) {
  SasAtoms sas(atoms, probe);
  find_overlapping_spheres(sas, threads);
  clock.lap("neighbours");
  std::vector<ChunkArcs> chunk_arcs = exposed_arcs(field, sas, threads);
  clock.lap("arcs");
  const std::vector<std::uint8_t> face = atom_faces(chunk_arcs, atoms.size());
  const Carving carving = resolve_pockets(field, pockets, chunk_arcs, carve_cavities);
  clock.lap("pockets");
  const auto chunk_centres = collect_centres(field, sas, face, chunk_arcs, carving, threads);
  chunk_arcs.clear();
  clock.lap("projections");
  return sort_by_block(chunk_centres, threads);
}

template std::vector<Vec3> surface_probe_centres<double>(Grid3<double>&, const std::vector<Atom>&, double,
                                                         const Pockets&, bool, int, StageTimer&);
template std::vector<Vec3> surface_probe_centres<float>(Grid3<float>&, const std::vector<Atom>&, double, const Pockets&,
                                                        bool, int, StageTimer&);

}  // namespace spheremap::detail
