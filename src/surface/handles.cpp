#include "spheremap/surface/handles.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <limits>
#include <queue>
#include <stdexcept>

#include "spheremap/surface/contour.hpp"
#include "spheremap/topology/components.hpp"

namespace spheremap {
namespace {

// The 14 neighbours of a vertex in the Freudenthal triangulation: ±e1, ±e2, ±e3, ±(e1+e2), ±(e1+e3),
// ±(e2+e3), ±(e1+e2+e3) — the edges of the six tetrahedra per cell used by contour_isosurface.
constexpr std::array<std::array<int, 3>, 14> kNeighbour = {{{1, 0, 0},  {-1, 0, 0},  {0, 1, 0},  {0, -1, 0},  {0, 0, 1},
                                                            {0, 0, -1}, {1, 1, 0},   {-1, -1, 0}, {1, 0, 1},  {-1, 0, -1},
                                                            {0, 1, 1},  {0, -1, -1}, {1, 1, 1},  {-1, -1, -1}}};

// Two neighbours of a vertex are joined in its link when their difference is itself a lattice edge.
struct Link {
  std::array<std::array<bool, 14>, 14> adjacent{};
  Link() {
    for (int a = 0; a < 14; ++a)
      for (int b = 0; b < 14; ++b) {
        if (a == b) continue;
        const std::array<int, 3> d{kNeighbour[b][0] - kNeighbour[a][0], kNeighbour[b][1] - kNeighbour[a][1],
                                   kNeighbour[b][2] - kNeighbour[a][2]};
        for (const auto& n : kNeighbour) adjacent[a][b] = adjacent[a][b] || n == d;
      }
  }
};

// Number of connected parts of the link vertices whose flag equals `value` (flags over the 14 neighbours).
int parts(const Link& link, const std::array<bool, 14>& flag, bool value) {
  std::array<bool, 14> seen{};
  int count = 0;
  for (int start = 0; start < 14; ++start) {
    if (flag[start] != value || seen[start]) continue;
    ++count;
    std::array<int, 14> stack{};
    int top = 0;
    stack[top++] = start;
    seen[start] = true;
    while (top > 0) {
      const int a = stack[--top];
      for (int b = 0; b < 14; ++b)
        if (!seen[b] && flag[b] == value && link.adjacent[a][b]) seen[b] = true, stack[top++] = b;
    }
  }
  return count;
}

// Grows a set by simple samples only, deepest first, and returns membership. For the inside (solid) the
// seed is the deepest inside sample and the set stays a ball; for the outside the seed is the whole grid
// border (with everything beyond the grid counted in), so the set stays a shell and what it encloses a
// ball.
// How deep each outside sample lies: its squared distance (grid units²) to the nearest inside sample.
// The SES field is flat (-probe) wherever a probe fits, so it cannot order the outside growth; this
// distance makes the two fronts entering a tunnel meet at its narrowest section, where a fill is smallest.
std::vector<float> outside_depth(const Grid3<double>& field, double level) {
  Grid3<float> depth;
  depth.size = field.size;
  depth.values.resize(field.values.size());
  for (std::size_t s = 0; s < field.values.size(); ++s)
    depth.values[s] = field.values[s] > level ? 0.0f : std::numeric_limits<float>::infinity();
  squared_distance_transform_in_place(depth);
  return std::move(depth.values);
}

std::vector<std::uint8_t> grow(const Grid3<double>& field, double level, bool solid) {
  const std::vector<float> depth = solid ? std::vector<float>() : outside_depth(field, level);
  static const Link link;
  const auto [nx, ny, nz] = field.size;
  const auto total = field.count();
  auto candidate = [&](std::int64_t s) { return solid ? field.values[s] > level : field.values[s] <= level; };
  // Deeper = farther inside the set being grown; for the outside, farther from the solid, then by field value.
  auto deeper = [&](std::int64_t a, std::int64_t b) {
    if (solid) return field.values[a] > field.values[b];
    if (depth[a] != depth[b]) return depth[a] > depth[b];
    return field.values[a] < field.values[b];
  };
  std::vector<std::uint8_t> in_set(static_cast<std::size_t>(total), 0);
  std::vector<std::uint8_t> queued(static_cast<std::size_t>(total), 0);
  auto neighbour = [&](std::int64_t s, int n) -> std::int64_t {
    const std::int64_t i = s % nx + kNeighbour[n][0], j = (s / nx) % ny + kNeighbour[n][1], k = s / (nx * ny) + kNeighbour[n][2];
    if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) return -1;
    return field.index(i, j, k);
  };
  // Deepest first; ties by index, so the result does not depend on the order of insertion.
  auto later = [&](std::int64_t a, std::int64_t b) { return deeper(b, a) ? true : deeper(a, b) ? false : a > b; };
  std::priority_queue<std::int64_t, std::vector<std::int64_t>, decltype(later)> frontier(later);
  auto offer_neighbours = [&](std::int64_t s) {
    for (int n = 0; n < 14; ++n) {
      const auto t = neighbour(s, n);
      if (t >= 0 && !in_set[t] && !queued[t] && candidate(t)) queued[t] = 1, frontier.push(t);
    }
  };
  if (solid) {
    // The seed is the deepest sample of the largest connected piece (by samples), so that the piece kept
    // whole is the main body even when a small detached piece is thicker.
    std::int64_t seed = -1, seed_piece_size = 0;
    {
      std::vector<std::int64_t> stack;
      for (std::int64_t start = 0; start < total; ++start) {
        if (!candidate(start) || in_set[start]) continue;
        std::int64_t size = 0, deepest = start;
        in_set[start] = 1;
        stack.push_back(start);
        while (!stack.empty()) {
          const auto v = stack.back();
          stack.pop_back();
          ++size;
          if (deeper(v, deepest)) deepest = v;
          for (int n = 0; n < 14; ++n) {
            const auto t = neighbour(v, n);
            if (t >= 0 && !in_set[t] && candidate(t)) in_set[t] = 1, stack.push_back(t);
          }
        }
        if (size > seed_piece_size) seed_piece_size = size, seed = deepest;
      }
      std::fill(in_set.begin(), in_set.end(), 0);
    }
    if (seed < 0) throw std::invalid_argument("cut_handles: nothing is inside");
    in_set[seed] = 1;
    offer_neighbours(seed);
  } else {
    for (std::int64_t k = 0; k < nz; ++k)
      for (std::int64_t j = 0; j < ny; ++j)
        for (std::int64_t i = 0; i < nx; ++i) {
          if (i != 0 && j != 0 && k != 0 && i != nx - 1 && j != ny - 1 && k != nz - 1) continue;
          const auto s = field.index(i, j, k);
          if (!candidate(s)) throw std::invalid_argument("cut_handles: the solid reaches the border of the grid");
          in_set[s] = 1;
        }
    for (std::int64_t s = 0; s < total; ++s)
      if (in_set[s]) offer_neighbours(s);
  }
  // A sample refused now may become simple later, when more of its neighbours are in: it is offered again
  // whenever a neighbour joins (queued is cleared on refusal). Each sample is offered at most 14 times.
  while (!frontier.empty()) {
    const auto s = frontier.top();
    frontier.pop();
    queued[s] = 0;
    std::array<bool, 14> member{};
    for (int n = 0; n < 14; ++n) {
      const auto t = neighbour(s, n);
      member[n] = t >= 0 ? in_set[t] != 0 : !solid;  // beyond the grid is outside
    }
    if (parts(link, member, true) == 1 && parts(link, member, false) == 1) {
      in_set[s] = 1;
      offer_neighbours(s);
    }
  }
  return in_set;
}

// The simplices of the Freudenthal triangulation that contain a vertex, as lists of neighbour numbers:
// its 14 edges, 36 triangles (adjacent pairs in the link) and 24 tetrahedra (link triangles).
struct Star {
  std::vector<std::array<int, 2>> triangles;
  std::vector<std::array<int, 3>> tetrahedra;
  explicit Star(const Link& link) {
    for (int a = 0; a < 14; ++a)
      for (int b = a + 1; b < 14; ++b) {
        if (!link.adjacent[a][b]) continue;
        triangles.push_back({a, b});
        for (int c = b + 1; c < 14; ++c)
          if (link.adjacent[a][c] && link.adjacent[b][c]) tetrahedra.push_back({a, b, c});
      }
    if (triangles.size() != 36 || tetrahedra.size() != 24) throw std::logic_error("Freudenthal star miscounted");
  }
};

}  // namespace

HandleRepair repair_handles(Grid3<double>& field, double level) {
  static const Link link;
  static const Star star(link);
  const auto solid = grow(field, level, true);
  const auto outside = grow(field, level, false);
  const auto [nx, ny, nz] = field.size;
  const auto total = field.count();
  auto neighbour = [&](std::int64_t s, int n) -> std::int64_t {
    const std::int64_t i = s % nx + kNeighbour[n][0], j = (s / nx) % ny + kNeighbour[n][1], k = s / (nx * ny) + kNeighbour[n][2];
    if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) return -1;
    return field.index(i, j, k);
  };
  // Clusters of left-out samples: label 0 none, else cluster number + 1.
  std::vector<std::int32_t> cluster(static_cast<std::size_t>(total), 0);
  std::vector<TopologyChange> clusters;
  for (std::int64_t s = 0; s < total; ++s) {
    const bool inside = field.values[s] > level;
    if (cluster[s] != 0 || (inside ? solid[s] != 0 : outside[s] != 0)) continue;
    TopologyChange change;
    change.filled = !inside;
    const auto label = static_cast<std::int32_t>(clusters.size() + 1);
    std::vector<std::int64_t> stack{s};
    cluster[s] = label;
    while (!stack.empty()) {
      const auto v = stack.back();
      stack.pop_back();
      change.samples.push_back(v);
      for (int n = 0; n < 14; ++n) {
        const auto t = neighbour(v, n);
        if (t < 0 || cluster[t] != 0 || (field.values[t] > level) != inside) continue;
        if (inside ? solid[t] != 0 : outside[t] != 0) continue;
        cluster[t] = label;
        stack.push_back(t);
      }
    }
    std::sort(change.samples.begin(), change.samples.end());
    clusters.push_back(std::move(change));
  }
  // Smallest first; ties by first sample (deterministic).
  std::vector<std::size_t> order(clusters.size());
  for (std::size_t c = 0; c < order.size(); ++c) order[c] = c;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return clusters[a].samples.size() != clusters[b].samples.size() ? clusters[a].samples.size() < clusters[b].samples.size()
                                                                    : clusters[a].samples.front() < clusters[b].samples.front();
  });
  std::vector<std::uint8_t> toggled(static_cast<std::size_t>(total), 0);
  const double below = std::nextafter(level, -1e300), above = std::nextafter(level, 1e300);
  HandleRepair repair;
  for (const auto c : order) {
    auto& change = clusters[c];
    for (const auto v : change.samples) toggled[v] = 1;
    // Each simplex touching the cluster is counted once, from its smallest toggled vertex.
    auto inside_now = [&](std::int64_t t) { return t >= 0 && field.values[t] > level; };
    int before = 0, after = 0;
    for (const auto v : change.samples) {
      std::array<std::int64_t, 14> nb{};
      for (int n = 0; n < 14; ++n) nb[n] = neighbour(v, n);
      auto counted_here = [&](std::int64_t t) { return t < 0 || !toggled[t] || t > v; };
      auto inside_after = [&](std::int64_t t) { return t >= 0 && (toggled[t] ? change.filled : field.values[t] > level); };
      const bool v_before = inside_now(v), v_after = change.filled;
      before += v_before ? 1 : 0;
      after += v_after ? 1 : 0;
      for (int a = 0; a < 14; ++a) {
        if (!counted_here(nb[a])) continue;
        before -= (v_before && inside_now(nb[a])) ? 1 : 0;
        after -= (v_after && inside_after(nb[a])) ? 1 : 0;
      }
      for (const auto& [a, b] : star.triangles) {
        if (!counted_here(nb[a]) || !counted_here(nb[b])) continue;
        before += (v_before && inside_now(nb[a]) && inside_now(nb[b])) ? 1 : 0;
        after += (v_after && inside_after(nb[a]) && inside_after(nb[b])) ? 1 : 0;
      }
      for (const auto& [a, b, d] : star.tetrahedra) {
        if (!counted_here(nb[a]) || !counted_here(nb[b]) || !counted_here(nb[d])) continue;
        before -= (v_before && inside_now(nb[a]) && inside_now(nb[b]) && inside_now(nb[d])) ? 1 : 0;
        after -= (v_after && inside_after(nb[a]) && inside_after(nb[b]) && inside_after(nb[d])) ? 1 : 0;
      }
    }
    for (const auto v : change.samples) toggled[v] = 0;
    change.euler_change = after - before;
    if (change.euler_change <= 0) continue;
    change.original_values.reserve(change.samples.size());
    for (const auto v : change.samples) {
      change.original_values.push_back(field.values[v]);
      field.values[v] = change.filled ? above : below;
    }
    repair.samples_changed += static_cast<std::int64_t>(change.samples.size());
    repair.changes.push_back(std::move(change));
  }
  return repair;
}

void undo_handle_repair(Grid3<double>& field, const HandleRepair& repair) {
  for (auto change = repair.changes.rbegin(); change != repair.changes.rend(); ++change)
    for (std::size_t k = 0; k < change->samples.size(); ++k) field.values[change->samples[k]] = change->original_values[k];
}

HandleCut cut_handles(Grid3<double>& field, double level) {
  const auto solid = grow(field, level, true);
  const auto outside = grow(field, level, false);
  std::vector<std::int64_t> cuts, fills;
  for (std::int64_t s = 0; s < field.count(); ++s) {
    if (field.values[s] > level && !solid[s]) cuts.push_back(s);
    if (field.values[s] <= level && !outside[s]) fills.push_back(s);
  }
  HandleCut result;
  // The smaller change wins: cutting every handle, or filling every tunnel (and cavity).
  result.filled = fills.size() < cuts.size();
  const double below = std::nextafter(level, -1e300), above = std::nextafter(level, 1e300);
  if (result.filled) {
    for (auto s : fills) field.values[s] = above;
    result.removed_samples = std::move(fills);
  } else {
    for (auto s : cuts) field.values[s] = below;
    result.removed_samples = std::move(cuts);
  }
  result.samples_removed = static_cast<std::int64_t>(result.removed_samples.size());
  return result;
}

namespace {
int outer_genus(const Grid3<double>& field, double level) {
  const auto components = mesh_components(contour_isosurface(field, level));
  return components.empty() ? 0 : components.front().genus;
}
}  // namespace

GenusRepair repair_outer_genus(Grid3<double>& field, double level) {
  GenusRepair result;
  result.outer_genus_before = outer_genus(field, level);
  if (result.outer_genus_before == 0) return result;
  // The clusters of one round are judged against each other's original surroundings; a handle whose two
  // membranes interact may survive a round, so the growths are redone on the changed field (a few rounds).
  constexpr int kRounds = 4;
  for (int round = 0; round < kRounds; ++round) {
    HandleRepair more = repair_handles(field, level);
    const bool changed = !more.changes.empty();
    result.per_handle.samples_changed += more.samples_changed;
    for (auto& change : more.changes) result.per_handle.changes.push_back(std::move(change));
    if (outer_genus(field, level) == 0) {
      result.method = "per-handle";
      result.samples_changed = result.per_handle.samples_changed;
      return result;
    }
    if (!changed) break;
  }
  undo_handle_repair(field, result.per_handle);
  result.per_handle = {};
  result.global = cut_handles(field, level);
  result.method = result.global.filled ? "fill" : "cut";
  result.samples_changed = result.global.samples_removed;
  return result;
}

}  // namespace spheremap
