#include "spheremap/surface/handles.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <queue>
#include <stdexcept>

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
std::vector<std::uint8_t> grow(const Grid3<double>& field, double level, bool solid) {
  static const Link link;
  const auto [nx, ny, nz] = field.size;
  const auto total = field.count();
  auto candidate = [&](std::int64_t s) { return solid ? field.values[s] > level : field.values[s] <= level; };
  auto deeper = [&](std::int64_t a, std::int64_t b) { return solid ? field.values[a] > field.values[b] : field.values[a] < field.values[b]; };
  std::vector<std::uint8_t> in_set(static_cast<std::size_t>(total), 0);
  std::vector<std::uint8_t> queued(static_cast<std::size_t>(total), 0);
  auto neighbour = [&](std::int64_t s, int n) -> std::int64_t {
    const std::int64_t i = s % nx + kNeighbour[n][0], j = (s / nx) % ny + kNeighbour[n][1], k = s / (nx * ny) + kNeighbour[n][2];
    if (i < 0 || j < 0 || k < 0 || i >= nx || j >= ny || k >= nz) return -1;
    return field.index(i, j, k);
  };
  // Deepest first; ties by index, so the result does not depend on the order of insertion.
  auto later = [&](std::int64_t a, std::int64_t b) { return field.values[a] != field.values[b] ? deeper(b, a) : a > b; };
  std::priority_queue<std::int64_t, std::vector<std::int64_t>, decltype(later)> frontier(later);
  auto offer_neighbours = [&](std::int64_t s) {
    for (int n = 0; n < 14; ++n) {
      const auto t = neighbour(s, n);
      if (t >= 0 && !in_set[t] && !queued[t] && candidate(t)) queued[t] = 1, frontier.push(t);
    }
  };
  if (solid) {
    std::int64_t seed = -1;
    for (std::int64_t s = 0; s < total; ++s)
      if (candidate(s) && (seed < 0 || deeper(s, seed))) seed = s;
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

}  // namespace

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

}  // namespace spheremap
