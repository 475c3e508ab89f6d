#include "spheremap/surface/contour.hpp"

#include <gtest/gtest.h>

#include "../test_support.hpp"

#include <cmath>
#include <map>
#include <numbers>
#include <random>

#include "spheremap/geometry/vec.hpp"
#include "spheremap/sphere/map.hpp"
#include "spheremap/topology/prepare.hpp"

namespace spheremap {
namespace {

using testing_support::sample;

using testing_support::expect_closed_oriented_manifold;

TEST(Contour, SphereIsAClosedOutwardGenusZeroSurfaceWithTheRightArea) {
  const double radius = 5;
  const auto grid = sample(33, 0.4, {-6.4, -6.4, -6.4}, [&](const Vec3& p) { return radius - norm(p); });
  const Mesh mesh = contour_isosurface(grid, 0);
  expect_closed_oriented_manifold(mesh);
  const auto prepared = prepare_mesh(mesh);
  EXPECT_EQ(prepared.report.genus, 0);
  EXPECT_EQ(prepared.report.triangles_flipped, 0) << "triangles must face outward";
  double area = 0;
  for (const auto& t : mesh.triangles)
    area += triangle_area(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
  EXPECT_NEAR(area / (4 * std::numbers::pi * radius * radius), 1.0, 0.02);
  for (const auto& p : mesh.positions) EXPECT_NEAR(norm(p), radius, 0.05);
  // Straight into the mapper.
  const auto map = map_to_sphere(prepared.mesh);
  EXPECT_TRUE(map.certificate.certified())
      << map.certificate.folded << " folded, " << map.certificate.collapsed << " collapsed";
}

TEST(Contour, TorusHasGenusOne) {
  const auto grid = sample(40, 0.25, {-5, -5, -5}, [](const Vec3& p) {
    const double ring = std::sqrt(p[0] * p[0] + p[1] * p[1]) - 3;
    return 1.0 - std::sqrt(ring * ring + p[2] * p[2]);
  });
  const Mesh mesh = contour_isosurface(grid, 0);
  expect_closed_oriented_manifold(mesh);
  // V - E + F = 0 for a torus.
  const auto edges = static_cast<std::int64_t>(mesh.triangles.size()) * 3 / 2;
  EXPECT_EQ(static_cast<std::int64_t>(mesh.vertex_count()) - edges + static_cast<std::int64_t>(mesh.triangle_count()),
            0);
}

TEST(Contour, RandomFieldsAlwaysGiveClosedManifolds) {
  std::mt19937 random(11);
  for (int trial = 0; trial < 20; ++trial) {
    Grid3<double> grid;
    grid.size = {9, 8, 10};
    grid.values.resize(static_cast<std::size_t>(grid.count()));
    for (std::int64_t k = 0; k < grid.size[2]; ++k)
      for (std::int64_t j = 0; j < grid.size[1]; ++j)
        for (std::int64_t i = 0; i < grid.size[0]; ++i) {
          const bool border =
              i == 0 || j == 0 || k == 0 || i == grid.size[0] - 1 || j == grid.size[1] - 1 || k == grid.size[2] - 1;
          // Many exact ties with the level too (value 0 counts as outside).
          grid.values[grid.index(i, j, k)] = border ? -1.0 : static_cast<double>(static_cast<int>(random() % 5) - 2);
        }
    const Mesh mesh = contour_isosurface(grid, 0);
    expect_closed_oriented_manifold(mesh);
  }
}

TEST(Contour, TheMinimumFractionKeepsVerticesOffSamplesAndZeroInterpolatesPlainly) {
  // A slab -1.5 < x < 0.03: its face x = 0.03 passes 3% of a step from the samples at x = 0.
  const auto grid = sample(6, 1, {-2, -2, -2}, [](const Vec3& p) {
    return std::max(std::abs(p[1]), std::abs(p[2])) > 1.5 ? -1.0 : std::min(0.03 - p[0], p[0] + 1.5);
  });
  for (const double fraction : {kContourMinimumFraction, 0.0, 0.02}) {
    const Mesh mesh = contour_isosurface(grid, 0, 0, fraction);
    expect_closed_oriented_manifold(mesh);
    for (const auto& p : mesh.positions)
      if (std::abs(p[1]) < 1 && std::abs(p[2]) < 1 && std::abs(p[0]) < 1 && p[0] > -0.5)  // on the plane
        EXPECT_NEAR(p[0], std::max(0.03, fraction), 1e-12) << fraction;
  }
  EXPECT_THROW(contour_isosurface(grid, 0, 0, -0.1), std::invalid_argument);
  EXPECT_THROW(contour_isosurface(grid, 0, 0, 0.51), std::invalid_argument);
  // 0.5: every vertex at the midpoint of its lattice edge (the binary field contoured at 1/2).
  const Mesh midpoints = contour_isosurface(grid, 0, 0, 0.5);
  expect_closed_oriented_manifold(midpoints);
  for (const auto& p : midpoints.positions) {
    int halves = 0;
    for (const double x : p)
      halves += std::abs(x * 2 - std::round(x * 2)) < 1e-12 && std::abs(x - std::round(x)) > 0.25;
    EXPECT_GE(halves, 1) << p[0] << " " << p[1] << " " << p[2];
  }
}

TEST(Contour, RefusesASurfaceThatReachesTheBorder) {
  const auto grid = sample(5, 1, {0, 0, 0}, [](const Vec3&) { return 1.0; });
  EXPECT_THROW(contour_isosurface(grid, 0), std::invalid_argument);
}

}  // namespace
}  // namespace spheremap
