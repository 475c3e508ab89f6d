// Regular 3D grids and the exact Euclidean distance transform (stage: surface).
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// A regular grid of nx * ny * nz samples at origin + spacing * (i, j, k); index = i + nx * (j + ny * k).
template <typename T>
struct Grid3 {
  std::array<std::int64_t, 3> size{0, 0, 0};
  Vec3 origin{0, 0, 0};
  double spacing = 1;
  std::vector<T> values;

  [[nodiscard]] std::int64_t index(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return i + size[0] * (j + size[1] * k);
  }
  [[nodiscard]] Vec3 point(std::int64_t i, std::int64_t j, std::int64_t k) const {
    return {origin[0] + spacing * static_cast<double>(i), origin[1] + spacing * static_cast<double>(j),
            origin[2] + spacing * static_cast<double>(k)};
  }
  [[nodiscard]] std::int64_t count() const { return size[0] * size[1] * size[2]; }
};

/// Exact squared Euclidean distance, in grid units², from every sample to the nearest sample where
/// `is_target` is nonzero (Felzenszwalb & Huttenlocher 2012, separable lower envelopes of parabolas):
/// O(samples). Samples farther than any target (no target at all) get +infinity.
/// `threads`: 0 = one per hardware thread; the result does not depend on it.
/// Precondition: is_target.values.size() == is_target.count().
Grid3<double> squared_distance_transform(const Grid3<std::uint8_t>& is_target, int threads = 0);

/// The same transform in place, for any initial values f >= 0 (+infinity allowed): afterwards each
/// sample q holds min over samples p of |q - p|² (grid units²) + f(p). With f = 0 on targets and
/// +infinity elsewhere this is squared_distance_transform without a second grid. Lines are computed in
/// double; with T = float the result is exact as long as the squared distances are integers below 2^24
/// (a 0/infinity start on grids up to 4096 samples per axis). Precondition: values.size() == count().
template <typename T>
void squared_distance_transform_in_place(Grid3<T>& grid, int threads = 0);

extern template void squared_distance_transform_in_place<double>(Grid3<double>&, int);
extern template void squared_distance_transform_in_place<float>(Grid3<float>&, int);

}  // namespace spheremap
