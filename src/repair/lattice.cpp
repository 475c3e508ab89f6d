#include "lattice.hpp"

#include <stdexcept>

namespace spheremap::detail {
namespace {

// Number of connected parts of the link vertices whose bit in `mask` equals `value`.
int parts(const LatticeLink& link, unsigned mask, bool value) {
  std::array<bool, 14> seen{};
  int count = 0;
  auto has = [&](int n) { return (((mask >> n) & 1u) != 0) == value; };
  for (int start = 0; start < 14; ++start) {
    if (!has(start) || seen[start]) continue;
    ++count;
    std::array<int, 14> stack{};
    int top = 0;
    stack[top++] = start;
    seen[start] = true;
    while (top > 0) {
      const int a = stack[--top];
      for (int b = 0; b < 14; ++b)
        if (!seen[b] && has(b) && link.adjacent[a][b]) seen[b] = true, stack[top++] = b;
    }
  }
  return count;
}

}  // namespace

LatticeLink::LatticeLink() {
  for (int a = 0; a < 14; ++a)
    for (int b = 0; b < 14; ++b) {
      if (a == b) continue;
      const std::array<int, 3> d{kNeighbour[b][0] - kNeighbour[a][0], kNeighbour[b][1] - kNeighbour[a][1],
                                 kNeighbour[b][2] - kNeighbour[a][2]};
      for (const auto& n : kNeighbour) adjacent[a][b] = adjacent[a][b] || n == d;
    }
}

const LatticeLink& lattice_link() {
  static const LatticeLink link;
  return link;
}

const std::array<bool, 1u << 14>& simple_table() {
  static const std::array<bool, 1u << 14> table = [] {
    std::array<bool, 1u << 14> simple{};
    const LatticeLink& link = lattice_link();
    for (unsigned mask = 0; mask < (1u << 14); ++mask)
      simple[mask] = parts(link, mask, true) == 1 && parts(link, mask, false) == 1;
    return simple;
  }();
  return table;
}

LatticeStar::LatticeStar(const LatticeLink& link) {
  for (int a = 0; a < 14; ++a)
    for (int b = a + 1; b < 14; ++b) {
      if (!link.adjacent[a][b]) continue;
      triangles.push_back({a, b});
      for (int c = b + 1; c < 14; ++c)
        if (link.adjacent[a][c] && link.adjacent[b][c]) tetrahedra.push_back({a, b, c});
    }
  if (triangles.size() != 36 || tetrahedra.size() != 24) throw std::logic_error("Freudenthal star miscounted");
}

const LatticeStar& lattice_star() {
  static const LatticeStar star(lattice_link());
  return star;
}

}  // namespace spheremap::detail
