#include "spheremap/sphere/certify.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "spheremap/geometry/predicates.hpp"
#include "spheremap/geometry/vec.hpp"

namespace spheremap {
namespace {

constexpr double kPi = std::numbers::pi;

// Faces of a convex mesh around the origin, each turned counter-clockwise seen from outside.
void orient_outward(Mesh& mesh) {
  for (auto& t : mesh.triangles)
    if (orientation_sign(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]) < 0) std::swap(t[1], t[2]);
}

Mesh icosahedron(double radius) {
  const double phi = (1 + std::sqrt(5.0)) / 2;
  Mesh mesh;
  mesh.positions = {{-1, phi, 0},  {1, phi, 0},  {-1, -phi, 0}, {1, -phi, 0}, {0, -1, phi},  {0, 1, phi},
                    {0, -1, -phi}, {0, 1, -phi}, {phi, 0, -1},  {phi, 0, 1},  {-phi, 0, -1}, {-phi, 0, 1}};
  for (auto& p : mesh.positions) p = radius * normalized(p);
  mesh.triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                    {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  orient_outward(mesh);
  return mesh;
}

std::vector<Vec3> projected_to_unit_sphere(const std::vector<Vec3>& points) {
  std::vector<Vec3> sphere;
  for (const auto& p : points) sphere.push_back(normalized(p));
  return sphere;
}

// Tetrahedron: a, b, c around the z axis at height `top_height`, d at the south pole.
Mesh tetrahedron(double top_radius, double top_height) {
  Mesh mesh;
  for (int k = 0; k < 3; ++k) {
    const double angle = 2 * kPi * k / 3;
    mesh.positions.push_back({top_radius * std::cos(angle), top_radius * std::sin(angle), top_height});
  }
  mesh.positions.push_back({0, 0, -1});
  mesh.triangles = {{0, 1, 2}, {0, 3, 1}, {1, 3, 2}, {2, 3, 0}};
  return mesh;
}

TEST(SolidAngle, OctantIsAnEighthOfTheSphereWithSignFromOrientation) {
  const Vec3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  EXPECT_NEAR(signed_solid_angle(x, y, z), kPi / 2, 1e-15);
  EXPECT_NEAR(signed_solid_angle(y, z, x), kPi / 2, 1e-15);
  EXPECT_NEAR(signed_solid_angle(y, x, z), -kPi / 2, 1e-15);
  EXPECT_EQ(signed_solid_angle(x, y, x), 0);
}

TEST(Certificate, ProjectedIcosahedronCertifies) {
  const Mesh surface = icosahedron(3.0);
  const auto sphere = projected_to_unit_sphere(surface.positions);
  const Certificate certificate = certify_sphere_map(surface, sphere);
  EXPECT_TRUE(certificate.certified());
  EXPECT_EQ(certificate.triangle_count, 20);
  EXPECT_EQ(certificate.folded, 0);
  EXPECT_EQ(certificate.collapsed, 0);
  EXPECT_EQ(certificate.decided_exactly, 0);
  EXPECT_TRUE(certificate.folded_triangles.empty());
  EXPECT_TRUE(certificate.collapsed_triangles.empty());
  EXPECT_NEAR(certificate.coverage, 1.0, 1e-12);
  EXPECT_NEAR(certificate.total_solid_angle, 4 * kPi, 1e-11);
  // All faces are congruent, so each keeps exactly its fair share.
  EXPECT_NEAR(certificate.min_area_ratio, 1.0, 1e-12);
  EXPECT_EQ(certificate.collapse_floor, kDefaultCollapseFloor);
}

TEST(Certificate, SwappedVerticesFoldTriangles) {
  const Mesh surface = icosahedron(1.0);
  auto sphere = projected_to_unit_sphere(surface.positions);
  std::swap(sphere[0], sphere[1]);  // neighbours: the two faces on edge 0-1 turn over
  const Certificate certificate = certify_sphere_map(surface, sphere);
  EXPECT_FALSE(certificate.certified());
  EXPECT_GT(certificate.folded, 0);
  EXPECT_EQ(certificate.folded, static_cast<std::int64_t>(certificate.folded_triangles.size()));
  EXPECT_TRUE(std::is_sorted(certificate.folded_triangles.begin(), certificate.folded_triangles.end()));
  for (const auto index : certificate.folded_triangles) {
    const auto& t = surface.triangles[index];
    EXPECT_LE(orientation_sign(sphere[t[0]], sphere[t[1]], sphere[t[2]]), 0);
  }
}

TEST(Certificate, SwappingFarVerticesChangesCoverage) {
  // Vertices 0 and 3 are antipodal: after the swap the faces around them wrap the sphere the other way.
  const Mesh surface = icosahedron(1.0);
  auto sphere = projected_to_unit_sphere(surface.positions);
  std::swap(sphere[0], sphere[3]);
  const Certificate certificate = certify_sphere_map(surface, sphere);
  EXPECT_FALSE(certificate.certified());
  EXPECT_GT(certificate.folded, 0);
  EXPECT_GT(std::fabs(certificate.coverage - 1), 1e-3);
}

TEST(Certificate, MirroredMapCoversTheSphereNegatively) {
  const Mesh surface = icosahedron(1.0);
  auto sphere = projected_to_unit_sphere(surface.positions);
  for (auto& s : sphere) s[0] = -s[0];
  const Certificate certificate = certify_sphere_map(surface, sphere);
  EXPECT_EQ(certificate.folded, 20);
  EXPECT_NEAR(certificate.coverage, -1.0, 1e-12);
  EXPECT_EQ(certificate.min_area_ratio, 0.0) << "no positively oriented triangle";
  EXPECT_FALSE(certificate.certified());
}

TEST(Certificate, TinySphericalTriangleIsCollapsed) {
  // The surface is a fat tetrahedron; on the sphere its top face shrinks to a cap of ~1e-8 sr, a
  // normalized ratio of ~4e-9, while the three side faces share the rest of the sphere.
  const Mesh surface = tetrahedron(1.0, 0.33);
  std::vector<Vec3> sphere;
  for (int k = 0; k < 3; ++k) {
    const double angle = 2 * kPi * k / 3;
    sphere.push_back(normalized({1e-4 * std::cos(angle), 1e-4 * std::sin(angle), 1}));
  }
  sphere.push_back({0, 0, -1});
  const Certificate certificate = certify_sphere_map(surface, sphere);
  EXPECT_EQ(certificate.folded, 0);
  EXPECT_EQ(certificate.collapsed, 1);
  ASSERT_EQ(certificate.collapsed_triangles.size(), 1u);
  EXPECT_EQ(certificate.collapsed_triangles[0], 0);
  EXPECT_NEAR(certificate.coverage, 1.0, 1e-12);
  EXPECT_GT(certificate.min_area_ratio, 0);
  EXPECT_LT(certificate.min_area_ratio, 1e-8);
  EXPECT_FALSE(certificate.certified());

  // A lower floor lets the same map through.
  const Certificate lenient = certify_sphere_map(surface, sphere, 1e-10);
  EXPECT_EQ(lenient.collapsed, 0);
  EXPECT_TRUE(lenient.certified());
}

TEST(Certificate, ZeroAreaSurfaceTriangleIsNeverCollapsed) {
  // Top face flattened to a segment on the surface (three collinear points) but a fair cap on the sphere.
  Mesh surface = tetrahedron(1.0, 0.33);
  surface.positions[2] = 0.5 * (surface.positions[0] + surface.positions[1]);
  const auto sphere = projected_to_unit_sphere(tetrahedron(1.0, 0.33).positions);
  const Certificate certificate = certify_sphere_map(surface, sphere);
  EXPECT_EQ(certificate.folded, 0);
  EXPECT_EQ(certificate.collapsed, 0);
  EXPECT_TRUE(std::isfinite(certificate.min_area_ratio));
  EXPECT_TRUE(certificate.certified());
}

TEST(Certificate, SizeMismatchThrows) {
  const Mesh surface = icosahedron(1.0);
  std::vector<Vec3> sphere = projected_to_unit_sphere(surface.positions);
  sphere.pop_back();
  EXPECT_THROW(certify_sphere_map(surface, sphere), std::invalid_argument);
}

TEST(Certificate, CertifiedNeedsAllThreeConditions) {
  Certificate certificate;
  certificate.coverage = 1;
  EXPECT_TRUE(certificate.certified());
  certificate.coverage = 1 + 1e-8;
  EXPECT_FALSE(certificate.certified());
  certificate.coverage = 1;
  certificate.folded = 1;
  EXPECT_FALSE(certificate.certified());
  certificate.folded = 0;
  certificate.collapsed = 1;
  EXPECT_FALSE(certificate.certified());
}

}  // namespace
}  // namespace spheremap
