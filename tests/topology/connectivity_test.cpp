#include "spheremap/topology/connectivity.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <stdexcept>
#include <utility>
#include <vector>

#include "spheremap/shapes/shapes.hpp"

namespace spheremap {
namespace {

TEST(NumberEdges, BothHalfEdgesOfAnEdgeShareADenseIdInVertexOrder) {
  const Mesh mesh = make_icosphere(1);
  const auto edges = number_edges(mesh.positions.size(), mesh.triangles);
  ASSERT_EQ(edges.edge_of_half_edge.size(), 3 * mesh.triangles.size());
  EXPECT_EQ(edges.edge_endpoints.size(), 3 * mesh.triangles.size() / 2);  // closed: E = 3F/2
  for (std::size_t e = 1; e < edges.edge_endpoints.size(); ++e) {
    EXPECT_LT(edges.edge_endpoints[e][0], edges.edge_endpoints[e][1]);
    EXPECT_LT(edges.edge_endpoints[e - 1], edges.edge_endpoints[e]);  // (lower, higher) order, no repeats
  }
  std::vector<int> seen(edges.edge_endpoints.size(), 0);
  for (std::size_t h = 0; h < edges.edge_of_half_edge.size(); ++h) {
    const auto e = edges.edge_of_half_edge[h];
    ASSERT_GE(e, 0);
    ++seen[static_cast<std::size_t>(e)];
    const auto a = half_edge_origin(mesh.triangles, h), b = half_edge_target(mesh.triangles, h);
    EXPECT_EQ(edges.edge_endpoints[static_cast<std::size_t>(e)],
              (std::array<std::int32_t, 2>{std::min(a, b), std::max(a, b)}));
  }
  for (const int count : seen) EXPECT_EQ(count, 2);
}

TEST(OppositeHalfEdges, PairsEveryEdgeOfAClosedMeshTheSameOnAnyNumberOfThreads) {
  const Mesh mesh = make_icosphere(4);
  const auto opposite = opposite_half_edges(mesh.positions.size(), mesh.triangles);
  ASSERT_EQ(opposite.size(), 3 * mesh.triangles.size());
  for (std::size_t h = 0; h < opposite.size(); ++h) {
    const auto g = opposite[h];
    ASSERT_GE(g, 0) << h;
    EXPECT_EQ(opposite[static_cast<std::size_t>(g)], static_cast<std::int32_t>(h));
    EXPECT_EQ(half_edge_origin(mesh.triangles, static_cast<std::size_t>(g)), half_edge_target(mesh.triangles, h));
    EXPECT_EQ(half_edge_target(mesh.triangles, static_cast<std::size_t>(g)), half_edge_origin(mesh.triangles, h));
  }
  const Mesh large = make_icosphere(5);  // 61,440 half-edges: three ranges
  const auto reference = opposite_half_edges(large.positions.size(), large.triangles, 1);
  for (const int threads : {2, 3})
    EXPECT_EQ(opposite_half_edges(large.positions.size(), large.triangles, threads), reference);
}

TEST(OppositeHalfEdges, NoneAcrossAHoleANonManifoldOrAMisorientedEdge) {
  // Two triangles on edge (0, 1) in opposite directions, then what breaks the pairing.
  std::vector<Triangle> triangles = {{0, 1, 2}, {1, 0, 3}};
  auto opposite = opposite_half_edges(5, triangles);
  EXPECT_EQ(opposite[0], 3);  // 0→1 across 1→0
  EXPECT_EQ(opposite[3], 0);
  for (const std::size_t h : {1, 2, 4, 5}) EXPECT_EQ(opposite[h], -1) << h;  // the boundary of the pair
  triangles.push_back({0, 1, 4});  // a third triangle on the edge: non-manifold
  opposite = opposite_half_edges(5, triangles);
  EXPECT_EQ(opposite[0], -1);
  EXPECT_EQ(opposite[3], -1);
  EXPECT_EQ(opposite[6], -1);
  triangles = {{0, 0, 1}, {1, 0, 0}};  // degenerate edges (0, 0)
  opposite = opposite_half_edges(5, triangles);
  EXPECT_EQ(opposite[0], -1);
  EXPECT_EQ(opposite[5], -1);
  triangles = {{0, 1, 2}, {0, 1, 3}};  // both 0→1: misoriented
  opposite = opposite_half_edges(5, triangles);
  EXPECT_EQ(opposite[0], -1);
  EXPECT_EQ(opposite[3], -1);
}

TEST(NumberEdges, HalfEdgesWalkTheirTriangle) {
  const std::vector<Triangle> triangles{{4, 7, 9}};
  EXPECT_EQ(next_half_edge(0), 1u);
  EXPECT_EQ(next_half_edge(2), 0u);
  EXPECT_EQ(previous_half_edge(0), 2u);
  EXPECT_EQ(half_edge_origin(triangles, 1), 7);
  EXPECT_EQ(half_edge_target(triangles, 2), 4);
}

}  // namespace
}  // namespace spheremap
