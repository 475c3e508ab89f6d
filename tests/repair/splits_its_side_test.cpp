#include "../../src/repair/splits_its_side.hpp"

#include <gtest/gtest.h>

#include <cmath>

#include "repair_test_support.hpp"

namespace spheremap {
namespace {

using namespace repair_testing;

// Moves the samples of `grid` where `where(point)` holds and the field is above the level 0 (`inside`) or
// not, to just across it, as the repair moves a cluster; returns them in ascending order.
std::vector<std::int64_t> move_across(Grid3<double>& grid, bool inside, auto&& where) {
  std::vector<std::int64_t> moved;
  for (std::int64_t k = 0; k < grid.size[2]; ++k)
    for (std::int64_t j = 0; j < grid.size[1]; ++j)
      for (std::int64_t i = 0; i < grid.size[0]; ++i) {
        const auto s = grid.index(i, j, k);
        if ((grid.values[static_cast<std::size_t>(s)] > 0) != inside || !where(grid.point(i, j, k))) continue;
        grid.values[static_cast<std::size_t>(s)] = inside ? -0.1 : 0.1;
        moved.push_back(s);
      }
  return moved;
}

constexpr std::int64_t kUnlimited = 1'000'000;

TEST(ClosureSplitsItsSide, ASecondCutAcrossARingSplitsItAndIsToldFromACutThatRemovesItsHandle) {
  auto grid = sample(48, 0.25, {-6, -6, -6}, [](const Vec3& p) {
    const double ring = std::sqrt(p[0] * p[0] + p[1] * p[1]) - 3;
    return 1.0 - std::sqrt(ring * ring + p[2] * p[2]);
  });
  // Both raise the Euler characteristic by one: the first removes the ring's handle, the second splits
  // the ring in two. Only the second splits.
  const auto first = move_across(grid, true, [](const Vec3& p) { return std::abs(p[0]) < 0.3 && p[1] > 0; });
  ASSERT_FALSE(first.empty());
  EXPECT_FALSE(detail::closure_splits_its_side(grid, 0, first, ClosureKind::kCut, kUnlimited));
  const auto second = move_across(grid, true, [](const Vec3& p) { return std::abs(p[0]) < 0.3 && p[1] < 0; });
  ASSERT_FALSE(second.empty());
  EXPECT_TRUE(detail::closure_splits_its_side(grid, 0, second, ClosureKind::kCut, kUnlimited));
  // Each half holds about 1,600 samples: a search limited to 100 gives up and calls the change harmless.
  EXPECT_FALSE(detail::closure_splits_its_side(grid, 0, second, ClosureKind::kCut, 100));
}

TEST(ClosureSplitsItsSide, ASecondFillAcrossAPipeClosesAVoidAndIsToldFromAFillThatRemovesItsTunnel) {
  auto grid = sample(48, 0.25, {-6, -6, -6}, [](const Vec3& p) {
    const double r = std::sqrt(p[0] * p[0] + p[1] * p[1]);
    return std::min({2.5 - r, r - 1.5, 3.0 - std::abs(p[2])});
  });
  const auto top =
      move_across(grid, false, [](const Vec3& p) { return std::abs(p[2] - 2.6) < 0.2 && std::hypot(p[0], p[1]) < 2; });
  ASSERT_FALSE(top.empty());
  EXPECT_FALSE(detail::closure_splits_its_side(grid, 0, top, ClosureKind::kFill, kUnlimited));
  const auto bottom =
      move_across(grid, false, [](const Vec3& p) { return std::abs(p[2] + 2.6) < 0.2 && std::hypot(p[0], p[1]) < 2; });
  ASSERT_FALSE(bottom.empty());
  EXPECT_TRUE(detail::closure_splits_its_side(grid, 0, bottom, ClosureKind::kFill, kUnlimited));
  // Samples made solid away from the solid float: a new piece, no handle removed.
  const auto floating = move_across(grid, false, [](const Vec3& p) { return norm(p - Vec3{4.5, 4.5, 4.5}) < 0.4; });
  ASSERT_FALSE(floating.empty());
  EXPECT_TRUE(detail::closure_splits_its_side(grid, 0, floating, ClosureKind::kFill, kUnlimited));
}

}  // namespace
}  // namespace spheremap
