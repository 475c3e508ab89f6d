// Regular 3D grids of samples (stage: surface).
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

}  // namespace spheremap
