// The boundary meridian: steepest descent, the kept path of an earlier round, and the shortest-path
// fallback when every descent stalls (interior minima of z, which only negative weights can make).
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <set>
#include <tuple>
#include <vector>

#include "../../src/sphere/meridian.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/shapes/shapes.hpp"
#include "spheremap/sphere/map.hpp"
#include "spheremap/sphere/poles.hpp"
#include "spheremap/topology/connectivity.hpp"

namespace spheremap {
namespace {

struct Fixture {
  Mesh mesh = make_icosphere(3);
  VertexRings rings = build_vertex_rings(static_cast<std::int32_t>(mesh.positions.size()), mesh.triangles);
  std::int32_t north = 0, south = 0;
  std::vector<double> height;  // along the pole axis: +1 at N, -1 at S
  Fixture() {
    std::tie(north, south) = farthest_pair(mesh.positions);
    const Vec3 axis = mesh.positions[north] - mesh.positions[south];
    const double half = std::sqrt(dot(axis, axis)) / 2;
    const Vec3 centre = 0.5 * (mesh.positions[north] + mesh.positions[south]);
    for (const auto& p : mesh.positions) height.push_back(dot(p - centre, axis) / (2 * half * half));
  }
  // z with the ring values the map fixes: +1 on N and its ring, -1 on S and its ring.
  std::vector<double> with_rings(std::vector<double> z) const {
    z[north] = 1, z[south] = -1;
    for (auto v : rings.ring(north)) z[v] = 1;
    for (auto v : rings.ring(south)) z[v] = -1;
    return z;
  }
};

bool adjacent(const VertexRings& rings, std::int32_t a, std::int32_t b) {
  const auto ring = rings.ring(a);
  return std::find(ring.begin(), ring.end(), b) != ring.end();
}

// What the φ solve relies on, whichever way the path was found: from the north ring to the south ring,
// consecutive vertices joined by edges, no pole, no repeated vertex, only its first vertex on the north
// ring, only its last on the south ring, and no chord (an edge between non-consecutive path vertices).
void expect_valid_meridian(const Fixture& f, const std::vector<std::int32_t>& path) {
  ASSERT_GE(path.size(), 2u);
  const auto north_ring = f.rings.ring(f.north), south_ring = f.rings.ring(f.south);
  const std::set<std::int32_t> on_north(north_ring.begin(), north_ring.end()),
      on_south(south_ring.begin(), south_ring.end());
  EXPECT_TRUE(on_north.count(path.front()));
  EXPECT_TRUE(on_south.count(path.back()));
  EXPECT_EQ(std::set<std::int32_t>(path.begin(), path.end()).size(), path.size()) << "a vertex repeats";
  for (std::size_t i = 0; i < path.size(); ++i) {
    EXPECT_NE(path[i], f.north);
    EXPECT_NE(path[i], f.south);
    if (i > 0) EXPECT_FALSE(on_north.count(path[i])) << "north-ring vertex inside the path at " << i;
    if (i + 1 < path.size()) {
      EXPECT_FALSE(on_south.count(path[i])) << "south-ring vertex inside the path at " << i;
      EXPECT_TRUE(adjacent(f.rings, path[i], path[i + 1])) << "no edge between path vertices " << i << " and " << i + 1;
    }
    for (std::size_t j = i + 2; j < path.size(); ++j)
      EXPECT_FALSE(adjacent(f.rings, path[i], path[j])) << "chord between path vertices " << i << " and " << j;
  }
}

TEST(Meridian, SteepestDescentWhenZDecreasesTowardsTheSouth) {
  const Fixture f;
  const auto z = f.with_rings(f.height);
  const auto meridian = detail::boundary_meridian(f.rings, z, f.north, f.south);
  EXPECT_TRUE(meridian.by_descent);
  EXPECT_FALSE(meridian.kept);
  expect_valid_meridian(f, meridian.path);
  for (std::size_t i = 1; i + 1 < meridian.path.size(); ++i) EXPECT_LT(z[meridian.path[i + 1]], z[meridian.path[i]]);
}

TEST(Meridian, ShortestPathWhenEveryDescentStallsAtAnInteriorMinimum) {
  const Fixture f;
  // z falls from the north ring to the equator and is 0.5 everywhere south of it: every descent ends
  // in the northern half at a vertex whose southern neighbours are higher, an interior minimum.
  std::vector<double> z(f.height.size());
  for (std::size_t v = 0; v < z.size(); ++v) z[v] = f.height[v] > 0 ? f.height[v] : 0.5;
  z = f.with_rings(z);
  const auto meridian = detail::boundary_meridian(f.rings, z, f.north, f.south);
  EXPECT_FALSE(meridian.by_descent);
  expect_valid_meridian(f, meridian.path);
  // Breadth-first: no path from ring to ring through the allowed vertices is shorter.
  const auto descent = detail::boundary_meridian(f.rings, f.with_rings(f.height), f.north, f.south);
  EXPECT_LE(meridian.path.size(), descent.path.size());
}

TEST(Meridian, KeptPathIsReusedOnlyWhileZStillDecreasesAlongIt) {
  const Fixture f;
  const auto z = f.with_rings(f.height);
  const auto first = detail::boundary_meridian(f.rings, z, f.north, f.south);
  const auto again = detail::boundary_meridian(f.rings, z, f.north, f.south, &first.path);
  EXPECT_TRUE(again.kept);
  EXPECT_EQ(again.path, first.path);
  // Raise one interior vertex of the kept path above its predecessor: the path no longer descends.
  auto bumped = z;
  ASSERT_GE(first.path.size(), 4u);
  bumped[first.path[2]] = z[first.path[1]] + 0.01;
  const auto fresh = detail::boundary_meridian(f.rings, bumped, f.north, f.south, &first.path);
  EXPECT_FALSE(fresh.kept);
  EXPECT_TRUE(fresh.by_descent);
  expect_valid_meridian(f, fresh.path);
}

}  // namespace
}  // namespace spheremap
