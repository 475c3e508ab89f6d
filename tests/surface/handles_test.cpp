#include "spheremap/surface/handles.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "../test_support.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/surface/contour.hpp"

namespace spheremap {
namespace {

using testing_support::expect_closed_oriented_manifold;

Grid3<double> sample(std::int64_t n, double spacing, const Vec3& origin, auto&& function) {
  Grid3<double> grid;
  grid.size = {n, n, n};
  grid.spacing = spacing;
  grid.origin = origin;
  grid.values.resize(static_cast<std::size_t>(grid.count()));
  for (std::int64_t k = 0; k < n; ++k)
    for (std::int64_t j = 0; j < n; ++j)
      for (std::int64_t i = 0; i < n; ++i) grid.values[grid.index(i, j, k)] = function(grid.point(i, j, k));
  return grid;
}

// One closed sphere: a single component with V - E + F = 2.
void expect_one_sphere(const Mesh& mesh) {
  expect_closed_oriented_manifold(mesh);
  std::vector<std::int32_t> parent(mesh.vertex_count());
  for (std::size_t v = 0; v < parent.size(); ++v) parent[v] = static_cast<std::int32_t>(v);
  auto find = [&](std::int32_t x) {
    while (parent[x] != x) x = parent[x] = parent[parent[x]];
    return x;
  };
  for (const auto& t : mesh.triangles) parent[find(t[1])] = find(t[0]), parent[find(t[2])] = find(t[0]);
  std::int64_t roots = 0;
  for (std::size_t v = 0; v < parent.size(); ++v) roots += find(static_cast<std::int32_t>(v)) == static_cast<std::int32_t>(v);
  EXPECT_EQ(roots, 1);
  const auto faces = static_cast<std::int64_t>(mesh.triangle_count());
  EXPECT_EQ(static_cast<std::int64_t>(mesh.vertex_count()) - faces * 3 / 2 + faces, 2);
}

TEST(Handles, ABallIsLeftAlone) {
  auto grid = sample(20, 0.5, {-5, -5, -5}, [](const Vec3& p) { return 3 - norm(p); });
  const auto before = grid.values;
  EXPECT_EQ(cut_handles(grid, 0).samples_removed, 0);
  EXPECT_EQ(grid.values, before);
}

TEST(Handles, ATorusBecomesASphere) {
  auto grid = sample(40, 0.25, {-5, -5, -5}, [](const Vec3& p) {
    const double ring = std::sqrt(p[0] * p[0] + p[1] * p[1]) - 3;
    return 1.0 - std::sqrt(ring * ring + p[2] * p[2]);
  });
  const auto cut = cut_handles(grid, 0);
  EXPECT_GT(cut.samples_removed, 0);
  // The hole of this torus (radius 2) is wider than the tube (radius 1) is thick: cutting is cheaper.
  EXPECT_FALSE(cut.filled);
  expect_one_sphere(contour_isosurface(grid, 0));
}

TEST(Handles, AThinRingAroundAWideHoleIsFilledWhenThatIsCheaper) {
  // A thick slab with a narrow hole through it: filling the hole changes far fewer samples than cutting.
  auto grid = sample(40, 0.25, {-5, -5, -5}, [](const Vec3& p) {
    const double slab = 1.5 - std::abs(p[2]);
    const double box = 4 - std::max(std::abs(p[0]), std::abs(p[1]));
    const double hole = std::sqrt(p[0] * p[0] + p[1] * p[1]) - 0.6;
    return std::min({slab, box, hole});
  });
  const auto cut = cut_handles(grid, 0);
  EXPECT_TRUE(cut.filled);
  expect_one_sphere(contour_isosurface(grid, 0));
}

TEST(Handles, RandomSolidsBecomeOneSphere) {
  std::mt19937 random(5);
  for (int trial = 0; trial < 15; ++trial) {
    Grid3<double> grid;
    grid.size = {10, 9, 11};
    grid.values.resize(static_cast<std::size_t>(grid.count()));
    for (std::int64_t k = 0; k < grid.size[2]; ++k)
      for (std::int64_t j = 0; j < grid.size[1]; ++j)
        for (std::int64_t i = 0; i < grid.size[0]; ++i) {
          const bool border = i == 0 || j == 0 || k == 0 || i == grid.size[0] - 1 || j == grid.size[1] - 1 || k == grid.size[2] - 1;
          grid.values[grid.index(i, j, k)] = border ? -1.0 : static_cast<double>(static_cast<int>(random() % 7) - 3);
        }
    if (*std::max_element(grid.values.begin(), grid.values.end()) <= 0) continue;
    cut_handles(grid, 0);
    expect_one_sphere(contour_isosurface(grid, 0));
  }
}

}  // namespace
}  // namespace spheremap
