#include "spheremap/surface/nearest_atoms.hpp"

#include <algorithm>
#include <atomic>
#include <cmath>
#include <limits>

#include "atom_grid.hpp"
#include "../util/parallel.hpp"
#include "spheremap/attributes.hpp"
#include "spheremap/error.hpp"

namespace spheremap {
namespace {

using detail::AtomGrid;
using detail::Sphere;

// Vertices are grouped by cubic cells of this side (Å); every vertex of a cell looks only at the cell's
// candidates. A 1.5 Å cell holds about 45 surface vertices at a 0.5 Å grid and 180 at 0.25 Å (1 Å cells
// spent more time on the cells than on the vertices at a 1 Å grid: 52 ms against 37 ms for 5hr7), and a few
// candidate atoms.
constexpr double kCell = 1.5;
// At most this many cells (the side grows for meshes spread over a large box).
constexpr double kMaximumCells = 1 << 24;
// Bounds are widened by this much (Å) so that rounding (and vertices a rounding error outside their
// cell) never drops the answer; it only lets in a few more candidates.
constexpr double kSlack = 1e-7;

// Distances from the box [lo, hi] to point c: nearest and farthest point of the box.
double nearest_in_box(const Vec3& lo, const Vec3& hi, const Vec3& c) {
  double sum = 0;
  for (int d = 0; d < 3; ++d) {
    const double e = c[d] < lo[d] ? lo[d] - c[d] : c[d] > hi[d] ? c[d] - hi[d] : 0.0;
    sum += e * e;
  }
  return std::sqrt(sum);
}
double farthest_in_box(const Vec3& lo, const Vec3& hi, const Vec3& c) {
  double sum = 0;
  for (int d = 0; d < 3; ++d) {
    const double e = std::max(std::abs(c[d] - lo[d]), std::abs(hi[d] - c[d]));
    sum += e * e;
  }
  return std::sqrt(sum);
}

// A candidate atom of a cell: its sphere and the smallest gap it can have in the cell (a lower bound).
struct Candidate {
  Sphere sphere;
  double least_gap;
};

// Appends to `out` every atom that can be nearest (smallest |x - centre| - radius) for some point x of
// the box [lo, hi]: the atoms whose sphere comes within `bound` of the box, where bound is the smallest,
// over atoms, of the farthest distance from the box to their sphere (so the nearest sphere of any point
// of the box is within it). The set does not depend on the order atoms are visited in.
void box_candidates(const AtomGrid& grid, const std::vector<Atom>& atoms, double largest_radius, const Vec3& lo, const Vec3& hi,
                    std::vector<Candidate>& out) {
  const Vec3 middle = 0.5 * (lo + hi);
  const std::int32_t first = grid.nearest_sphere(middle, largest_radius, grid.some_atom_near(middle), atoms);
  const Atom& closest = atoms[static_cast<std::size_t>(first)];
  double bound = farthest_in_box(lo, hi, closest.position) - closest.radius;
  double half = 0;
  for (int d = 0; d < 3; ++d) half = std::max(half, 0.5 * (hi[d] - lo[d]));
  const std::size_t begin = out.size();
  // Only centres within the box's half diagonal + bound + radius of its middle can qualify.
  const double half_diagonal = 0.5 * norm(hi - lo);
  grid.near_spheres(middle, half + bound + largest_radius + kSlack, [&](const Sphere& s) {
    const double reach = half_diagonal + bound + s.radius + kSlack;
    if (squared_distance(s.centre, middle) > reach * reach) return;
    if (nearest_in_box(lo, hi, s.centre) - s.radius > bound + kSlack) return;
    bound = std::min(bound, farthest_in_box(lo, hi, s.centre) - s.radius);
    out.push_back({s, nearest_in_box(lo, hi, s.centre) - s.radius});
  });
  // An atom visited later may have lowered the bound below what let earlier ones in.
  const auto first_kept = out.begin() + static_cast<std::ptrdiff_t>(begin);
  out.erase(std::remove_if(first_kept, out.end(), [&](const Candidate& c) { return c.least_gap > bound + kSlack; }), out.end());
  // Most likely first, so that a vertex can stop early (ties by index: the order is deterministic).
  std::sort(first_kept, out.end(), [](const Candidate& a, const Candidate& b) {
    return a.least_gap < b.least_gap || (a.least_gap == b.least_gap && a.sphere.index < b.sphere.index);
  });
}

// box_candidates for a box inside a larger one, from the larger one's candidates (a superset: the best
// bound of the small box is at most the large one's, and its atoms come at least as near the large box).
void sub_box_candidates(const std::vector<Candidate>& outer, const Vec3& lo, const Vec3& hi, std::vector<Candidate>& out) {
  double bound = std::numeric_limits<double>::infinity();
  for (const Candidate& c : outer) bound = std::min(bound, farthest_in_box(lo, hi, c.sphere.centre) - c.sphere.radius);
  const std::size_t begin = out.size();
  for (const Candidate& c : outer) {
    const double least = nearest_in_box(lo, hi, c.sphere.centre) - c.sphere.radius;
    if (least <= bound + kSlack) out.push_back({c.sphere, least});
  }
  std::sort(out.begin() + static_cast<std::ptrdiff_t>(begin), out.end(), [](const Candidate& a, const Candidate& b) {
    return a.least_gap < b.least_gap || (a.least_gap == b.least_gap && a.sphere.index < b.sphere.index);
  });
}

}  // namespace

void add_nearest_atoms(Mesh& mesh, const std::vector<Atom>& atoms, const SurfaceOptions& options) {
  const std::size_t n = mesh.vertex_count();
  std::vector<std::int32_t> atom_index(n), serial(n), residue(n), model(n);
  if (n > 0) {
    if (atoms.empty()) throw InputError("no atoms to take surface provenance from");
    const int threads = detail::surface_threads(options.threads);
    double largest_radius = 0;
    for (const auto& a : atoms) largest_radius = std::max(largest_radius, a.radius);
    const AtomGrid grid(atoms, 2.0);
    constexpr std::int64_t kChunk = 16384;
    const auto vertex_count = static_cast<std::int64_t>(n);
    // The box of the vertices, and its cells.
    Vec3 lo = mesh.positions.front(), hi = lo;
    for (const Vec3& p : mesh.positions)
      for (int d = 0; d < 3; ++d) lo[d] = std::min(lo[d], p[d]), hi[d] = std::max(hi[d], p[d]);
    double side = kCell;
    std::array<std::int64_t, 3> cells{};
    for (;;) {
      for (int d = 0; d < 3; ++d) cells[d] = static_cast<std::int64_t>(std::floor((hi[d] - lo[d]) / side)) + 1;
      if (static_cast<double>(cells[0]) * static_cast<double>(cells[1]) * static_cast<double>(cells[2]) <= kMaximumCells) break;
      side *= 2;
    }
    auto cell_of = [&](const Vec3& p) {
      std::int64_t c[3];
      for (int d = 0; d < 3; ++d) c[d] = std::clamp<std::int64_t>(detail::floor_to_int((p[d] - lo[d]) / side), 0, cells[d] - 1);
      return c[0] + cells[0] * (c[1] + cells[1] * c[2]);
    };
    // slot[cell]: -1 without vertices; then the cell's rank among the cells with vertices.
    std::vector<std::int32_t> slot(static_cast<std::size_t>(cells[0] * cells[1] * cells[2]), -1);
    detail::parallel_ranges(vertex_count, kChunk, threads, [&](std::int64_t first, std::int64_t end) {
      for (auto v = static_cast<std::size_t>(first); v < static_cast<std::size_t>(end); ++v)
        std::atomic_ref<std::int32_t>(slot[static_cast<std::size_t>(cell_of(mesh.positions[v]))]).store(0, std::memory_order_relaxed);
    });
    std::vector<std::int64_t> used;
    for (std::size_t c = 0; c < slot.size(); ++c)
      if (slot[c] == 0) slot[c] = static_cast<std::int32_t>(used.size()), used.push_back(static_cast<std::int64_t>(c));
    // Candidates of each used cell, from those of its parent (the cell of twice the side holding it), which
    // come from the atom grid: cells grouped by parent, groups in chunks, chunks concatenated in order.
    auto box_of = [&](std::int64_t c, double box_side, std::int64_t per_row, std::int64_t per_plane) {
      const std::int64_t index[3] = {c % per_row, (c / per_row) % per_plane, c / (per_row * per_plane)};
      std::pair<Vec3, Vec3> box;
      for (int d = 0; d < 3; ++d) {
        box.first[d] = lo[d] + box_side * static_cast<double>(index[d]);
        box.second[d] = box.first[d] + box_side;
      }
      return box;
    };
    const std::int64_t parent_row = (cells[0] + 1) / 2, parent_plane = (cells[1] + 1) / 2;
    std::vector<std::pair<std::int64_t, std::uint32_t>> by_parent(used.size());  // parent, child rank
    for (std::size_t u = 0; u < used.size(); ++u) {
      const std::int64_t c = used[u], x = c % cells[0], y = (c / cells[0]) % cells[1], z = c / (cells[0] * cells[1]);
      by_parent[u] = {x / 2 + parent_row * (y / 2 + parent_plane * (z / 2)), static_cast<std::uint32_t>(u)};
    }
    std::sort(by_parent.begin(), by_parent.end());
    std::vector<std::size_t> group_start;  // groups of children with the same parent
    for (std::size_t g = 0; g < by_parent.size(); ++g)
      if (g == 0 || by_parent[g].first != by_parent[g - 1].first) group_start.push_back(g);
    group_start.push_back(by_parent.size());
    constexpr std::int64_t kGroupsPerChunk = 64;
    const auto groups = static_cast<std::int64_t>(group_start.size()) - 1;
    const std::int64_t group_chunks = (groups + kGroupsPerChunk - 1) / kGroupsPerChunk;
    std::vector<std::vector<Candidate>> chunk_candidates(static_cast<std::size_t>(group_chunks));
    std::vector<std::int64_t> candidate_begin(used.size()), candidate_end(used.size());  // within the chunk, then global
    std::vector<std::int64_t> chunk_of_child(used.size());
    detail::parallel_chunks(group_chunks, threads, [&](std::int64_t chunk, int) {
      auto& out = chunk_candidates[static_cast<std::size_t>(chunk)];
      std::vector<Candidate> parent;
      for (std::int64_t g = chunk * kGroupsPerChunk; g < std::min(groups, (chunk + 1) * kGroupsPerChunk); ++g) {
        const auto [parent_lo, parent_hi] = box_of(by_parent[group_start[static_cast<std::size_t>(g)]].first, 2 * side, parent_row, parent_plane);
        parent.clear();
        box_candidates(grid, atoms, largest_radius, parent_lo, parent_hi, parent);
        for (auto m = group_start[static_cast<std::size_t>(g)]; m < group_start[static_cast<std::size_t>(g) + 1]; ++m) {
          const std::uint32_t u = by_parent[m].second;
          const auto [box_lo, box_hi] = box_of(used[u], side, cells[0], cells[1]);
          candidate_begin[u] = static_cast<std::int64_t>(out.size());
          sub_box_candidates(parent, box_lo, box_hi, out);
          candidate_end[u] = static_cast<std::int64_t>(out.size());
          chunk_of_child[u] = chunk;
        }
      }
    });
    std::vector<std::int64_t> chunk_offset(static_cast<std::size_t>(group_chunks) + 1, 0);
    for (std::int64_t c = 0; c < group_chunks; ++c)
      chunk_offset[static_cast<std::size_t>(c) + 1] = chunk_offset[static_cast<std::size_t>(c)] + static_cast<std::int64_t>(chunk_candidates[static_cast<std::size_t>(c)].size());
    for (std::size_t u = 0; u < used.size(); ++u) {
      const std::int64_t offset = chunk_offset[static_cast<std::size_t>(chunk_of_child[u])];
      candidate_begin[u] += offset, candidate_end[u] += offset;
    }
    std::vector<Candidate> candidates;
    candidates.reserve(static_cast<std::size_t>(chunk_offset.back()));
    for (auto& part : chunk_candidates) candidates.insert(candidates.end(), part.begin(), part.end()), std::vector<Candidate>().swap(part);
    detail::parallel_ranges(vertex_count, kChunk, threads, [&](std::int64_t first, std::int64_t end) {
      for (auto v = static_cast<std::size_t>(first); v < static_cast<std::size_t>(end); ++v) {
        const Vec3& p = mesh.positions[v];
        const auto u = static_cast<std::size_t>(slot[static_cast<std::size_t>(cell_of(p))]);
        double best = std::numeric_limits<double>::infinity();
        std::int32_t chosen = -1;
        for (auto m = candidate_begin[u]; m < candidate_end[u]; ++m) {
          const Candidate& c = candidates[static_cast<std::size_t>(m)];
          // The rest cannot come nearer (nor tie: the slack keeps rounding on the safe side).
          if (c.least_gap > best + kSlack) break;
          const Sphere& s = c.sphere;
          const double gap = norm(p - s.centre) - s.radius;
          if (gap < best || (gap == best && s.index < chosen)) best = gap, chosen = s.index;
        }
        const Atom& atom = atoms[static_cast<std::size_t>(chosen)];
        atom_index[v] = chosen;
        serial[v] = atom.serial;
        residue[v] = atom.residue_number;
        model[v] = atom.model;
      }
    });
  }
  mesh.integer_attributes[attributes::kAtomId] = std::move(atom_index);
  mesh.integer_attributes[attributes::kAtomSerial] = std::move(serial);
  mesh.integer_attributes[attributes::kResidueNumber] = std::move(residue);
  mesh.integer_attributes[attributes::kModel] = std::move(model);
}

}  // namespace spheremap
