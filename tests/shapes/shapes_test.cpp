#include "spheremap/shapes/shapes.hpp"

#include <gtest/gtest.h>

#include "../test_support.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <map>
#include <numeric>
#include <set>
#include <stdexcept>
#include <utility>
#include <vector>

#include "spheremap/geometry/vec.hpp"

namespace spheremap {
namespace {

// Self-contained checks (no dependency on the topology stage, which is tested on its own).

using testing_support::signed_volume;

std::vector<int> vertex_degrees(const Mesh& mesh) {
  std::vector<int> degree(mesh.vertex_count(), 0);
  for (const auto& triangle : mesh.triangles)
    for (const auto v : triangle) ++degree[v];
  return degree;
}

std::int64_t edge_key(std::int32_t a, std::int32_t b) {
  return (static_cast<std::int64_t>(a) << 32) | static_cast<std::uint32_t>(b);
}

/// Closed, consistently oriented, vertex-manifold, connected, Euler characteristic 2 (so a sphere),
/// outward (positive volume), no degenerate index triples, no duplicate vertex positions.
void expect_oriented_sphere(const Mesh& mesh) {
  const auto vertex_count = static_cast<std::int32_t>(mesh.vertex_count());
  ASSERT_GT(mesh.triangle_count(), 0u);

  // Directed edges: each appears once, and its reverse appears once (opposite directions).
  std::vector<std::int64_t> directed;
  directed.reserve(3 * mesh.triangle_count());
  for (const auto& t : mesh.triangles) {
    for (int k = 0; k < 3; ++k) {
      ASSERT_GE(t[k], 0);
      ASSERT_LT(t[k], vertex_count);
      ASSERT_NE(t[k], t[(k + 1) % 3]) << "degenerate triangle";
      directed.push_back(edge_key(t[k], t[(k + 1) % 3]));
    }
  }
  std::sort(directed.begin(), directed.end());
  ASSERT_EQ(std::adjacent_find(directed.begin(), directed.end()), directed.end())
      << "edge used twice in the same direction";
  for (const auto key : directed) {
    const auto a = static_cast<std::int32_t>(key >> 32), b = static_cast<std::int32_t>(key & 0xffffffff);
    ASSERT_TRUE(std::binary_search(directed.begin(), directed.end(), edge_key(b, a)))
        << "edge " << a << "-" << b << " has no opposite";
  }

  // Each vertex's triangles form one closed fan: following "after b comes c" from any start visits all.
  std::vector<std::vector<std::pair<std::int32_t, std::int32_t>>> fan(mesh.vertex_count());
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) fan[t[k]].emplace_back(t[(k + 1) % 3], t[(k + 2) % 3]);
  for (std::int32_t v = 0; v < vertex_count; ++v) {
    ASSERT_GE(fan[v].size(), 3u) << "vertex " << v;
    std::map<std::int32_t, std::int32_t> successor(fan[v].begin(), fan[v].end());
    std::size_t steps = 0;
    std::int32_t current = fan[v][0].first;
    do {
      current = successor.at(current);
      ++steps;
    } while (current != fan[v][0].first && steps <= fan[v].size());
    ASSERT_EQ(steps, fan[v].size()) << "vertex " << v << " has several fans";
  }

  // Connected (union-find), so Euler characteristic 2 means genus 0.
  std::vector<std::int32_t> parent(mesh.vertex_count());
  std::iota(parent.begin(), parent.end(), 0);
  const auto root = [&](std::int32_t v) {
    while (parent[v] != v) v = parent[v] = parent[parent[v]];
    return v;
  };
  for (const auto& t : mesh.triangles) {
    parent[root(t[0])] = root(t[1]);
    parent[root(t[1])] = root(t[2]);
  }
  for (std::int32_t v = 0; v < vertex_count; ++v) ASSERT_EQ(root(v), root(0)) << "disconnected";

  const auto edges = static_cast<std::int64_t>(directed.size() / 2);
  EXPECT_EQ(static_cast<std::int64_t>(mesh.vertex_count()) - edges + static_cast<std::int64_t>(mesh.triangle_count()),
            2);
  EXPECT_GT(signed_volume(mesh), 0);

  std::vector<Vec3> sorted_positions = mesh.positions;
  std::sort(sorted_positions.begin(), sorted_positions.end());
  EXPECT_EQ(std::adjacent_find(sorted_positions.begin(), sorted_positions.end()), sorted_positions.end())
      << "duplicate vertex";
}

/// For a convex mesh around the origin every face normal points away from the origin.
void expect_faces_point_away_from_origin(const Mesh& mesh) {
  for (const auto& [a, b, c] : mesh.triangles) {
    const auto& p = mesh.positions;
    const Vec3 face_normal = cross(p[b] - p[a], p[c] - p[a]);
    const Vec3 centroid = (1.0 / 3) * (p[a] + p[b] + p[c]);
    ASSERT_GT(dot(face_normal, centroid), 0);
  }
}

bool same_mesh(const Mesh& x, const Mesh& y) { return x.positions == y.positions && x.triangles == y.triangles; }

TEST(ShapesIcosphere, IsAnOrientedUnitSphereWithExpectedCounts) {
  for (int levels = 0; levels <= 4; ++levels) {
    SCOPED_TRACE(levels);
    const Mesh mesh = make_icosphere(levels);
    const std::size_t expected_vertices = 10 * (std::size_t{1} << (2 * levels)) + 2;
    EXPECT_EQ(mesh.vertex_count(), expected_vertices);
    EXPECT_EQ(mesh.triangle_count(), 2 * expected_vertices - 4);
    expect_oriented_sphere(mesh);
    expect_faces_point_away_from_origin(mesh);
    for (const auto& p : mesh.positions) EXPECT_NEAR(norm(p), 1.0, 1e-12);
  }
}

TEST(ShapesIcosphere, LevelEightHasExpectedCountsAndIsDeterministic) {
  const Mesh mesh = make_icosphere(8);
  EXPECT_EQ(mesh.vertex_count(), 655362u);
  EXPECT_EQ(mesh.triangle_count(), 1310720u);
  EXPECT_TRUE(same_mesh(mesh, make_icosphere(8)));
}

TEST(ShapesIcosphere, RejectsLevelsOutsideZeroToTen) {
  EXPECT_THROW(make_icosphere(-1), std::invalid_argument);
  EXPECT_THROW(make_icosphere(11), std::invalid_argument);
}

TEST(ShapesEllipsoid, IsTheScaledIcosphere) {
  const Mesh mesh = make_ellipsoid(3, 1, 2, 20);
  expect_oriented_sphere(mesh);
  expect_faces_point_away_from_origin(mesh);
  const Mesh sphere = make_icosphere(3);
  ASSERT_EQ(mesh.triangles, sphere.triangles);
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    EXPECT_DOUBLE_EQ(mesh.positions[v][0], sphere.positions[v][0]);
    EXPECT_DOUBLE_EQ(mesh.positions[v][1], 2 * sphere.positions[v][1]);
    EXPECT_DOUBLE_EQ(mesh.positions[v][2], 20 * sphere.positions[v][2]);
  }
}

TEST(ShapesEllipsoid, RejectsNonPositiveOrNonFiniteAxes) {
  EXPECT_THROW(make_ellipsoid(2, 0, 1, 1), std::invalid_argument);
  EXPECT_THROW(make_ellipsoid(2, 1, -1, 1), std::invalid_argument);
  EXPECT_THROW(make_ellipsoid(2, 1, 1, std::nan("")), std::invalid_argument);
  EXPECT_THROW(make_ellipsoid(-1, 1, 1, 1), std::invalid_argument);
}

/// A surface of revolution about x is embedded when its rings have increasing x and positive radius;
/// each face normal must then point away from the axis.
void expect_faces_point_away_from_x_axis(const Mesh& mesh) {
  for (const auto& [a, b, c] : mesh.triangles) {
    const auto& p = mesh.positions;
    const Vec3 face_normal = cross(p[b] - p[a], p[c] - p[a]);
    const Vec3 centroid = (1.0 / 3) * (p[a] + p[b] + p[c]);
    ASSERT_GT(dot(face_normal, Vec3{0, centroid[1], centroid[2]}), 0);
  }
}

TEST(ShapesDumbbell, ThinNeckIsAValidOrientedSphere) {
  const Mesh mesh = make_dumbbell(4, 0.05, 200, 32);
  EXPECT_EQ(mesh.vertex_count(), 200u * 32 + 2);
  expect_oriented_sphere(mesh);
  expect_faces_point_away_from_x_axis(mesh);
  double smallest_ring_radius = 1e9;
  for (const auto& p : mesh.positions) {
    EXPECT_LE(std::abs(p[0]), 3.0);
    if (std::abs(p[0]) < 3.0) smallest_ring_radius = std::min(smallest_ring_radius, std::hypot(p[1], p[2]));
  }
  EXPECT_NEAR(smallest_ring_radius, 0.05, 1e-12);  // the neck is there
}

TEST(ShapesDumbbell, OverlappingSpheresAndCoarseSampling) {
  expect_oriented_sphere(make_dumbbell(1, 0.5, 20, 8));
  expect_oriented_sphere(make_dumbbell(0, 0.5, 1, 3));  // a triangular bipyramid
}

TEST(ShapesDumbbell, RejectsInvalidArguments) {
  EXPECT_THROW(make_dumbbell(-1, 0.5, 10, 8), std::invalid_argument);
  EXPECT_THROW(make_dumbbell(4, 0, 10, 8), std::invalid_argument);
  EXPECT_THROW(make_dumbbell(4, 1, 10, 8), std::invalid_argument);
  EXPECT_THROW(make_dumbbell(4, 0.5, 0, 8), std::invalid_argument);
  EXPECT_THROW(make_dumbbell(4, 0.5, 10, 2), std::invalid_argument);
}

TEST(ShapesPerturb, MovesWithinBoundKeepsTopologyAndIsDeterministic) {
  Mesh sphere = make_icosphere(3);
  sphere.real_attributes["label"] = std::vector<double>(sphere.vertex_count(), 1.0);
  const double amplitude = 0.2;
  const Mesh moved = perturb_vertices(sphere, amplitude, 7);
  EXPECT_EQ(moved.triangles, sphere.triangles);
  EXPECT_EQ(moved.real_attributes, sphere.real_attributes);
  expect_oriented_sphere(moved);
  // Icosphere level 3 edges are shorter than 0.2, so no vertex may move further than 0.2 * 0.2.
  bool any_moved = false;
  for (std::size_t v = 0; v < sphere.vertex_count(); ++v) {
    const double distance = norm(moved.positions[v] - sphere.positions[v]);
    EXPECT_LE(distance, amplitude * 0.2);
    any_moved = any_moved || distance > 0;
  }
  EXPECT_TRUE(any_moved);
  EXPECT_TRUE(same_mesh(moved, perturb_vertices(sphere, amplitude, 7)));
  EXPECT_FALSE(same_mesh(moved, perturb_vertices(sphere, amplitude, 8)));
  EXPECT_TRUE(same_mesh(sphere, perturb_vertices(sphere, 0, 7)));
}

TEST(ShapesPerturb, RejectsInvalidArguments) {
  EXPECT_THROW(perturb_vertices(make_icosphere(1), -0.1, 1), std::invalid_argument);
  EXPECT_THROW(perturb_vertices(make_icosphere(1), INFINITY, 1), std::invalid_argument);
  Mesh broken = make_icosphere(0);
  broken.triangles[0][0] = 99;
  EXPECT_THROW(perturb_vertices(broken, 0.1, 1), std::invalid_argument);
}

TEST(ShapesEdgeFlips, KeepsAValidSphereAndCreatesDegreeThreeVertices) {
  const Mesh sphere = make_icosphere(2);
  // Seed 1 with probability 0.3 yields degree-3 vertices (checked below); the icosphere has none.
  const Mesh flipped = random_edge_flips(sphere, 0.3, 1);
  EXPECT_EQ(flipped.positions, sphere.positions);
  EXPECT_NE(flipped.triangles, sphere.triangles);
  expect_oriented_sphere(flipped);
  // Not "faces point away from the origin": a flip can make a face's plane pass through the centre.
  for (const auto& [a, b, c] : flipped.triangles)
    EXPECT_GT(triangle_area(flipped.positions[a], flipped.positions[b], flipped.positions[c]), 1e-6);
  const auto original_degrees = vertex_degrees(sphere);
  EXPECT_EQ(*std::min_element(original_degrees.begin(), original_degrees.end()), 5);
  const auto degrees = vertex_degrees(flipped);
  EXPECT_EQ(*std::min_element(degrees.begin(), degrees.end()), 3);
}

TEST(ShapesEdgeFlips, IsDeterministicAndSeedDependent) {
  const Mesh sphere = make_icosphere(3);
  const Mesh flipped = random_edge_flips(sphere, 0.5, 42);
  EXPECT_TRUE(same_mesh(flipped, random_edge_flips(sphere, 0.5, 42)));
  EXPECT_FALSE(same_mesh(flipped, random_edge_flips(sphere, 0.5, 43)));
  EXPECT_TRUE(same_mesh(sphere, random_edge_flips(sphere, 0, 42)));
}

TEST(ShapesEdgeFlips, AllEdgesTriedStillValidOnCubeAndDumbbell) {
  // Probability 1 exercises every rejection rule; flat cube faces make many flips legal.
  for (const Mesh& input :
       {make_subdivided_cube(4), make_dumbbell(4, 0.05, 40, 16), perturb_vertices(make_icosphere(3), 0.3, 5)}) {
    const Mesh flipped = random_edge_flips(input, 1.0, 3);
    expect_oriented_sphere(flipped);
    const auto degrees = vertex_degrees(flipped);
    EXPECT_GE(*std::min_element(degrees.begin(), degrees.end()), 3);
  }
}

TEST(ShapesEdgeFlips, RejectsInvalidArguments) {
  const Mesh sphere = make_icosphere(1);
  EXPECT_THROW(random_edge_flips(sphere, -0.1, 1), std::invalid_argument);
  EXPECT_THROW(random_edge_flips(sphere, 1.5, 1), std::invalid_argument);
  Mesh open = sphere;
  open.triangles.pop_back();
  EXPECT_THROW(random_edge_flips(open, 0.5, 1), std::invalid_argument);
  Mesh misoriented = sphere;
  std::swap(misoriented.triangles[0][1], misoriented.triangles[0][2]);
  EXPECT_THROW(random_edge_flips(misoriented, 0.5, 1), std::invalid_argument);
}

TEST(ShapesCube, IsAnOrientedSphereOnTheCubeSurface) {
  for (int n : {1, 2, 5}) {
    SCOPED_TRACE(n);
    const Mesh cube = make_subdivided_cube(n);
    EXPECT_EQ(cube.vertex_count(), static_cast<std::size_t>(6 * n * n + 2));
    EXPECT_EQ(cube.triangle_count(), static_cast<std::size_t>(12 * n * n));
    expect_oriented_sphere(cube);
    expect_faces_point_away_from_origin(cube);
    EXPECT_NEAR(signed_volume(cube), 8.0, 1e-12);
    for (const auto& p : cube.positions)
      EXPECT_DOUBLE_EQ(std::max({std::abs(p[0]), std::abs(p[1]), std::abs(p[2])}), 1.0);
  }
}

TEST(ShapesCube, RejectsInvalidN) {
  EXPECT_THROW(make_subdivided_cube(0), std::invalid_argument);
  EXPECT_THROW(make_subdivided_cube(-3), std::invalid_argument);
}

}  // namespace
}  // namespace spheremap
