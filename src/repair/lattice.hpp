// Private to the handle repair: the grid's samples as the vertices of the Freudenthal triangulation that
// contour_isosurface contours (six tetrahedra per cell), with the link and star of a vertex.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

namespace spheremap::detail {

// The 14 neighbours of a vertex: ±e1, ±e2, ±e3, ±(e1+e2), ±(e1+e3), ±(e2+e3), ±(e1+e2+e3), the edges of
// the six tetrahedra per cell. Neighbour n ^ 1 is the opposite of neighbour n.
// clang-format off
constexpr std::array<std::array<int, 3>, 14> kNeighbour = {{
    {1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}, {1, 1, 0}, {-1, -1, 0},
    {1, 0, 1}, {-1, 0, -1}, {0, 1, 1}, {0, -1, -1}, {1, 1, 1}, {-1, -1, -1}}};
// clang-format on

// The link of a vertex (a triangulated sphere): two neighbours are joined when their difference is itself
// a lattice edge.
struct LatticeLink {
  std::array<std::array<bool, 14>, 14> adjacent{};
  LatticeLink();
};
const LatticeLink& lattice_link();

// simple[mask], for the 2^14 patterns of set membership among the 14 neighbours: whether adding the vertex
// to the set keeps the set's topology (the part of the link in the set, and the rest, both non-empty and
// connected: for a full subcomplex of a 2-sphere this is contractibility, by Alexander duality).
const std::array<bool, 1u << 14>& simple_table();

// The simplices that contain a vertex, as lists of neighbour numbers: its 14 edges, 36 triangles (joined
// pairs of the link) and 24 tetrahedra (link triangles).
struct LatticeStar {
  std::vector<std::array<int, 2>> triangles;
  std::vector<std::array<int, 3>> tetrahedra;
  explicit LatticeStar(const LatticeLink& link);
};
const LatticeStar& lattice_star();

// Neighbour access: sample index offsets, and a border test only for samples on the grid's outer layer.
// Samples that are inside, or outside but not on the border, have all 14 neighbours in the grid (the
// border is outside by precondition), which is what lets the growths use plain offsets.
class Lattice {
 public:
  explicit Lattice(const std::array<std::int64_t, 3>& size) : nx_(size[0]), ny_(size[1]), nz_(size[2]) {
    for (int n = 0; n < 14; ++n) offset_[n] = kNeighbour[n][0] + nx_ * (kNeighbour[n][1] + ny_ * kNeighbour[n][2]);
  }
  [[nodiscard]] std::int64_t count() const { return nx_ * ny_ * nz_; }
  [[nodiscard]] std::int64_t offset(int n) const { return offset_[n]; }
  [[nodiscard]] std::array<std::int64_t, 3> coordinates(std::int64_t s) const {
    return {s % nx_, (s / nx_) % ny_, s / (nx_ * ny_)};
  }
  [[nodiscard]] bool on_border(std::int64_t s) const {
    const auto [i, j, k] = coordinates(s);
    return i == 0 || j == 0 || k == 0 || i == nx_ - 1 || j == ny_ - 1 || k == nz_ - 1;
  }
  // Calls visit(n, t) for each neighbour n of s inside the grid (t its index), visit(n, -1) outside it.
  template <typename Visit>
  void neighbours(std::int64_t s, Visit&& visit) const {
    const auto [i, j, k] = coordinates(s);
    if (i > 0 && j > 0 && k > 0 && i + 1 < nx_ && j + 1 < ny_ && k + 1 < nz_) {
      for (int n = 0; n < 14; ++n) visit(n, s + offset_[n]);
      return;
    }
    for (int n = 0; n < 14; ++n) {
      const std::int64_t a = i + kNeighbour[n][0], b = j + kNeighbour[n][1], c = k + kNeighbour[n][2];
      const bool inside = a >= 0 && b >= 0 && c >= 0 && a < nx_ && b < ny_ && c < nz_;
      visit(n, inside ? s + offset_[n] : std::int64_t{-1});
    }
  }
  // Calls visit(s) for every sample of the grid's outer layer, by increasing index.
  template <typename Visit>
  void border(Visit&& visit) const {
    for (std::int64_t k = 0; k < nz_; ++k)
      for (std::int64_t j = 0; j < ny_; ++j) {
        const std::int64_t row = nx_ * (j + ny_ * k);
        if (k == 0 || k == nz_ - 1 || j == 0 || j == ny_ - 1) {
          for (std::int64_t i = 0; i < nx_; ++i) visit(row + i);
        } else {
          visit(row);
          if (nx_ > 1) visit(row + nx_ - 1);
        }
      }
  }

 private:
  std::int64_t nx_, ny_, nz_;
  std::array<std::int64_t, 14> offset_{};
};

}  // namespace spheremap::detail
