#include "spheremap/repair/global_closure.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "repair_test_support.hpp"
#include "spheremap/surface/contour.hpp"

namespace spheremap {
namespace {

using namespace repair_testing;

TEST(GlobalClosure, ABallIsLeftAlone) {
  auto grid = sample(20, 0.5, {-5, -5, -5}, [](const Vec3& p) { return 3 - norm(p); });
  const auto before = grid.values;
  EXPECT_TRUE(close_all_handles(grid, 0).samples.empty());
  EXPECT_EQ(grid.values, before);
}

TEST(GlobalClosure, ATorusBecomesASphere) {
  auto grid = sample(40, 0.25, {-5, -5, -5}, [](const Vec3& p) {
    const double ring = std::sqrt(p[0] * p[0] + p[1] * p[1]) - 3;
    return 1.0 - std::sqrt(ring * ring + p[2] * p[2]);
  });
  const auto cut = close_all_handles(grid, 0);
  EXPECT_FALSE(cut.samples.empty());
  // The hole of this torus (radius 2) is wider than the tube (radius 1) is thick: cutting is cheaper.
  EXPECT_EQ(cut.kind, ClosureKind::kCut);
  expect_one_sphere(contour_isosurface(grid, 0));
}

TEST(GlobalClosure, AThinRingAroundAWideHoleIsFilledWhenThatIsCheaper) {
  // A thick slab with a narrow hole through it: filling the hole changes far fewer samples than cutting.
  auto grid = sample(40, 0.25, {-5, -5, -5}, [](const Vec3& p) {
    const double slab = 1.5 - std::abs(p[2]);
    const double box = 4 - std::max(std::abs(p[0]), std::abs(p[1]));
    const double hole = std::sqrt(p[0] * p[0] + p[1] * p[1]) - 0.6;
    return std::min({slab, box, hole});
  });
  const auto cut = close_all_handles(grid, 0);
  EXPECT_EQ(cut.kind, ClosureKind::kFill);
  expect_one_sphere(contour_isosurface(grid, 0));
}

TEST(GlobalClosure, RandomSolidsBecomeOneSphere) {
  std::mt19937 random(5);
  for (int trial = 0; trial < 15; ++trial) {
    Grid3<double> grid;
    grid.size = {10, 9, 11};
    grid.values.resize(static_cast<std::size_t>(grid.count()));
    for (std::int64_t k = 0; k < grid.size[2]; ++k)
      for (std::int64_t j = 0; j < grid.size[1]; ++j)
        for (std::int64_t i = 0; i < grid.size[0]; ++i) {
          const bool border =
              i == 0 || j == 0 || k == 0 || i == grid.size[0] - 1 || j == grid.size[1] - 1 || k == grid.size[2] - 1;
          grid.values[grid.index(i, j, k)] = border ? -1.0 : static_cast<double>(static_cast<int>(random() % 7) - 3);
        }
    if (*std::max_element(grid.values.begin(), grid.values.end()) <= 0) continue;
    close_all_handles(grid, 0);
    expect_one_sphere(contour_isosurface(grid, 0));
  }
}

}  // namespace
}  // namespace spheremap
