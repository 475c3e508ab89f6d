#include "spheremap/surface/nearest_atoms.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <limits>
#include <utility>

#include "../util/parallel.hpp"
#include "../util/rounding.hpp"
#include "atom_grid.hpp"
#include "spheremap/attributes.hpp"
#include "spheremap/error.hpp"

namespace spheremap {
namespace {

using detail::AtomGrid;
using detail::Sphere;

// Vertices are grouped by cubic cells of this side (Å); every vertex of a cell looks only at the cell's
// candidates. A 1.5 Å cell holds tens to hundreds of surface vertices and a few candidate atoms; smaller
// cells cost more in the cells than they save in the vertices.
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
void box_candidates(const AtomGrid& grid, const std::vector<Atom>& atoms, double largest_radius, const Vec3& lo,
                    const Vec3& hi, std::vector<Candidate>& out) {
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
  out.erase(std::remove_if(first_kept, out.end(), [&](const Candidate& c) { return c.least_gap > bound + kSlack; }),
            out.end());
  // Most likely first, so that a vertex can stop early (ties by index: the order is deterministic).
  std::sort(first_kept, out.end(), [](const Candidate& a, const Candidate& b) {
    return a.least_gap < b.least_gap || (a.least_gap == b.least_gap && a.sphere.index < b.sphere.index);
  });
}

// box_candidates for a box inside a larger one, from the larger one's candidates (a superset: the best
// bound of the small box is at most the large one's, and its atoms come at least as near the large box).
void sub_box_candidates(const std::vector<Candidate>& outer, const Vec3& lo, const Vec3& hi,
                        std::vector<Candidate>& out) {
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

// The vertices' box in cubic cells of side kCell (doubled until there are at most kMaximumCells).
struct VertexCells {
  Vec3 lo{}, hi{};
  double side = kCell;
  std::array<std::int64_t, 3> cells{};

  explicit VertexCells(const std::vector<Vec3>& positions) {
    lo = positions.front(), hi = lo;
    for (const Vec3& p : positions)
      for (int d = 0; d < 3; ++d) lo[d] = std::min(lo[d], p[d]), hi[d] = std::max(hi[d], p[d]);
    for (;;) {
      for (int d = 0; d < 3; ++d) cells[d] = static_cast<std::int64_t>(std::floor((hi[d] - lo[d]) / side)) + 1;
      if (static_cast<double>(cells[0]) * static_cast<double>(cells[1]) * static_cast<double>(cells[2]) <=
          kMaximumCells)
        break;
      side *= 2;
    }
  }
  [[nodiscard]] std::int64_t count() const { return cells[0] * cells[1] * cells[2]; }
  [[nodiscard]] std::int64_t cell_of(const Vec3& p) const {
    std::int64_t c[3];
    for (int d = 0; d < 3; ++d)
      c[d] = std::clamp<std::int64_t>(detail::floor_to_int((p[d] - lo[d]) / side), 0, cells[d] - 1);
    return c[0] + cells[0] * (c[1] + cells[1] * c[2]);
  }
  // The box of cell c of a grid of cells of `box_side` with `per_row` x `per_plane` cells per plane.
  [[nodiscard]] std::pair<Vec3, Vec3> box_of(std::int64_t c, double box_side, std::int64_t per_row,
                                             std::int64_t per_plane) const {
    const std::int64_t index[3] = {c % per_row, (c / per_row) % per_plane, c / (per_row * per_plane)};
    std::pair<Vec3, Vec3> box;
    for (int d = 0; d < 3; ++d) {
      box.first[d] = lo[d] + box_side * static_cast<double>(index[d]);
      box.second[d] = box.first[d] + box_side;
    }
    return box;
  }
};

constexpr std::int64_t kVerticesPerChunk = 16384;

// The cells that hold vertices: slot[cell] is -1 without vertices, else the cell's rank among them;
// used[rank] is the cell.
struct UsedCells {
  std::vector<std::int32_t> slot;
  std::vector<std::int64_t> used;
};

UsedCells used_cells(const std::vector<Vec3>& positions, const VertexCells& cells, int threads) {
  UsedCells result;
  auto& slot = result.slot;
  slot.assign(static_cast<std::size_t>(cells.count()), -1);
  detail::parallel_ranges(static_cast<std::int64_t>(positions.size()), kVerticesPerChunk, threads,
                          [&](std::int64_t first, std::int64_t end) {
                            for (auto v = static_cast<std::size_t>(first); v < static_cast<std::size_t>(end); ++v)
                              std::atomic_ref<std::int32_t>(slot[static_cast<std::size_t>(cells.cell_of(positions[v]))])
                                  .store(0, std::memory_order_relaxed);
                          });
  for (std::size_t c = 0; c < slot.size(); ++c)
    if (slot[c] == 0)
      slot[c] = static_cast<std::int32_t>(result.used.size()), result.used.push_back(static_cast<std::int64_t>(c));
  return result;
}

// The candidates of every used cell: those of used cell u are candidates[begin[u] .. end[u]).
struct CellCandidates {
  std::vector<Candidate> candidates;
  std::vector<std::int64_t> begin, end;
};

// Candidates of each used cell, from those of its parent (the cell of twice the side holding it), which
// come from the atom grid: cells grouped by parent, groups in chunks, chunks concatenated in order.
CellCandidates cell_candidates(const AtomGrid& grid, const std::vector<Atom>& atoms, double largest_radius,
                               const VertexCells& cells, const std::vector<std::int64_t>& used, int threads) {
  const std::int64_t parent_row = (cells.cells[0] + 1) / 2, parent_plane = (cells.cells[1] + 1) / 2;
  std::vector<std::pair<std::int64_t, std::uint32_t>> by_parent(used.size());  // parent, child rank
  for (std::size_t u = 0; u < used.size(); ++u) {
    const std::int64_t c = used[u], x = c % cells.cells[0], y = (c / cells.cells[0]) % cells.cells[1],
                       z = c / (cells.cells[0] * cells.cells[1]);
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
  CellCandidates result;
  auto& candidate_begin = result.begin;  // within the chunk, then global
  auto& candidate_end = result.end;
  candidate_begin.resize(used.size()), candidate_end.resize(used.size());
  std::vector<std::int64_t> chunk_of_child(used.size());
  detail::parallel_chunks(group_chunks, threads, [&](std::int64_t chunk, int) {
    auto& out = chunk_candidates[static_cast<std::size_t>(chunk)];
    std::vector<Candidate> parent;
    for (std::int64_t g = chunk * kGroupsPerChunk; g < std::min(groups, (chunk + 1) * kGroupsPerChunk); ++g) {
      const auto [parent_lo, parent_hi] = cells.box_of(by_parent[group_start[static_cast<std::size_t>(g)]].first,
                                                       2 * cells.side, parent_row, parent_plane);
      parent.clear();
      box_candidates(grid, atoms, largest_radius, parent_lo, parent_hi, parent);
      for (auto m = group_start[static_cast<std::size_t>(g)]; m < group_start[static_cast<std::size_t>(g) + 1]; ++m) {
        const std::uint32_t u = by_parent[m].second;
        const auto [box_lo, box_hi] = cells.box_of(used[u], cells.side, cells.cells[0], cells.cells[1]);
        candidate_begin[u] = static_cast<std::int64_t>(out.size());
        sub_box_candidates(parent, box_lo, box_hi, out);
        candidate_end[u] = static_cast<std::int64_t>(out.size());
        chunk_of_child[u] = chunk;
      }
    }
  });
  std::vector<std::int64_t> chunk_offset(static_cast<std::size_t>(group_chunks) + 1, 0);
  for (std::int64_t c = 0; c < group_chunks; ++c)
    chunk_offset[static_cast<std::size_t>(c) + 1] =
        chunk_offset[static_cast<std::size_t>(c)] +
        static_cast<std::int64_t>(chunk_candidates[static_cast<std::size_t>(c)].size());
  for (std::size_t u = 0; u < used.size(); ++u) {
    const std::int64_t offset = chunk_offset[static_cast<std::size_t>(chunk_of_child[u])];
    candidate_begin[u] += offset, candidate_end[u] += offset;
  }
  result.candidates.reserve(static_cast<std::size_t>(chunk_offset.back()));
  for (auto& part : chunk_candidates)
    result.candidates.insert(result.candidates.end(), part.begin(), part.end()), std::vector<Candidate>().swap(part);
  return result;
}

// The nearest atom of each vertex among its cell's candidates (smallest |x - centre| - radius, ties to
// the smallest index).
std::vector<std::int32_t> nearest_atom_indices(const std::vector<Vec3>& positions, const VertexCells& cells,
                                               const UsedCells& used, const CellCandidates& candidates, int threads) {
  std::vector<std::int32_t> atom_index(positions.size());
  detail::parallel_ranges(static_cast<std::int64_t>(positions.size()), kVerticesPerChunk, threads,
                          [&](std::int64_t first, std::int64_t end) {
                            for (auto v = static_cast<std::size_t>(first); v < static_cast<std::size_t>(end); ++v) {
                              const Vec3& p = positions[v];
                              const auto u =
                                  static_cast<std::size_t>(used.slot[static_cast<std::size_t>(cells.cell_of(p))]);
                              double best = std::numeric_limits<double>::infinity();
                              std::int32_t chosen = -1;
                              for (auto m = candidates.begin[u]; m < candidates.end[u]; ++m) {
                                const Candidate& c = candidates.candidates[static_cast<std::size_t>(m)];
                                // The rest cannot come nearer (nor tie: the slack keeps rounding on the safe side).
                                if (c.least_gap > best + kSlack) break;
                                const Sphere& s = c.sphere;
                                const double gap = norm(p - s.centre) - s.radius;
                                if (gap < best || (gap == best && s.index < chosen)) best = gap, chosen = s.index;
                              }
                              atom_index[v] = chosen;
                            }
                          });
  return atom_index;
}

}  // namespace

void add_nearest_atoms(Mesh& mesh, const std::vector<Atom>& atoms, const SurfaceOptions& options) {
  const std::size_t n = mesh.vertex_count();
  std::vector<std::int32_t> atom_index, serial(n), residue(n), model(n);
  if (n > 0) {
    if (atoms.empty()) throw InputError("no atoms to take surface provenance from");
    const int threads = detail::surface_threads(options.threads);
    double largest_radius = 0;
    for (const auto& a : atoms) largest_radius = std::max(largest_radius, a.radius);
    const AtomGrid grid(atoms, 2.0);
    const VertexCells cells(mesh.positions);
    const UsedCells used = used_cells(mesh.positions, cells, threads);
    const CellCandidates candidates = cell_candidates(grid, atoms, largest_radius, cells, used.used, threads);
    atom_index = nearest_atom_indices(mesh.positions, cells, used, candidates, threads);
    detail::parallel_ranges(static_cast<std::int64_t>(n), kVerticesPerChunk, threads,
                            [&](std::int64_t first, std::int64_t end) {
                              for (auto v = static_cast<std::size_t>(first); v < static_cast<std::size_t>(end); ++v) {
                                const Atom& atom = atoms[static_cast<std::size_t>(atom_index[v])];
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
