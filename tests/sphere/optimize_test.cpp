// Optimization on the sphere that never leaves the valid maps: the energy's derivatives, the descent,
// the barrier, fixed vertices, and the refusal of an invalid start.
#include "spheremap/sphere/optimize.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <random>
#include <stdexcept>
#include <string>

#include "../../src/sphere/triangle_energy.hpp"
#include "spheremap/geometry/predicates.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/shapes/shapes.hpp"
#include "spheremap/sphere/certify.hpp"

namespace spheremap {
namespace {

Vec3 unit(double x, double y, double z) { return normalized(Vec3{x, y, z}); }

TEST(TriangleEnergy, GradientAndHessianMatchFiniteDifferences) {
  const Vec3 ra{0, 0, 0}, rb{1, 0.1, 0}, rc{0.3, 0.8, 0.1};
  const auto rest = detail::rest_triangle(ra, rb, rc, 0.02, 1e-3);
  const Vec3 a = unit(0.1, 0.05, 1), b = unit(0.25, 0.02, 1), c = unit(0.12, 0.22, 1);
  detail::Vector9 gradient;
  detail::Matrix9 hessian;
  const double value = detail::symmetric_dirichlet(rest, a, b, c, gradient, hessian);
  EXPECT_DOUBLE_EQ(value, detail::symmetric_dirichlet(rest, a, b, c));
  auto energy_at = [&](const detail::Vector9& x, detail::Vector9* g) {
    const Vec3 p{x[0], x[1], x[2]}, q{x[3], x[4], x[5]}, r{x[6], x[7], x[8]};
    detail::Matrix9 h;
    detail::Vector9 local;
    const double e = detail::symmetric_dirichlet(rest, p, q, r, local, h);
    if (g) *g = local;
    return e;
  };
  detail::Vector9 x;
  x << a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2];
  const double step = 1e-6;
  for (int i = 0; i < 9; ++i) {
    detail::Vector9 up = x, down = x;
    up[i] += step;
    down[i] -= step;
    detail::Vector9 g_up, g_down;
    const double numeric = (energy_at(up, &g_up) - energy_at(down, &g_down)) / (2 * step);
    EXPECT_NEAR(gradient[i], numeric, 1e-5 * std::max(1.0, std::abs(numeric))) << "gradient " << i;
    const detail::Vector9 column = (g_up - g_down) / (2 * step);
    for (int j = 0; j < 9; ++j)
      EXPECT_NEAR(hessian(j, i), column[j], 1e-4 * std::max(1.0, hessian.cwiseAbs().maxCoeff()))
          << "hessian " << j << "," << i;
  }
}

TEST(TriangleEnergy, BarrierAndMinimum) {
  // An equilateral rest triangle of area A and its image of the same shape and area: the minimum, 4A.
  const Vec3 a = unit(0, 0, 1), b = unit(0.01, 0, 1), c = unit(0.005, 0.005 * std::sqrt(3.0), 1);
  const double area = detail::half_det(a, b, c);
  const auto rest = detail::rest_triangle({0, 0, 0}, {1, 0, 0}, {0.5, std::sqrt(3.0) / 2, 0}, area, 1e-3);
  EXPECT_NEAR(detail::symmetric_dirichlet(rest, a, b, c), 4 * area, 1e-4 * area);
  // Folded or flat: +inf.
  EXPECT_EQ(detail::symmetric_dirichlet(rest, a, c, b), INFINITY);
  EXPECT_EQ(detail::symmetric_dirichlet(rest, a, a, b), INFINITY);
  // half_det keeps its relative precision on tiny triangles (det of three nearly equal unit vectors).
  const Vec3 p = unit(0.3, 0.4, 0.5), q = normalized(p + Vec3{1e-9, 0, 0}), r = normalized(p + Vec3{0, 1e-9, 0});
  const double exact = 0.5 * dot(p, cross(q - p, r - p));
  EXPECT_NEAR(detail::half_det(p, q, r), exact, 1e-6 * std::abs(exact));
  EXPECT_GT(detail::half_det(p, q, r), 0);
}

// An icosphere seen from an interior point off its centre: a valid map whose areas vary tenfold.
std::vector<Vec3> squashed(const Mesh& sphere, double shift) {
  std::vector<Vec3> points;
  for (const auto& p : sphere.positions) points.push_back(normalized(p + Vec3{0, 0, shift}));
  return points;
}

TEST(OptimizeOnSphere, StaysValidAndEqualizesAreas) {
  const Mesh ico = make_icosphere(3);
  auto points = squashed(ico, 0.8);
  const auto before = certify_sphere_map(ico, points);
  ASSERT_TRUE(before.certified());
  std::vector<char> fixed(points.size(), 0);
  fixed[0] = 1;
  const Vec3 pinned = points[0];
  const auto report = optimize_on_sphere(ico.positions, ico.triangles, points, fixed);
  EXPECT_GT(report.iterations, 0);
  EXPECT_LT(report.energy_after, report.energy_before);
  EXPECT_EQ(points[0], pinned);
  const auto after = certify_sphere_map(ico, points);
  EXPECT_TRUE(after.certified());
  EXPECT_LT(before.min_area_ratio, 0.35);
  EXPECT_GT(after.min_area_ratio, 0.9);  // the rest is the round sphere itself: equal areas are reachable
  for (const auto& p : points) EXPECT_NEAR(norm(p), 1, 1e-14);
}

TEST(OptimizeOnSphere, SameResultOnAnyNumberOfThreads) {
  // 5,120 triangles: three chunks of the parallel loops (2,048 triangles each).
  const Mesh ico = make_icosphere(4);
  std::vector<Vec3> reference;
  for (const int threads : {1, 2, 3}) {
    auto points = squashed(ico, 0.5);
    std::vector<char> fixed(points.size(), 0);
    fixed[0] = 1;
    SphereOptimizeOptions options;
    options.energy = SphereEnergy::kLogAreaRatio;
    options.max_iterations = 4;
    options.threads = threads;
    const auto report = optimize_on_sphere(ico.positions, ico.triangles, points, fixed, options);
    EXPECT_EQ(report.iterations, 4);
    if (reference.empty())
      reference = points;
    else
      EXPECT_EQ(points, reference) << threads << " threads";
  }
}

TEST(TriangleEnergy, EquilateralHalfDetHasTheSolidAngle) {
  // The equilateral spherical triangle whose ½·det equilateral_half_det gives has the solid angle asked
  // for, from tiny triangles (a 1e-20 share of the sphere) to nearly a hemisphere.
  for (const double omega : {1e-20, 1e-12, 1e-6, 1e-3, 0.1, 1.0, 3.0, 6.0}) {
    const double half_det = detail::equilateral_half_det(omega);
    // Corners at angular distance ρ from +z, 120° apart: half_det = (3√3/4) sin²ρ cos ρ; find ρ by bisection.
    double low = 0, high = std::numbers::pi / 2;
    const double peak = std::atan(std::sqrt(2.0));    // the maximum of sin²ρ cos ρ: large triangles lie beyond it
    const bool large = omega > std::numbers::pi / 2;  // the solid angle at the peak
    (large ? low : high) = peak;
    for (int i = 0; i < 200; ++i) {
      const double middle = 0.5 * (low + high);
      const double value = 0.75 * std::sqrt(3.0) * std::sin(middle) * std::sin(middle) * std::cos(middle);
      ((value < half_det) != large ? low : high) = middle;
    }
    const double rho = 0.5 * (low + high);
    Vec3 corner[3];
    for (int k = 0; k < 3; ++k) {
      const double phi = 2 * std::numbers::pi * k / 3;
      corner[k] = {std::sin(rho) * std::cos(phi), std::sin(rho) * std::sin(phi), std::cos(rho)};
    }
    // Van Oosterom & Strackee, the determinant from edge vectors (precise for tiny triangles).
    const double solid =
        2 * std::atan2(dot(corner[0], cross(corner[1] - corner[0], corner[2] - corner[0])),
                       1 + dot(corner[0], corner[1]) + dot(corner[1], corner[2]) + dot(corner[2], corner[0]));
    EXPECT_NEAR(solid, omega, 1e-8 * omega) << omega;
  }
}

TEST(OptimizeOnSphere, LiftsCollapsedTriangles) {
  // A conformal squeeze towards +z (tan(θ/2) scaled by 1e-4): valid, but the north keeps 1e-8 of its share.
  const Mesh ico = make_icosphere(2);
  std::vector<Vec3> points;
  for (const auto& p : ico.positions) {
    const double theta = std::atan2(std::hypot(p[0], p[1]), p[2]), phi = std::atan2(p[1], p[0]);
    const double squeezed = 2 * std::atan(1e-4 * std::tan(theta / 2));
    points.push_back({std::sin(squeezed) * std::cos(phi), std::sin(squeezed) * std::sin(phi), std::cos(squeezed)});
  }
  const auto before = certify_sphere_map(ico, points);
  ASSERT_EQ(before.folded, 0);
  ASSERT_GT(before.collapsed, 0);
  const auto report = optimize_on_sphere(ico.positions, ico.triangles, points, std::vector<char>(points.size(), 0));
  EXPECT_TRUE(certify_sphere_map(ico, points).certified())
      << to_string(report.stop_reason) << " after " << report.iterations;
}

TEST(OptimizeOnSphere, RefusesAnInvalidStart) {
  const Mesh ico = make_icosphere(1);
  auto points = ico.positions;
  points[0] = -1.0 * points[0];  // to the antipode: every triangle around it folds
  std::vector<char> fixed(points.size(), 0);
  EXPECT_THROW(optimize_on_sphere(ico.positions, ico.triangles, points, fixed), std::invalid_argument);
  EXPECT_THROW(optimize_on_sphere(ico.positions, ico.triangles, points, std::vector<char>(3, 0)),
               std::invalid_argument);
}

TEST(OptimizeOnSphere, RestSizeFromTinyToHugeGivesTheSameMap) {
  // The energy compares shapes, not sizes: a surface scaled by a power of two gives the same map to the
  // bit, even where its areas would overflow (2^1000: coordinates of 1e301) or underflow (2^-1000).
  const Mesh ico = make_icosphere(2);
  std::vector<char> fixed(ico.positions.size(), 0);
  fixed[0] = 1;
  SphereOptimizeOptions options;
  options.energy = SphereEnergy::kLogAreaRatio;
  const auto map_with = [&](double scale) {
    std::vector<Vec3> rest;
    for (const auto& p : ico.positions) rest.push_back(scale * p);
    rest[5] = 1.5 * rest[5];  // a bump, so that the rest areas are not already equal
    auto points = squashed(ico, 0.5);
    const auto report = optimize_on_sphere(rest, ico.triangles, points, fixed, options);
    EXPECT_LT(report.energy_after, report.energy_before) << scale;
    EXPECT_TRUE(certify_sphere_map(ico, points).certified()) << scale;
    return points;
  };
  const auto reference = map_with(1);
  EXPECT_EQ(map_with(std::ldexp(1.0, 1000)), reference);
  EXPECT_EQ(map_with(std::ldexp(1.0, -1000)), reference);
  const auto huge = map_with(1e305);  // not a power of two: equal up to the rounding of the scaled input
  for (std::size_t v = 0; v < huge.size(); ++v) EXPECT_LT(norm(huge[v] - reference[v]), 1e-9) << v;
}

TEST(OptimizeOnSphere, RefusesRestPositionsThatAreNotFinite) {
  const Mesh ico = make_icosphere(1);
  auto rest = ico.positions;
  rest[3][1] = NAN;
  auto points = ico.positions;
  try {
    optimize_on_sphere(rest, ico.triangles, points, std::vector<char>(points.size(), 0));
    FAIL() << "no exception";
  } catch (const std::invalid_argument& error) {
    EXPECT_NE(std::string(error.what()).find("rest position 3 is not finite"), std::string::npos) << error.what();
  }
}

TEST(OptimizeOnSphere, NothingFreeIsAlreadyOptimal) {
  const Mesh ico = make_icosphere(1);
  auto points = ico.positions;
  const auto report = optimize_on_sphere(ico.positions, ico.triangles, points, std::vector<char>(points.size(), 1));
  EXPECT_EQ(report.iterations, 0);
  EXPECT_EQ(points, ico.positions);
}

}  // namespace
}  // namespace spheremap
