#include "spheremap/sphere/map.hpp"

#include <gtest/gtest.h>

#include "../test_support.hpp"

#include <cmath>
#include <iostream>
#include <numbers>
#include <random>

#include "spheremap/error.hpp"
#include "spheremap/geometry/predicates.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/shapes/shapes.hpp"
#include "spheremap/topology/connectivity.hpp"
#include "spheremap/topology/prepare.hpp"

namespace spheremap {
namespace {

Mesh prepared(const Mesh& mesh) { return prepare_mesh(mesh).mesh; }

// Every expectation of a valid map, checked independently of the certificate's own bookkeeping.
void expect_certified(const Mesh& mesh, const SphereMap& map, const std::string& what) {
  ASSERT_EQ(map.sphere.size(), mesh.vertex_count()) << what;
  EXPECT_TRUE(map.certificate.certified()) << what << ": folded " << map.certificate.folded << ", collapsed "
                                           << map.certificate.collapsed << ", coverage " << map.certificate.coverage;
  testing_support::expect_valid_on_sphere(mesh, map.sphere, what);
  for (const auto& p : map.sphere) ASSERT_NEAR(norm(p), 1.0, 1e-12) << what;
  ASSERT_EQ(map.theta.size(), mesh.vertex_count());
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) {
    EXPECT_GE(map.theta[v], 0);
    EXPECT_LE(map.theta[v], std::numbers::pi);
    EXPECT_GE(map.phi[v], 0);
    EXPECT_LT(map.phi[v], 2 * std::numbers::pi);
  }
}

TEST(SphereMap, IcospheresMapCertifiedAndCloseToIdentity) {
  for (int level = 0; level <= 4; ++level) {
    const Mesh mesh = prepared(make_icosphere(level));
    const auto map = map_to_sphere(mesh);
    expect_certified(mesh, map, "icosphere " + std::to_string(level));
    EXPECT_EQ(map.diagnostics.repair.plain_certificate.folded, 0);
    // The surface is already a sphere: after superposition the map should be close to it (no mirror).
    EXPECT_LT(map.superposition.rmsd, 0.3) << level;
    std::cout << "icosphere " << level << " rmsd " << map.superposition.rmsd << "\n";
  }
}

TEST(SphereMap, TinyMeshesAreMappedThroughARefinement) {
  PolygonSoup tetra;
  tetra.positions = {{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  tetra.faces = {{0, 2, 1}, {0, 1, 3}, {0, 3, 2}, {1, 2, 3}};
  const Mesh tetrahedron = prepare_mesh(tetra).mesh;
  const auto map = map_to_sphere(tetrahedron);
  EXPECT_EQ(map.diagnostics.construction.method, MapMethod::kRefinedPolesAndRings);
  expect_certified(tetrahedron, map, "tetrahedron");

  PolygonSoup octa;
  octa.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  octa.faces = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  const Mesh octahedron = prepare_mesh(octa).mesh;
  expect_certified(octahedron, map_to_sphere(octahedron), "octahedron");
}

TEST(SphereMap, BipyramidsWithGraphDiameterTwoAreMappedThroughARefinement) {
  for (int equator = 4; equator <= 16; equator += 4) {
    PolygonSoup soup;
    soup.positions = {{0, 0, 1}, {0, 0, -1}};
    for (int k = 0; k < equator; ++k)
      soup.positions.push_back(
          {std::cos(2 * std::numbers::pi * k / equator), std::sin(2 * std::numbers::pi * k / equator), 0});
    for (int k = 0; k < equator; ++k) {
      const int a = 2 + k, b = 2 + (k + 1) % equator;
      soup.faces.push_back({0, a, b});
      soup.faces.push_back({1, b, a});
    }
    const Mesh mesh = prepare_mesh(soup).mesh;
    const auto map = map_to_sphere(mesh);
    EXPECT_EQ(map.diagnostics.construction.method, MapMethod::kRefinedPolesAndRings);
    expect_certified(mesh, map, "bipyramid " + std::to_string(equator));
  }
}

TEST(SphereMap, EveryWeightingOnAStretchedEllipsoid) {
  const Mesh mesh = prepared(make_ellipsoid(3, 1, 1, 20));
  for (auto weights : {Weights::kUniform, Weights::kCotangent, Weights::kMeanValue}) {
    MapOptions options;
    options.weights = weights;
    expect_certified(mesh, map_to_sphere(mesh, options), std::string("ellipsoid 1:20 ") + to_string(weights));
  }
}

TEST(SphereMap, DumbbellWithThinNeck) {
  const Mesh mesh = prepared(make_dumbbell(4, 0.05, 200, 32));
  const auto map = map_to_sphere(mesh);
  expect_certified(mesh, map, "dumbbell");
}

TEST(SphereMap, RandomFlipsCreateDividingEdgesThatAreSplitAndRepaired) {
  std::int64_t total_splits = 0;
  for (std::uint32_t seed = 1; seed <= 12; ++seed) {
    const Mesh mesh = prepared(perturb_vertices(random_edge_flips(make_icosphere(2), 0.35, seed), 0.2, seed));
    const auto map = map_to_sphere(mesh);
    expect_certified(mesh, map, "flips seed " + std::to_string(seed));
    total_splits += static_cast<std::int64_t>(map.diagnostics.construction.split_edges.size());
  }
  EXPECT_GT(total_splits, 0) << "the generated cases no longer exercise dividing edges";
}

TEST(SphereMap, DividingEdgeThroughAPoleIsSplitAndRecorded) {
  // Choose as north pole a vertex of degree 3 created by random flips: its ring is a triangle only if
  // the three neighbours are mutually adjacent, and any ring chord must be split.
  for (std::uint32_t seed = 1; seed <= 40; ++seed) {
    const Mesh mesh = prepared(random_edge_flips(make_icosphere(2), 0.35, seed));
    const auto rings = build_vertex_rings(static_cast<std::int32_t>(mesh.vertex_count()), mesh.triangles);
    for (std::int32_t v = 0; v < rings.vertex_count(); ++v) {
      if (rings.degree(v) != 3) continue;
      // The degree-3 vertex is a ring vertex of each neighbour's pole: take a neighbour as pole.
      const std::int32_t pole = rings.ring(v)[0];
      const auto distance = graph_distances(rings, pole);
      const auto south =
          static_cast<std::int32_t>(std::max_element(distance.begin(), distance.end()) - distance.begin());
      MapOptions options;
      options.poles = std::make_pair(pole, south);
      const auto map = map_to_sphere(mesh, options);
      EXPECT_EQ(map.poles.north, pole);
      EXPECT_FALSE(map.diagnostics.construction.split_edges.empty());
      expect_certified(mesh, map, "degree-3 ring vertex, seed " + std::to_string(seed));
      return;
    }
  }
  FAIL() << "no degree-3 vertex found in the generated meshes";
}

TEST(SphereMap, SymmetricMeshWithZTiesIsDeterministic) {
  const Mesh mesh = prepared(make_subdivided_cube(8));
  const auto first = map_to_sphere(mesh);
  const auto second = map_to_sphere(mesh);
  expect_certified(mesh, first, "subdivided cube");
  ASSERT_EQ(first.sphere, second.sphere);
  EXPECT_EQ(first.diagnostics.construction.meridian, second.diagnostics.construction.meridian);
}

TEST(SphereMap, GaussSeidelAgreesWithTheDirectSolver) {
  const Mesh mesh = prepared(perturb_vertices(make_icosphere(2), 0.2, 3));
  MapOptions direct_options, relaxed_options;
  relaxed_options.solver = Solver::kGaussSeidel;
  relaxed_options.repair = direct_options.repair = false;
  const auto direct = map_to_sphere(mesh, direct_options);
  const auto relaxed = map_to_sphere(mesh, relaxed_options);
  EXPECT_TRUE(relaxed.diagnostics.solve.gauss_seidel_converged);
  EXPECT_GT(relaxed.diagnostics.solve.gauss_seidel_sweeps, 10);
  // θ depends on z alone; φ also on the meridian, which may take another path where two descents
  // nearly tie at Gauss–Seidel's precision.
  for (std::size_t v = 0; v < mesh.vertex_count(); ++v) EXPECT_NEAR(direct.theta[v], relaxed.theta[v], 1e-9);
  EXPECT_EQ(direct.diagnostics.repair.plain_certificate.folded, relaxed.diagnostics.repair.plain_certificate.folded);
}

TEST(SphereMap, PolesOptionIsHonouredAndValidated) {
  const Mesh mesh = prepared(make_icosphere(2));
  MapOptions options;
  options.poles = std::make_pair(5, 17);
  const auto map = map_to_sphere(mesh, options);
  EXPECT_EQ(map.poles.north, 5);
  EXPECT_EQ(map.poles.south, 17);
  expect_certified(mesh, map, "poles 5,17");
  options.poles = std::make_pair(5, 5);
  EXPECT_THROW(map_to_sphere(mesh, options), InputError);
  options.poles = std::make_pair(5, 100000);
  EXPECT_THROW(map_to_sphere(mesh, options), InputError);
  // Adjacent poles have no disjoint rings.
  const auto rings = build_vertex_rings(static_cast<std::int32_t>(mesh.vertex_count()), mesh.triangles);
  options.poles = std::make_pair(5, rings.ring(5)[0]);
  EXPECT_THROW(map_to_sphere(mesh, options), InputError);
}

TEST(SphereMap, PhiIncreasesEastwardSoTheMapIsNotAMirrorImage) {
  // On a sphere mapped onto itself, φ must turn the same way as the azimuth around the north pole.
  const Mesh mesh = prepared(make_icosphere(3));
  MapOptions options;
  options.repair = false;
  const auto map = map_to_sphere(mesh, options);
  EXPECT_EQ(map.diagnostics.repair.plain_certificate.folded, 0);
  EXPECT_NEAR(map.diagnostics.repair.plain_certificate.coverage, 1.0, 1e-9);
}

TEST(SphereMap, MapMetadataFollowsThePaper) {
  const Mesh mesh = prepared(make_icosphere(3));
  const auto map = map_to_sphere(mesh);
  const auto distance = graph_distances(
      build_vertex_rings(static_cast<std::int32_t>(mesh.vertex_count()), mesh.triangles), map.poles.north);
  EXPECT_EQ(map.poles.graph_distance, distance[map.poles.south]);
  EXPECT_DOUBLE_EQ(map.diagnostics.construction.theta0, std::numbers::pi / map.poles.graph_distance);
  EXPECT_NEAR(map.diagnostics.construction.mercator_c,
              1.0 / std::log((1 + std::cos(map.diagnostics.construction.theta0)) /
                             std::sin(map.diagnostics.construction.theta0)),
              1e-15);
  EXPECT_GE(map.diagnostics.construction.meridian.size(), 2u);
}

}  // namespace
}  // namespace spheremap
