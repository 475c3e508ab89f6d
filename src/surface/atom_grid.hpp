// Private to the surface stage: atoms bucketed in a dense grid of cubic cells, for neighbour searches.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "../util/rounding.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/molecule/structure.hpp"

namespace spheremap::detail {

/// An atom's sphere, copied out of Atom (whose strings would spread the centres over memory).
struct Sphere {
  Vec3 centre;
  double radius;
  std::int32_t index;  // into the atoms
};

/// Atoms in a dense grid of cubic cells (atoms of a cell in increasing index order, stored contiguously).
/// Precondition: `atoms` is not empty and `cell` > 0.
class AtomGrid {
 public:
  AtomGrid(const std::vector<Atom>& atoms, double cell) : cell_(cell) {
    Vec3 hi = atoms.front().position;
    lo_ = hi;
    for (const auto& a : atoms)
      for (int d = 0; d < 3; ++d) lo_[d] = std::min(lo_[d], a.position[d]), hi[d] = std::max(hi[d], a.position[d]);
    for (int d = 0; d < 3; ++d) n_[d] = static_cast<std::int64_t>(std::floor((hi[d] - lo_[d]) / cell_)) + 1;
    start_.assign(static_cast<std::size_t>(n_[0] * n_[1] * n_[2] + 1), 0);
    std::vector<std::int64_t> cell_of(atoms.size());
    for (std::size_t a = 0; a < atoms.size(); ++a) {
      const auto c = cell_index(atoms[a].position);
      cell_of[a] = c[0] + n_[0] * (c[1] + n_[1] * c[2]);
      ++start_[static_cast<std::size_t>(cell_of[a]) + 1];
    }
    for (std::size_t c = 1; c < start_.size(); ++c) start_[c] += start_[c - 1];
    spheres_.resize(atoms.size());
    std::vector<std::int32_t> fill(start_.begin(), start_.end() - 1);
    for (std::size_t a = 0; a < atoms.size(); ++a)
      spheres_[static_cast<std::size_t>(fill[static_cast<std::size_t>(cell_of[a])]++)] = {
          atoms[a].position, atoms[a].radius, static_cast<std::int32_t>(a)};
  }

  /// Calls visit(sphere) for every atom in the cells that meet the cube of half-width `reach` around p
  /// (a superset of the atoms whose centre is within `reach`), cell by cell in grid order.
  template <typename Visit>
  void near_spheres(const Vec3& p, double reach, Visit&& visit) const {
    std::array<std::int64_t, 3> first, last;
    if (!cell_range(p, reach, first, last)) return;
    for (std::int64_t z = first[2]; z <= last[2]; ++z)
      for (std::int64_t y = first[1]; y <= last[1]; ++y) {
        const auto row = static_cast<std::size_t>(n_[0] * (y + n_[1] * z));
        const Sphere* begin = spheres_.data() + start_[row + static_cast<std::size_t>(first[0])];
        const Sphere* end = spheres_.data() + start_[row + static_cast<std::size_t>(last[0]) + 1];
        for (const Sphere* s = begin; s != end; ++s) visit(*s);
      }
  }

  /// near_spheres, by atom index.
  template <typename Visit>
  void near(const Vec3& p, double reach, Visit&& visit) const {
    near_spheres(p, reach, [&](const Sphere& s) { visit(s.index); });
  }

  /// The atom whose van der Waals sphere is nearest to p: smallest |p - centre| - radius (computed as
  /// norm(p - centre) - radius), ties to the smallest index. `hint` (any atom, e.g. the answer for a
  /// nearby point) gives the first bound; the answer does not depend on it. Only cells that can hold a
  /// nearer sphere are visited. `largest_radius`: at least every atom's radius.
  [[nodiscard]] std::int32_t nearest_sphere(const Vec3& p, double largest_radius, std::int32_t hint,
                                            const std::vector<Atom>& atoms) const {
    std::int32_t chosen = hint;
    double best =
        norm(p - atoms[static_cast<std::size_t>(hint)].position) - atoms[static_cast<std::size_t>(hint)].radius;
    // An atom can only be nearer if its centre is within best + largest_radius of p.
    std::array<std::int64_t, 3> first, last;
    if (!cell_range(p, best + largest_radius, first, last)) return chosen;
    auto gap_along = [&](int d, std::int64_t c) {
      const double low = lo_[d] + cell_ * static_cast<double>(c), high = low + cell_;
      return p[d] < low ? low - p[d] : p[d] > high ? p[d] - high : 0.0;
    };
    for (std::int64_t z = first[2]; z <= last[2]; ++z) {
      const double gz = gap_along(2, z);
      for (std::int64_t y = first[1]; y <= last[1]; ++y) {
        const double gy = gap_along(1, y), gyz = gy * gy + gz * gz;
        for (std::int64_t x = first[0]; x <= last[0]; ++x) {
          const auto c = static_cast<std::size_t>(x + n_[0] * (y + n_[1] * z));
          if (start_[c] == start_[c + 1]) continue;
          const double gx = gap_along(0, x), bound = best + largest_radius;
          if (gx * gx + gyz > bound * bound) continue;  // every centre in the cell is farther than bound
          for (auto m = start_[c]; m < start_[c + 1]; ++m) {
            const Sphere& s = spheres_[static_cast<std::size_t>(m)];
            const double limit = best + s.radius;
            if (squared_distance(p, s.centre) > limit * limit * (1 + 1e-12)) continue;  // gap > best for sure
            const double gap = norm(p - s.centre) - s.radius;
            if (gap < best || (gap == best && s.index < chosen)) best = gap, chosen = s.index;
          }
        }
      }
    }
    return chosen;
  }

  /// Some atom in the cells around p (the first found), or atom 0.
  [[nodiscard]] std::int32_t some_atom_near(const Vec3& p) const {
    const auto home = cell_index(p);
    for (std::int64_t r = 0; r <= 2; ++r)
      for (std::int64_t z = std::max<std::int64_t>(0, home[2] - r); z <= std::min(n_[2] - 1, home[2] + r); ++z)
        for (std::int64_t y = std::max<std::int64_t>(0, home[1] - r); y <= std::min(n_[1] - 1, home[1] + r); ++y)
          for (std::int64_t x = std::max<std::int64_t>(0, home[0] - r); x <= std::min(n_[0] - 1, home[0] + r); ++x) {
            const auto c = static_cast<std::size_t>(x + n_[0] * (y + n_[1] * z));
            if (start_[c] < start_[c + 1]) return spheres_[static_cast<std::size_t>(start_[c])].index;
          }
    return 0;
  }

 private:
  std::array<std::int64_t, 3> cell_index(const Vec3& p) const {
    std::array<std::int64_t, 3> c;
    for (int d = 0; d < 3; ++d) c[d] = std::clamp<std::int64_t>(floor_to_int((p[d] - lo_[d]) / cell_), 0, n_[d] - 1);
    return c;
  }
  // The cells that meet the cube of half-width `reach` around p; false when there are none.
  bool cell_range(const Vec3& p, double reach, std::array<std::int64_t, 3>& first,
                  std::array<std::int64_t, 3>& last) const {
    for (int d = 0; d < 3; ++d) {
      first[d] = std::max<std::int64_t>(0, floor_to_int((p[d] - reach - lo_[d]) / cell_));
      last[d] = std::min<std::int64_t>(n_[d] - 1, floor_to_int((p[d] + reach - lo_[d]) / cell_));
      if (first[d] > last[d]) return false;
    }
    return true;
  }
  double cell_;
  Vec3 lo_{};
  std::array<std::int64_t, 3> n_{};
  std::vector<std::int32_t> start_;
  std::vector<Sphere> spheres_;
};

}  // namespace spheremap::detail
