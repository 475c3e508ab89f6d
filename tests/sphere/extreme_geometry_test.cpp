// Geometry at the edge of double precision still ends in a certified map, never an internal error
// (FUZZING.md, findings 5 and 6): a sparse LU that finds a re-weighting round's system singular, and
// coordinates whose squares overflow (1e300 beside 1) in the fallback's smoothing and the superposition.
#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <utility>
#include <vector>

#include "spheremap/geometry/superposition.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/shapes/shapes.hpp"
#include "spheremap/sphere/certify.hpp"
#include "spheremap/sphere/fallback.hpp"
#include "spheremap/sphere/map.hpp"

namespace spheremap {
namespace {

// The prepared mesh of fuzz/regressions/map/mean-value-singular-lu: a flat bipyramid (every y = 0) with
// one apex 5.6e61 away and one 5.6e17 away. Its mean-value weights span about 1e-122 to 1e61.
Mesh far_apex_bipyramid() {
  Mesh mesh;
  mesh.positions = {{1, 0, 0}, {-1.4, 0, 0}, {-1, 0, 5.5555555555555559e61}, {5, 0, 0}, {-1, 0, 5.5555555555555552e17}};
  mesh.triangles = {{0, 2, 1}, {3, 1, 4}, {3, 0, 1}, {2, 0, 4}, {1, 2, 4}, {0, 3, 4}};
  return mesh;
}

TEST(SingularSystems, ARoundWhoseSystemIsSingularIsRejectedAndTheMapCertified) {
  MapOptions options;
  options.weights = Weights::kMeanValue;
  const SphereMap map = map_to_sphere(far_apex_bipyramid(), options);  // threw "singular system" before
  EXPECT_GE(map.diagnostics.solve.singular_systems, 1) << "the mesh no longer reaches a singular system";
  EXPECT_FALSE(map.diagnostics.solve.uniform_weights_instead);
  EXPECT_TRUE(map.certificate.certified())
      << map.certificate.folded << " folded, " << map.certificate.collapsed << " collapsed";
}

TEST(SingularSystems, UniformWeightsMeetNone) {
  const SphereMap map = map_to_sphere(far_apex_bipyramid());
  EXPECT_EQ(map.diagnostics.solve.singular_systems, 0);
  EXPECT_TRUE(map.certificate.certified());
}

// Bipyramids over a nearly flat ring with apexes 1e17 to 1e69 away, found by a random search of such
// shapes: with the weights asked for, the plain map's own system (not a re-weighting round's) is singular.
Mesh bipyramid(std::vector<Vec3> positions) {
  Mesh mesh;
  const auto ring = static_cast<std::int32_t>(positions.size()) - 2;
  mesh.positions = std::move(positions);
  for (std::int32_t i = 0; i < ring; ++i) {
    const std::int32_t j = (i + 1) % ring;
    mesh.triangles.push_back({i, j, ring});
    mesh.triangles.push_back({j, i, ring + 1});
  }
  return mesh;
}

TEST(SingularSystems, APlainSystemThatIsSingularIsSolvedWithUniformWeights) {
  const Mesh mean_value_singular = bipyramid({{16.200120249036054, 0, 0},
                                              {1.9389146078538271e-17, 0, 0.31664878546267788},
                                              {-0.36947248574783409, -3.9858008219673789e-15, 4.5247329704410111e-17},
                                              {-4.4836301816151282e-16, 0, -2.4407745889055832},
                                              {-0.68528904318302164, 6.1825044424397481e+69, 0.90134102814302253},
                                              {0.7407940705700653, -9.1612357645528767e+59, 0.68969054364596571}});
  const Mesh cotangent_singular = bipyramid({{1.8924220596314605, -0.0005498604363613701, 0},
                                             {0.025452550252548199, -0.0004097355311546984, 0.07833489489139342},
                                             {-4.5719157309455749, 31747771049227.043, 3.3216912129886764},
                                             {-0.76678202903218773, -1.6584583142091629e+17, -0.55709975380212551},
                                             {0.045272489591829342, -1.7313650419861556e-06, -0.13933439590371127},
                                             {0.44865166973482351, 1.2005390413667476e+32, 0.18539005634291783},
                                             {-0.79625963682250267, -5.5809196192456779e+27, -0.22370225455214665}});
  for (const auto& [mesh, weights] :
       {std::pair{mean_value_singular, Weights::kMeanValue}, std::pair{cotangent_singular, Weights::kCotangent}}) {
    MapOptions options;
    options.weights = weights;
    const SphereMap map = map_to_sphere(mesh, options);
    const auto name = to_string(weights);
    EXPECT_GE(map.diagnostics.solve.singular_systems, 1) << name << ": the mesh no longer reaches a singular system";
    EXPECT_TRUE(map.diagnostics.solve.uniform_weights_instead) << name;
    EXPECT_TRUE(map.certificate.certified()) << name;
    const SphereMap uniform = map_to_sphere(mesh);  // what the fallback solved: no singular system
    EXPECT_EQ(uniform.diagnostics.solve.singular_systems, 0) << name;
  }
}

// A cube with one vertex moved to z = 1e300: its areas overflow.
Mesh cube_with_a_vertex_at_1e300() {
  Mesh mesh = make_subdivided_cube(4);
  mesh.positions[30][2] = 1e300;
  return mesh;
}

// The map, under every weighting; the superposition must stay finite (it was NaN, and the map with it).
TEST(ExtremeGeometry, AVertexAt1e300StillMapsCertified) {
  for (const auto weights : {Weights::kUniform, Weights::kMeanValue, Weights::kCotangent}) {
    const Mesh mesh = cube_with_a_vertex_at_1e300();
    MapOptions options;
    options.weights = weights;
    options.poles = std::make_pair(0, static_cast<std::int32_t>(mesh.positions.size()) - 1);
    const SphereMap map = map_to_sphere(mesh, options);
    EXPECT_TRUE(map.certificate.certified()) << static_cast<int>(weights);
    EXPECT_TRUE(std::isfinite(map.superposition.rmsd) && std::isfinite(map.superposition.scale));
    for (const auto& p : map.sphere) ASSERT_NEAR(norm(p), 1.0, 1e-12);
  }
}

// The fallback itself: its smoothing has no finite energy there (it threw), so insertion alone must give
// a valid map.
TEST(ExtremeGeometry, TheFallbackMapsAVertexAt1e300) {
  const Mesh mesh = cube_with_a_vertex_at_1e300();
  FallbackReport report;
  const auto sphere = fallback_map(mesh, 0, static_cast<std::int32_t>(mesh.positions.size()) - 1, report);
  ASSERT_TRUE(report.embedding.valid);
  EXPECT_TRUE(certify_sphere_map(mesh, sphere, MapOptions{}.collapse_floor).certified());
}

// The superposition of points whose squares overflow equals that of the same points scaled down.
TEST(Superposition, CoordinatesWhoseSquaresOverflowGiveTheScaledDownRotation) {
  const Mesh cube = make_subdivided_cube(2);
  std::vector<Vec3> sphere, small, huge;
  for (const auto& p : cube.positions) {
    sphere.push_back((1 / norm(p)) * p);
    const Vec3 q{p[0] + 0.3 * p[1], 2 * p[1], p[2] - 0.2 * p[0]};  // not a rotation of the sphere
    small.push_back(q);
    huge.push_back(1e300 * q);
  }
  const Superposition a = superpose_sphere_on_surface(small, sphere);
  const Superposition b = superpose_sphere_on_surface(huge, sphere);
  for (int k = 0; k < 9; ++k) EXPECT_NEAR(a.rotation[k], b.rotation[k], 1e-12) << k;
  EXPECT_NEAR(b.scale / 1e300, a.scale, 1e-12 * a.scale);
  EXPECT_NEAR(b.rmsd / 1e300, a.rmsd, 1e-12 * a.rmsd);
}

}  // namespace
}  // namespace spheremap
