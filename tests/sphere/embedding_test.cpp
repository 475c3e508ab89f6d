// Valid starts built without the harmonic map: the convex (Tutte, Maxwell–Cremona, central projection)
// embedding of small meshes, and the progressive embedding of hard ones.
#include "spheremap/sphere/embedding.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>
#include <stdexcept>

#include "spheremap/geometry/predicates.hpp"
#include "spheremap/shapes/hard_cases.hpp"
#include "spheremap/shapes/shapes.hpp"
#include "spheremap/sphere/certify.hpp"
#include "spheremap/topology/connectivity.hpp"

namespace spheremap {
namespace {

// A bipyramid: `k` equator vertices, apexes k (top) and k + 1 (bottom), outward.
Mesh bipyramid(int k) {
  Mesh mesh;
  for (int i = 0; i < k; ++i) mesh.positions.push_back({std::cos(2 * M_PI * i / k), std::sin(2 * M_PI * i / k), 0});
  mesh.positions.push_back({0, 0, 1});
  mesh.positions.push_back({0, 0, -1});
  for (int i = 0; i < k; ++i) {
    mesh.triangles.push_back({k, i, (i + 1) % k});
    mesh.triangles.push_back({k + 1, (i + 1) % k, i});
  }
  return mesh;
}

std::int64_t folded(const Mesh& mesh, const std::vector<Vec3>& sphere) {
  std::int64_t count = 0;
  for (const auto& t : mesh.triangles) count += orientation_sign(sphere[t[0]], sphere[t[1]], sphere[t[2]]) <= 0;
  return count;
}

TEST(ConvexEmbedding, SmallMeshesAnyNonAdjacentPoles) {
  for (const Mesh& mesh : {bipyramid(3), bipyramid(7), make_icosphere(1), make_icosphere(2)}) {
    const auto n = static_cast<std::int32_t>(mesh.vertex_count());
    const auto rings = build_vertex_rings(n, mesh.triangles);
    std::mt19937 generator(5);
    for (int pair = 0; pair < 6; ++pair) {
      const auto north = static_cast<std::int32_t>(generator() % n);
      const auto distance = graph_distances(rings, north);
      std::vector<std::int32_t> candidates;
      for (std::int32_t v = 0; v < n; ++v)
        if (distance[v] >= 2) candidates.push_back(v);
      if (candidates.empty()) continue;  // an equator vertex of the triangular bipyramid
      const auto south = candidates[generator() % candidates.size()];
      const auto sphere = convex_embedding(n, mesh.triangles, north, south);
      EXPECT_EQ(folded(mesh, sphere), 0) << n << " vertices, poles " << north << "," << south;
      EXPECT_EQ(sphere[north], (Vec3{0, 0, 1}));
      EXPECT_EQ(sphere[south], (Vec3{0, 0, -1}));
      EXPECT_NEAR(certify_sphere_map(mesh, sphere).coverage, 1, 1e-12);
    }
  }
}

TEST(ConvexEmbedding, RefusesAdjacentOrEqualPoles) {
  const Mesh mesh = bipyramid(4);
  EXPECT_THROW(convex_embedding(6, mesh.triangles, 4, 0), std::invalid_argument);
  EXPECT_THROW(convex_embedding(6, mesh.triangles, 4, 4), std::invalid_argument);
  EXPECT_THROW(convex_embedding(6, mesh.triangles, 4, 6), std::invalid_argument);
}

TEST(ConvexEmbedding, TuttesTinyTrianglesAreWhyItIsOnlyTheBase) {
  // A long coarse tube: Tutte's embedding shrinks each ring by a constant factor, so the far end is
  // below what doubles can hold on the sphere.
  const Mesh tube = make_bent_tube(TubeBend::kU, 4, 80);
  const auto sphere = convex_embedding(static_cast<std::int32_t>(tube.vertex_count()), tube.triangles,
                                       static_cast<std::int32_t>(tube.vertex_count()) - 2,
                                       static_cast<std::int32_t>(tube.vertex_count()) - 1);
  EXPECT_FALSE(certify_sphere_map(tube, sphere).certified());
}

TEST(ProgressiveEmbedding, HardMeshesBecomeValidMaps) {
  const std::vector<Mesh> meshes{make_bent_tube(TubeBend::kU, 4, 80), make_bent_tube(TubeBend::kC, 3, 40),
                                 make_stacked_triangulation(300, 0.9, 1), make_spiky_sphere(1, 6, 5, 10, 1),
                                 bipyramid(3)};
  for (const auto& mesh : meshes) {
    const auto n = static_cast<std::int32_t>(mesh.vertex_count());
    const std::int32_t north = n - 2;  // an apex of the bipyramid, an end of the tubes
    const auto distance = graph_distances(build_vertex_rings(n, mesh.triangles), north);
    const auto south = static_cast<std::int32_t>(std::max_element(distance.begin(), distance.end()) - distance.begin());
    ASSERT_GE(distance[south], 2);
    std::vector<Vec3> sphere;
    const auto report = progressive_embedding(mesh, north, south, sphere);
    EXPECT_TRUE(report.valid) << n << " vertices";
    EXPECT_EQ(report.failed_insertions, 0);
    EXPECT_EQ(report.insertions, n - report.base_vertices);
    EXPECT_GE(report.base_vertices, 5);
    EXPECT_EQ(sphere[north], (Vec3{0, 0, 1}));
    EXPECT_EQ(sphere[south], (Vec3{0, 0, -1}));
    EXPECT_TRUE(certify_sphere_map(mesh, sphere).certified()) << n << " vertices";
    EXPECT_LT(report.energy_after, report.energy_before + 1e-12);
  }
}

TEST(ProgressiveEmbedding, RefusesBadPoles) {
  const Mesh mesh = bipyramid(4);
  std::vector<Vec3> sphere;
  EXPECT_THROW(progressive_embedding(mesh, 4, 0, sphere), std::invalid_argument);
  EXPECT_THROW(progressive_embedding(mesh, 4, 4, sphere), std::invalid_argument);
  EXPECT_THROW(progressive_embedding(mesh, -1, 5, sphere), std::invalid_argument);
}

}  // namespace
}  // namespace spheremap
