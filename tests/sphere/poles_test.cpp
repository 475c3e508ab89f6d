#include "spheremap/sphere/poles.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>
#include <utility>
#include <vector>

#include "spheremap/geometry/vec.hpp"
#include "spheremap/shapes/shapes.hpp"

namespace spheremap {
namespace {

// The first pair (i < j, in index order) at the largest squared distance, summed as farthest_pair does.
std::pair<std::int32_t, std::int32_t> brute_force_farthest_pair(const std::vector<Vec3>& points) {
  double best = -1;
  std::pair<std::int32_t, std::int32_t> pair;
  for (std::int32_t i = 0; i < static_cast<std::int32_t>(points.size()); ++i)
    for (std::int32_t j = i + 1; j < static_cast<std::int32_t>(points.size()); ++j) {
      double d = 0;
      for (int a = 0; a < 3; ++a) d += std::abs(points[i][a] - points[j][a]) * std::abs(points[i][a] - points[j][a]);
      if (d > best) best = d, pair = {i, j};
    }
  return pair;
}

TEST(FarthestPair, MatchesBruteForce) {
  std::mt19937 random(7);
  for (int trial = 0; trial < 20; ++trial) {
    std::vector<Vec3> points(50 + trial * 37);
    for (auto& p : points)
      for (auto& c : p) c = static_cast<double>(random() % 1000) / 7.0;  // many exact ties
    EXPECT_EQ(farthest_pair(points), brute_force_farthest_pair(points)) << "trial " << trial;
  }
  // All points on a sphere: the worst case for hull-based methods.
  const Mesh ico = make_icosphere(3);
  const auto [a, b] = farthest_pair(ico.positions);
  EXPECT_NEAR(norm(ico.positions[a] - ico.positions[b]), 2.0, 1e-12);
  // Point sets where the search visits many points (nearly all as far from the centre: past the first
  // few, scanned, it goes through the k-d tree) and a few (a cube's corners), against brute force,
  // ties included (antipodal pairs by the hundred).
  for (const Mesh& shape : {make_icosphere(3), perturb_vertices(make_icosphere(3), 0.3, 4), make_subdivided_cube(12),
                            make_ellipsoid(3, 1, 1, 1.001), make_dumbbell(3, 0.5, 20, 16)})
    EXPECT_EQ(farthest_pair(shape.positions), brute_force_farthest_pair(shape.positions))
        << shape.positions.size() << " points";
  // Two pairs at exactly the same distance: the one of the point farthest from the centre is found first,
  // the other (smaller indices) must still win.
  const std::vector<Vec3> tie{{-1, 0, 0}, {1, 0, 0}, {0, -1.25, 0}, {0, 0.75, 0}, {0, 0.5, 0}};
  EXPECT_EQ(farthest_pair(tie), (std::pair<std::int32_t, std::int32_t>{0, 1}));
}

TEST(FarthestPair, FewerThanTwoPointsThrow) {
  EXPECT_THROW(farthest_pair({}), std::invalid_argument);
  EXPECT_THROW(farthest_pair({{1, 2, 3}}), std::invalid_argument);
  EXPECT_EQ(farthest_pair({{1, 2, 3}, {1, 2, 3}}), (std::pair<std::int32_t, std::int32_t>{0, 1}));
}

}  // namespace
}  // namespace spheremap
