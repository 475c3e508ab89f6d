// The hard-case generators: closed, outward-oriented genus-0 meshes of the documented sizes,
// deterministic for a seed, with the features that make them hard (tiny nested triangles, thin tubes).
#include "spheremap/shapes/hard_cases.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <set>
#include <stdexcept>
#include <utility>

#include "../test_support.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/shapes/shapes.hpp"

namespace spheremap {
namespace {

using testing_support::signed_volume;

// Closed oriented 2-manifold with Euler characteristic 2, outward, every triangle of positive area;
// returns the smallest triangle area relative to the total.
double expect_genus0_outward(const Mesh& mesh) {
  testing_support::expect_closed_oriented_manifold(mesh);
  std::set<std::pair<std::int32_t, std::int32_t>> edges;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) edges.insert(std::minmax(t[k], t[(k + 1) % 3]));
  EXPECT_EQ(static_cast<std::int64_t>(mesh.vertex_count()) - static_cast<std::int64_t>(edges.size()) +
                static_cast<std::int64_t>(mesh.triangle_count()),
            2);
  EXPECT_GT(signed_volume(mesh), 0);
  double smallest = INFINITY, total = 0;
  for (const auto& t : mesh.triangles) {
    const double area = triangle_area(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
    EXPECT_GT(area, 0);
    smallest = std::min(smallest, area);
    total += area;
  }
  return smallest / total;
}

TEST(HardCases, StackedTriangulationsAreSpheresWithNestedTinyTriangles) {
  const Mesh flat = make_stacked_triangulation(300, 0.0, 1);
  ASSERT_EQ(flat.vertex_count(), 300u);
  ASSERT_EQ(flat.triangle_count(), 596u);
  const double flat_smallest = expect_genus0_outward(flat);
  const Mesh deep = make_stacked_triangulation(300, 0.9, 1);
  const double deep_smallest = expect_genus0_outward(deep);
  // Nesting is what makes the triangles tiny: each insertion splits one triangle into three.
  EXPECT_LT(deep_smallest, 1e-12);
  EXPECT_LT(deep_smallest, 1e-4 * flat_smallest);
  // Deterministic for a seed; another seed gives another mesh.
  EXPECT_EQ(make_stacked_triangulation(300, 0.9, 1).positions, deep.positions);
  EXPECT_NE(make_stacked_triangulation(300, 0.9, 2).positions, deep.positions);
  // A tetrahedron is the smallest.
  EXPECT_EQ(make_stacked_triangulation(4, 0.5, 1).triangle_count(), 4u);
}

TEST(HardCases, StackedTriangulationRefusesBadArguments) {
  EXPECT_THROW(make_stacked_triangulation(3, 0, 1), std::invalid_argument);
  EXPECT_THROW(make_stacked_triangulation(10, 1.5, 1), std::invalid_argument);
  EXPECT_THROW(make_stacked_triangulation(10, 0, 1, -1), std::invalid_argument);
  // A chain nested thousands of times deep shrinks a triangle below what doubles hold.
  EXPECT_THROW(make_stacked_triangulation(3000, 1.0, 1), std::invalid_argument);
}

TEST(HardCases, BentTubesAreClosedAndCoarse) {
  for (const auto bend : {TubeBend::kU, TubeBend::kC})
    for (int segments = 3; segments <= 6; ++segments) {
      const Mesh tube = make_bent_tube(bend, segments, 21);
      ASSERT_EQ(tube.vertex_count(), static_cast<std::size_t>(21 * segments + 2));
      ASSERT_EQ(tube.triangle_count(), static_cast<std::size_t>(2 * (21 * segments)));
      expect_genus0_outward(tube);
    }
  // The U's legs end side by side, the C's ends face each other across the gap.
  const Mesh u = make_bent_tube(TubeBend::kU, 4, 21);
  const auto& first = u.positions[u.vertex_count() - 2];
  const auto& last = u.positions[u.vertex_count() - 1];
  EXPECT_NEAR(first[0], -1, 1e-12);
  EXPECT_NEAR(last[0], 1, 1e-12);
  EXPECT_NEAR(first[1], last[1], 1e-12);
  EXPECT_THROW(make_bent_tube(TubeBend::kU, 2, 10), std::invalid_argument);
  EXPECT_THROW(make_bent_tube(TubeBend::kC, 4, 1), std::invalid_argument);
  EXPECT_THROW(make_bent_tube(TubeBend::kC, 4, 10, 0.6), std::invalid_argument);
}

TEST(HardCases, SpikySpheresGrowThinTubes) {
  const Mesh spiky = make_spiky_sphere(1, 4, 3, 5, 1);
  const Mesh ico = make_icosphere(1);
  // Each spike: 5 rings of as many vertices as the star had (5 or 6), two triangles per ring edge.
  std::size_t added = spiky.vertex_count() - ico.vertex_count();
  EXPECT_TRUE(added >= 4 * 5 * 5 && added <= 4 * 5 * 6) << added;
  EXPECT_EQ(spiky.triangle_count() - ico.triangle_count(), 2 * added);
  expect_genus0_outward(spiky);
  int tips = 0;
  for (const auto& p : spiky.positions) tips += norm(p) > 3.99;
  EXPECT_EQ(tips, 4);
  EXPECT_EQ(make_spiky_sphere(1, 4, 3, 5, 1).positions, spiky.positions);
  EXPECT_THROW(make_spiky_sphere(7, 1, 1, 1, 1), std::invalid_argument);
  EXPECT_THROW(make_spiky_sphere(1, -1, 1, 1, 1), std::invalid_argument);
  EXPECT_THROW(make_spiky_sphere(1, 1, 0, 1, 1), std::invalid_argument);
  EXPECT_THROW(make_spiky_sphere(1, 1, 1, 0, 1), std::invalid_argument);
}

}  // namespace
}  // namespace spheremap
