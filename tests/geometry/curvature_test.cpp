// Principal curvatures and Koenderink's shape descriptors on surfaces with known answers: a sphere, a
// cylinder and a saddle.
#include "spheremap/geometry/curvature.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>

#include "spheremap/properties/shape.hpp"
#include "spheremap/shapes/shapes.hpp"

namespace spheremap {
namespace {

// A grid of (rows + 1) x (columns + 1) vertices, p(i, j), two counter-clockwise triangles per cell (seen from
// where `p` puts the outside).
template <typename Point>
Mesh grid_mesh(int rows, int columns, Point p) {
  Mesh mesh;
  for (int i = 0; i <= rows; ++i)
    for (int j = 0; j <= columns; ++j) mesh.positions.push_back(p(i, j));
  const auto at = [&](int i, int j) { return static_cast<std::int32_t>(i * (columns + 1) + j); };
  for (int i = 0; i < rows; ++i)
    for (int j = 0; j < columns; ++j) {
      mesh.triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
      mesh.triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
    }
  return mesh;
}

TEST(ShapeIndex, KnownValues) {
  EXPECT_DOUBLE_EQ(shape_index(1, 1), 1);      // convex cap
  EXPECT_DOUBLE_EQ(shape_index(-1, -1), -1);   // cup
  EXPECT_DOUBLE_EQ(shape_index(1, 0), 0.5);    // ridge
  EXPECT_DOUBLE_EQ(shape_index(0, -1), -0.5);  // rut
  EXPECT_DOUBLE_EQ(shape_index(1, -1), 0);     // symmetric saddle
  EXPECT_DOUBLE_EQ(shape_index(0, 1), 0.5);    // order does not matter
  EXPECT_TRUE(std::isnan(shape_index(0, 0)));  // a plane has no shape
  EXPECT_DOUBLE_EQ(curvedness(3, 4), std::sqrt(12.5));
}

TEST(Curvature, SphereOfRadiusTwo) {
  Mesh sphere = make_icosphere(4);
  for (auto& p : sphere.positions) p = {2 * p[0], 2 * p[1], 2 * p[2]};
  const PrincipalCurvatures k = principal_curvatures(sphere.positions, sphere.triangles);
  for (std::size_t v = 0; v < sphere.vertex_count(); ++v) {
    EXPECT_NEAR(k.k1[v], 0.5, 0.02) << v;
    EXPECT_NEAR(k.k2[v], 0.5, 0.02) << v;
    EXPECT_GT(shape_index(k.k1[v], k.k2[v]), 0.95) << v;
  }
}

TEST(Curvature, CylinderOfRadiusThreeIsARidge) {
  constexpr int kAround = 64, kAlong = 40;
  const double radius = 3;
  // Outward normals: counter-clockwise seen from outside.
  const Mesh tube = grid_mesh(kAlong, kAround, [&](int i, int j) {
    const double angle = 2 * std::numbers::pi * j / kAround;
    return Vec3{radius * std::cos(angle), radius * std::sin(angle), 0.25 * i};
  });
  const PrincipalCurvatures k = principal_curvatures(tube.positions, tube.triangles);
  int checked = 0;
  for (int i = 5; i <= kAlong - 5; ++i)
    for (int j = 2; j < kAround - 2; ++j) {  // away from the open ends and the seam (not welded)
      const auto v = static_cast<std::size_t>(i * (kAround + 1) + j);
      EXPECT_NEAR(k.k1[v], 1 / radius, 0.02) << v;
      EXPECT_NEAR(k.k2[v], 0, 0.02) << v;
      EXPECT_NEAR(shape_index(k.k1[v], k.k2[v]), 0.5, 0.05) << v;
      ++checked;
    }
  EXPECT_GT(checked, 1000);
}

TEST(Curvature, SaddleAtItsCentre) {
  // z = (x² - y²) / 2 with the normal up: principal curvatures +1 and -1 at the origin, shape index 0.
  constexpr int kCells = 40;
  const double step = 0.02;
  const Mesh saddle = grid_mesh(kCells, kCells, [&](int i, int j) {
    const double x = (j - kCells / 2) * step, y = (i - kCells / 2) * step;
    return Vec3{x, y, (x * x - y * y) / 2};
  });
  const PrincipalCurvatures k = principal_curvatures(saddle.positions, saddle.triangles);
  const auto centre = static_cast<std::size_t>((kCells / 2) * (kCells + 1) + kCells / 2);
  EXPECT_NEAR(k.k1[centre], 1, 0.05);
  EXPECT_NEAR(k.k2[centre], -1, 0.05);
  EXPECT_NEAR(shape_index(k.k1[centre], k.k2[centre]), 0, 0.03);
}

TEST(Curvature, IsolatedVertexHasNoValue) {
  Mesh sphere = make_icosphere(2);
  sphere.positions.push_back({5, 5, 5});
  const PrincipalCurvatures k = principal_curvatures(sphere.positions, sphere.triangles);
  EXPECT_TRUE(std::isnan(k.k1.back()));
  EXPECT_TRUE(std::isnan(k.k2.back()));
}

TEST(MapShape, LogAreaRatioAndOctants) {
  const Mesh sphere = make_icosphere(3);
  // The unit sphere mapped to itself keeps every area share (but for the flat triangles' areas against their
  // spherical ones): ln 1 = 0 everywhere, nearly.
  for (const double r : vertex_log_area_ratios(sphere, sphere.positions)) EXPECT_NEAR(r, 0, 2e-3);
  EXPECT_EQ(octant_of({1, 1, 1}), 0);
  EXPECT_EQ(octant_of({-1, 1, 1}), 1);
  EXPECT_EQ(octant_of({1, -1, -1}), 6);
  EXPECT_EQ(octant_of({0, 0, 0}), 0);
  EXPECT_EQ(octant_names()[7], "-x-y-z");
  EXPECT_THROW(vertex_log_area_ratios(sphere, {}), std::invalid_argument);
}

}  // namespace
}  // namespace spheremap
