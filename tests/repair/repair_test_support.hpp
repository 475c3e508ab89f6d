// Shared by the tests of the handle repair: sampled solids and checks of their contours.
#pragma once

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <random>
#include <vector>

#include "../test_support.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/mesh.hpp"
#include "spheremap/surface/contour.hpp"
#include "spheremap/surface/grid.hpp"
#include "spheremap/topology/components.hpp"

namespace spheremap::repair_testing {

using testing_support::sample;

// One closed sphere: a single component with V - E + F = 2.
inline void expect_one_sphere(const Mesh& mesh) {
  testing_support::expect_closed_oriented_manifold(mesh);
  EXPECT_EQ(mesh_components(mesh).size(), 1u);
  const auto faces = static_cast<std::int64_t>(mesh.triangle_count());
  EXPECT_EQ(static_cast<std::int64_t>(mesh.vertex_count()) - faces * 3 / 2 + faces, 2);
}

// A thick ring around a wide hole (cheaper to cut) beside a slab with a narrow hole (cheaper to fill).
inline double ring_and_slab(const Vec3& p) {
  const Vec3 q{p[0] + 4.5, p[1], p[2]};
  const double around = std::sqrt(q[0] * q[0] + q[1] * q[1]) - 2.5;
  const double ring = 0.8 - std::sqrt(around * around + q[2] * q[2]);
  const Vec3 r{p[0] - 1.0, p[1], p[2]};
  const double slab = std::min(
      {1.5 - std::abs(r[2]), 3 - std::max(std::abs(r[0]), std::abs(r[1])), std::sqrt(r[0] * r[0] + r[1] * r[1]) - 0.6});
  return std::max(ring, slab);
}

inline Grid3<double> ring_and_slab_grid() {
  Grid3<double> grid;
  grid.size = {80, 40, 24};
  grid.spacing = 0.25;
  grid.origin = {-9.5, -5, -3};
  grid.values.resize(static_cast<std::size_t>(grid.count()));
  for (std::int64_t k = 0; k < grid.size[2]; ++k)
    for (std::int64_t j = 0; j < grid.size[1]; ++j)
      for (std::int64_t i = 0; i < grid.size[0]; ++i)
        grid.values[grid.index(i, j, k)] = ring_and_slab(grid.point(i, j, k));
  return grid;
}

// A random walk of `count` ball centres from the origin, steps of `step_length` in random directions
// (`step` draws each coordinate), clamped to the cube [-bound, bound]³: the way chains of atoms close loops.
inline std::vector<Vec3> random_walk(std::mt19937& random, std::uniform_real_distribution<double>& step,
                                     std::size_t count, double step_length, double bound) {
  std::vector<Vec3> centres{{0, 0, 0}};
  while (centres.size() < count) {
    Vec3 d{step(random), step(random), step(random)};
    const double length = norm(d);
    if (length < 0.2) continue;
    Vec3 next = centres.back() + (step_length / length) * d;
    for (auto& x : next) x = std::clamp(x, -bound, bound);
    centres.push_back(next);
  }
  return centres;
}

// The union of balls of `radius` at `centres`: positive inside.
inline double necklace(const std::vector<Vec3>& centres, double radius, const Vec3& p) {
  double best = -1e9;
  for (const auto& c : centres) best = std::max(best, radius - norm(p - c));
  return best;
}

// Total area of a contour (every component).
inline double contour_area(const Grid3<double>& grid) {
  double area = 0;
  for (const auto& c : mesh_components(contour_isosurface(grid, 0))) area += c.area;
  return area;
}

Grid3<double> sampled_box(std::array<std::int64_t, 3> size, double spacing, const Vec3& origin, auto&& function) {
  Grid3<double> grid;
  grid.size = size;
  grid.spacing = spacing;
  grid.origin = origin;
  grid.values.resize(static_cast<std::size_t>(grid.count()));
  for (std::int64_t k = 0; k < size[2]; ++k)
    for (std::int64_t j = 0; j < size[1]; ++j)
      for (std::int64_t i = 0; i < size[0]; ++i) grid.values[grid.index(i, j, k)] = function(grid.point(i, j, k));
  return grid;
}

}  // namespace spheremap::repair_testing
