#include "spheremap/topology/subdivide.hpp"

#include <gtest/gtest.h>

#include <stdexcept>
#include <vector>

#include "../test_support.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/shapes/shapes.hpp"
#include "spheremap/topology/components.hpp"
#include "spheremap/topology/connectivity.hpp"

namespace spheremap {
namespace {

// A closed, oriented 2-manifold of one component and genus 0, outward (positive volume).
void expect_oriented_sphere(const Mesh& mesh) {
  testing_support::expect_closed_oriented_manifold(mesh);
  const auto components = mesh_components(mesh);
  ASSERT_EQ(components.size(), 1u);
  EXPECT_EQ(components.front().genus, 0);
  EXPECT_GT(components.front().signed_volume, 0);
}

double signed_volume(const Mesh& mesh) { return mesh_components(mesh).front().signed_volume; }

bool same_mesh(const Mesh& x, const Mesh& y) { return x.positions == y.positions && x.triangles == y.triangles; }

TEST(Subdivide, MatchesTheDirectlyBuiltFinerMeshes) {
  const Mesh cube = subdivide_midpoint(make_subdivided_cube(1), 2);
  EXPECT_EQ(cube.vertex_count(), make_subdivided_cube(4).vertex_count());
  expect_oriented_sphere(cube);
  EXPECT_NEAR(signed_volume(cube), 8.0, 1e-12);  // midpoints stay on the flat faces

  const Mesh icosahedron = make_icosphere(0);
  const Mesh subdivided = subdivide_midpoint(icosahedron, 3);
  EXPECT_EQ(subdivided.vertex_count(), make_icosphere(3).vertex_count());
  expect_oriented_sphere(subdivided);
  EXPECT_LT(signed_volume(subdivided), signed_volume(icosahedron) + 1e-12);  // no smoothing, no projection
  EXPECT_NEAR(signed_volume(subdivided), signed_volume(icosahedron), 1e-12);
}

TEST(Subdivide, LevelZeroKeepsGeometryAndAttributesAreDropped) {
  Mesh sphere = make_icosphere(1);
  sphere.integer_attributes["region"] = std::vector<std::int32_t>(sphere.vertex_count(), 2);
  const Mesh same = subdivide_midpoint(sphere, 0);
  EXPECT_TRUE(same_mesh(same, sphere));
  EXPECT_TRUE(same.integer_attributes.empty());
  EXPECT_TRUE(subdivide_midpoint(sphere, 1).integer_attributes.empty());
}

TEST(Subdivide, RejectsInvalidArguments) {
  EXPECT_THROW(subdivide_midpoint(make_icosphere(0), -1), std::invalid_argument);
  Mesh broken = make_icosphere(0);
  broken.triangles[3][2] = -1;
  EXPECT_THROW(subdivide_midpoint(broken, 1), std::invalid_argument);
}

TEST(Subdivide, MidpointsAreNumberedByEdgeAndProjectedOnRequest) {
  const Mesh icosahedron = make_icosphere(0);
  const auto edges = number_edges(icosahedron.positions.size(), icosahedron.triangles);
  std::vector<Vec3> positions = icosahedron.positions;
  std::vector<Triangle> triangles = icosahedron.triangles;
  subdivide_midpoint_in_place(positions, triangles, true);
  ASSERT_EQ(positions.size(), icosahedron.positions.size() + edges.edge_endpoints.size());
  EXPECT_EQ(triangles.size(), 4 * icosahedron.triangles.size());
  for (std::size_t e = 0; e < edges.edge_endpoints.size(); ++e) {
    const auto [a, b] = edges.edge_endpoints[e];
    EXPECT_EQ(positions[icosahedron.positions.size() + e], normalized(0.5 * (positions[a] + positions[b])));
  }
  const Mesh icosphere = make_icosphere(1);  // the same split, as the generated shape does it
  EXPECT_EQ(positions, icosphere.positions);
  EXPECT_EQ(triangles, icosphere.triangles);
}

}  // namespace
}  // namespace spheremap
