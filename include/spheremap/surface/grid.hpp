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
/// Precondition: is_target.values.size() == is_target.count().
Grid3<double> squared_distance_transform(const Grid3<std::uint8_t>& is_target);

}  // namespace spheremap
