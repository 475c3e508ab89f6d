// Untangling on the sphere (src/sphere/untangle.hpp): the frame a map builds once and shares between
// its untangling calls.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <numeric>
#include <stdexcept>
#include <vector>

#include "../../src/sphere/untangle.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/shapes/shapes.hpp"
#include "spheremap/sphere/certify.hpp"
#include "spheremap/topology/connectivity.hpp"

namespace spheremap {
namespace {

// An icosphere with some degree-3 vertices (random flips), its own points as a certified sphere map;
// 81,920 triangles, so that the frame and the first scan of the untangling run in several chunks.
Mesh flipped_icosphere() { return random_edge_flips(make_icosphere(6), 0.2, 7); }

// The icosphere's points with vertex v moved across the great circle through two of its neighbours:
// some of its triangles fold.
std::vector<Vec3> folded_at(const Mesh& mesh, const VertexRings& rings, std::int32_t v) {
  std::vector<Vec3> sphere = mesh.positions;
  for (auto& p : sphere) p = normalized(p);
  const auto ring = rings.ring(v);
  const Vec3 normal = normalized(cross(sphere[ring[0]], sphere[ring[1]]));
  const Vec3& p = sphere[v];
  sphere[v] = normalized(p - 2.5 * dot(p, normal) * normal);
  return sphere;
}

TEST(Untangling, FrameNamesTheTriangleOfEachRingSlot) {
  const Mesh mesh = flipped_icosphere();
  const auto n = static_cast<std::int32_t>(mesh.positions.size());
  const VertexRings rings = build_vertex_rings(n, mesh.triangles);
  const detail::UntanglingFrame frame = detail::untangling_frame(mesh, rings);
  ASSERT_EQ(frame.star_triangle.size(), rings.neighbors.size());
  ASSERT_EQ(frame.target.size(), mesh.triangles.size());
  for (std::int32_t v = 0; v < n; ++v) {
    const auto ring = rings.ring(v);
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const auto t = frame.star_triangle[static_cast<std::size_t>(rings.offsets[v]) + k];
      ASSERT_GE(t, 0) << "vertex " << v << " slot " << k;
      // (v, ring[k], ring[k+1]) in the triangle's own cyclic order.
      const Triangle& tri = mesh.triangles[static_cast<std::size_t>(t)];
      const auto at = static_cast<int>(std::find(tri.begin(), tri.end(), v) - tri.begin());
      ASSERT_LT(at, 3);
      EXPECT_EQ(tri[(at + 1) % 3], ring[k]);
      EXPECT_EQ(tri[(at + 2) % 3], ring[(k + 1) % ring.size()]);
    }
  }
  // The targets share the sphere in proportion to the triangles' areas.
  const double total = std::accumulate(frame.target.begin(), frame.target.end(), 0.0);
  EXPECT_NEAR(total, 4 * std::numbers::pi, 1e-12);
}

TEST(Untangling, OneFrameServesSeveralMapsAsAFreshOneWould) {
  const Mesh mesh = flipped_icosphere();
  const auto n = static_cast<std::int32_t>(mesh.positions.size());
  const VertexRings rings = build_vertex_rings(n, mesh.triangles);
  const detail::UntanglingFrame shared = detail::untangling_frame(mesh, rings);
  // Folds in the first, the last and a middle chunk of the untangling's 16,384 triangles.
  for (const std::int32_t v : {mesh.triangles[16383][0], mesh.triangles[81919][1], 20000}) {
    std::vector<Vec3> with_shared = folded_at(mesh, rings, v);
    const Certificate before = certify_sphere_map(mesh, with_shared);
    ASSERT_GT(before.folded, 0) << "vertex " << v << ": the test's fold folded nothing";
    std::vector<Vec3> with_fresh = with_shared;
    const auto moves = detail::untangle_on_sphere(mesh, rings, shared, with_shared, kDefaultCollapseFloor, 200);
    const auto fresh_moves = detail::untangle_on_sphere(mesh, rings, detail::untangling_frame(mesh, rings), with_fresh,
                                                        kDefaultCollapseFloor, 200);
    EXPECT_GT(moves, 0);
    EXPECT_EQ(moves, fresh_moves);
    EXPECT_EQ(with_shared, with_fresh) << "vertex " << v;
    EXPECT_TRUE(certify_sphere_map(mesh, with_shared).certified()) << "vertex " << v;
  }
}

// A fixed vertex stays where it is, to the bit, even when it is the one whose move would undo the fold:
// its neighbours move instead (the coarse start keeps the poles so).
TEST(Untangling, FixedVerticesNeverMove) {
  const Mesh mesh = flipped_icosphere();
  const auto n = static_cast<std::int32_t>(mesh.positions.size());
  const VertexRings rings = build_vertex_rings(n, mesh.triangles);
  const std::int32_t v = 20000;
  std::vector<Vec3> sphere = folded_at(mesh, rings, v);
  ASSERT_GT(certify_sphere_map(mesh, sphere).folded, 0);
  const Vec3 where = sphere[v];
  std::vector<char> fixed(sphere.size(), 0);
  fixed[v] = 1;
  const auto moves = detail::untangle_on_sphere(mesh, rings, detail::untangling_frame(mesh, rings), sphere,
                                                kDefaultCollapseFloor, 200, fixed);
  EXPECT_GT(moves, 0);
  EXPECT_EQ(sphere[v], where);
  EXPECT_EQ(certify_sphere_map(mesh, sphere).folded, 0);
  fixed.pop_back();
  EXPECT_THROW(detail::untangle_on_sphere(mesh, rings, detail::untangling_frame(mesh, rings), sphere,
                                          kDefaultCollapseFloor, 200, fixed),
               std::invalid_argument);
}

}  // namespace
}  // namespace spheremap
