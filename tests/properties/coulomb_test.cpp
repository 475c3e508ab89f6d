#include "spheremap/properties/coulomb.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <random>
#include <stdexcept>

#include "spheremap/geometry/normals.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/shapes/shapes.hpp"

namespace spheremap {
namespace {

CoulombOptions with(Dielectric dielectric, double value, CoulombSummation summation) {
  CoulombOptions options;
  options.dielectric = dielectric;
  options.dielectric_value = value;
  options.summation = summation;
  return options;
}

TEST(Coulomb, BjerrumLengthFromCodata) {
  // e²/(4πε₀ k T) at 298.15 K (CODATA 2018), and the 332.0637 kcal·Å/(mol·e²) of the literature divided by kT.
  EXPECT_NEAR(bjerrum_length(298.15), 560.4593221, 1e-6);
  EXPECT_NEAR(bjerrum_length(298.15) * 0.592484949713764, 332.0637133, 1e-6);
  EXPECT_NEAR(bjerrum_length(310), 167100.94689828737 / 310, 1e-12);
  EXPECT_THROW(bjerrum_length(0), std::invalid_argument);
}

// One charge at the centre of a sphere of radius 10 Å: every vertex moved 1.4 Å out along its normal is at
// 11.4 Å, where the potential is known in closed form.
TEST(Coulomb, OneChargeGivesTheAnalyticPotentialAtTheOffsetPoints) {
  Mesh sphere = make_icosphere(3);
  for (auto& p : sphere.positions) p = 10.0 * p;
  const auto points = offset_along_normals(sphere.positions, vertex_normals(sphere.positions, sphere.triangles), 1.4);
  const PointCharges charge{{{0, 0, 0}}, {-1.5}};
  const double lb = bjerrum_length(298.15);
  for (const auto summation : {CoulombSummation::kExact, CoulombSummation::kTreecode}) {
    const auto distance_dependent =
        coulomb_potential(charge, points, with(Dielectric::kDistanceDependent, 4, summation));
    const auto constant = coulomb_potential(charge, points, with(Dielectric::kConstant, 80, summation));
    for (std::size_t v = 0; v < points.size(); ++v) {
      const double r = norm(points[v]);
      // The icosphere's vertex normals are radial up to its slight flattening between vertices.
      ASSERT_NEAR(r, 11.4, 2e-2);
      EXPECT_NEAR(distance_dependent[v], lb * -1.5 / (4 * r * r), 1e-12);
      EXPECT_NEAR(constant[v], lb * -1.5 / (80 * r), 1e-12);
    }
    EXPECT_NEAR(distance_dependent[0], -1.5 * 560.4593221475344 / (4 * 11.4 * 11.4), 2e-3);  // -1.617 kT/e
  }
}

TEST(Coulomb, TwoOppositeChargesGiveAnAntisymmetricField) {
  const PointCharges dipole{{{3, 0, 0}, {-3, 0, 0}}, {1, -1}};
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-20, 20);
  std::vector<Vec3> points, mirrored;
  for (int i = 0; i < 2000; ++i) {
    const Vec3 p = {coordinate(random), coordinate(random), coordinate(random)};
    if (squared_distance(p, {3, 0, 0}) < 1 || squared_distance(p, {-3, 0, 0}) < 1) continue;
    points.push_back(p);
    mirrored.push_back({-p[0], p[1], p[2]});
  }
  points.push_back({0, 5, 1});  // on the mid-plane
  mirrored.push_back({0, 5, 1});
  for (const auto dielectric : {Dielectric::kDistanceDependent, Dielectric::kConstant}) {
    const auto options = with(dielectric, 4, CoulombSummation::kExact);
    const auto phi = coulomb_potential(dipole, points, options),
               phi_mirrored = coulomb_potential(dipole, mirrored, options);
    for (std::size_t i = 0; i < points.size(); ++i) {
      EXPECT_EQ(phi_mirrored[i], -phi[i]);
      if (points[i][0] > 0) EXPECT_GT(phi[i], 0);  // nearer the positive charge
      if (points[i][0] < 0) EXPECT_LT(phi[i], 0);
    }
    EXPECT_EQ(phi.back(), 0.0);
  }
}

// About a protein's worth of charges in a ball of radius 30 Å (one per 11 Å³), points 1.5 to 3 Å outside it
// and in a few clefts cut through it.
struct RandomSystem {
  PointCharges charges;
  std::vector<Vec3> points;
};

RandomSystem random_system(int atoms, int points, std::uint32_t seed) {
  std::mt19937 random(seed);
  std::uniform_real_distribution<double> unit(-1, 1), charge(-0.8, 0.8);
  RandomSystem system;
  while (static_cast<int>(system.charges.positions.size()) < atoms) {
    const Vec3 p = {30 * unit(random), 30 * unit(random), 30 * unit(random)};
    if (norm(p) > 30 || std::abs(p[2]) < 2) continue;  // a slab-shaped cleft at z = 0
    system.charges.positions.push_back(p);
    system.charges.charges.push_back(charge(random));
  }
  while (static_cast<int>(system.points.size()) < points) {
    const Vec3 direction = normalized({unit(random), unit(random), unit(random)});
    if (system.points.size() % 4 == 0)  // in the cleft
      system.points.push_back({28 * unit(random), 28 * unit(random), 0.5 * unit(random)});
    else
      system.points.push_back((31.5 + 1.5 * (unit(random) + 1) / 2) * direction);
  }
  return system;
}

TEST(Coulomb, TreecodeMatchesTheExactSumOnTenThousandCharges) {
  const RandomSystem system = random_system(10000, 20000, 11);
  for (const auto dielectric : {Dielectric::kDistanceDependent, Dielectric::kConstant}) {
    const auto exact = coulomb_potential(system.charges, system.points, with(dielectric, 4, CoulombSummation::kExact));
    const auto fast =
        coulomb_potential(system.charges, system.points, with(dielectric, 4, CoulombSummation::kTreecode));
    const double error = relative_rms_difference(fast, exact);
    RecordProperty(dielectric == Dielectric::kConstant ? "error_constant" : "error_distance_dependent",
                   std::to_string(error));
    EXPECT_LE(error, 1e-3) << "relative RMS error of the treecode (defaults) against the exact sum";
    EXPECT_GT(error, 0) << "the treecode must have expanded some cells for this test to test it";
  }
}

// Each order of the expansion must cut the error: a wrong term of any order shows here as an order that does
// not help (or makes it worse).
TEST(Coulomb, TreecodeErrorFallsWithTheOrderOfTheExpansion) {
  const RandomSystem system = random_system(4000, 6000, 5);
  for (const auto dielectric : {Dielectric::kDistanceDependent, Dielectric::kConstant}) {
    const auto exact = coulomb_potential(system.charges, system.points, with(dielectric, 4, CoulombSummation::kExact));
    double previous = INFINITY;
    for (int order = 0; order <= 6; ++order) {
      auto options = with(dielectric, 4, CoulombSummation::kTreecode);
      options.treecode.order = order;
      options.treecode.theta = 0.6;
      const double error = relative_rms_difference(coulomb_potential(system.charges, system.points, options), exact);
      EXPECT_LT(error, 0.7 * previous) << "order " << order;
      previous = error;
    }
    EXPECT_LT(previous, 1e-4);
  }
}

TEST(Coulomb, SameBytesWhateverTheThreadCount) {
  const RandomSystem system = random_system(3000, 5000, 3);
  for (const auto summation : {CoulombSummation::kExact, CoulombSummation::kTreecode}) {
    auto options = with(Dielectric::kDistanceDependent, 4, summation);
    options.threads = 1;
    const auto one = coulomb_potential(system.charges, system.points, options);
    options.threads = 3;
    EXPECT_EQ(coulomb_potential(system.charges, system.points, options), one);
  }
}

TEST(Coulomb, ZeroChargesAddNothingAndBadArgumentsThrow) {
  const PointCharges one{{{0, 0, 0}}, {1}}, padded{{{0, 0, 0}, {1, 0, 0}}, {1, 0}};
  const std::vector<Vec3> points = {{0, 0, 5}, {0, 7, 0}};
  EXPECT_EQ(coulomb_potential(padded, points), coulomb_potential(one, points));
  EXPECT_EQ(coulomb_potential(PointCharges{}, points), (std::vector<double>{0, 0}));
  EXPECT_THROW(coulomb_potential(PointCharges{{{0, 0, 0}}, {}}, points), std::invalid_argument);
  EXPECT_THROW(coulomb_potential(PointCharges{{{0, 0, NAN}}, {1}}, points), std::invalid_argument);
  auto options = with(Dielectric::kConstant, 0, CoulombSummation::kAuto);
  EXPECT_THROW(coulomb_potential(one, points, options), std::invalid_argument);
  options = with(Dielectric::kConstant, 1, CoulombSummation::kTreecode);
  options.treecode.order = 7;
  EXPECT_THROW(coulomb_potential(one, points, options), std::invalid_argument);
  options.treecode.order = 3;
  options.treecode.theta = 1;
  EXPECT_THROW(coulomb_potential(one, points, options), std::invalid_argument);
}

TEST(VertexNormals, AreaWeightedAndOutward) {
  const Mesh cube = make_subdivided_cube(2);
  const auto normals = vertex_normals(cube.positions, cube.triangles);
  Vec3 centre{0, 0, 0};
  for (const auto& p : cube.positions) centre = centre + (1.0 / cube.positions.size()) * p;
  for (std::size_t v = 0; v < normals.size(); ++v) {
    EXPECT_NEAR(norm(normals[v]), 1, 1e-12);
    EXPECT_GT(dot(normals[v], cube.positions[v] - centre), 0);
  }
  // One big and one small triangle sharing vertex 0: the normal leans to the big one's.
  const std::vector<Vec3> positions = {{0, 0, 0}, {10, 0, 0}, {0, 10, 0}, {0, 0, 1}, {0, -1, 0}};
  const std::vector<Triangle> triangles = {{0, 1, 2}, {0, 3, 4}};
  const auto n = vertex_normals(positions, triangles);
  EXPECT_NEAR(n[0][2], 100 / std::hypot(100.0, 1.0), 1e-12);
  EXPECT_NEAR(n[0][0], 1 / std::hypot(100.0, 1.0), 1e-12);
  EXPECT_EQ(vertex_normals({{0, 0, 0}}, {})[0], (Vec3{0, 0, 0}));
  EXPECT_EQ(offset_along_normals(positions, n, 2)[1], (positions[1] + 2.0 * n[1]));
  EXPECT_THROW(offset_along_normals(positions, {}, 1), std::invalid_argument);
}

}  // namespace
}  // namespace spheremap
