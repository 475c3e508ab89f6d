// The objectives of a certified map (MapOptions::objective): the new energies' derivatives, each energy
// lowered on a valid map without leaving the valid maps, and map_to_sphere's optimized maps certified,
// with the distortion each objective is for lowered, on an icosphere with a perturbed rest shape and on
// hard cases.
#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <numbers>
#include <string>
#include <vector>

#include "../../src/sphere/sphere_optimizer.hpp"
#include "../../src/sphere/triangle_energy.hpp"
#include "spheremap/error.hpp"
#include "spheremap/geometry/predicates.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/metrics/distortion.hpp"
#include "spheremap/pipeline/map_job.hpp"
#include "spheremap/shapes/hard_cases.hpp"
#include "spheremap/shapes/shapes.hpp"
#include "spheremap/sphere/certify.hpp"
#include "spheremap/sphere/map.hpp"
#include "spheremap/sphere/optimize.hpp"
#include "spheremap/topology/prepare.hpp"

namespace spheremap {
namespace {

Vec3 unit(double x, double y, double z) { return normalized(Vec3{x, y, z}); }

// Central differences of the energy and of its gradient against the analytic gradient and Hessian.
void check_derivatives(SphereEnergy energy, detail::SecondTerm w, const detail::RestTriangle& rest, const Vec3& a,
                       const Vec3& b, const Vec3& c) {
  detail::Vector9 gradient;
  detail::Matrix9 hessian;
  const double value = detail::triangle_energy(energy, w, rest, a, b, c, gradient, hessian);
  EXPECT_NEAR(value, detail::triangle_energy(energy, w, rest, a, b, c), 1e-14 * std::abs(value)) << to_string(energy);
  auto at = [&](const detail::Vector9& x, detail::Vector9& g) {
    detail::Matrix9 h;
    return detail::triangle_energy(energy, w, rest, {x[0], x[1], x[2]}, {x[3], x[4], x[5]}, {x[6], x[7], x[8]}, g, h);
  };
  detail::Vector9 x;
  x << a[0], a[1], a[2], b[0], b[1], b[2], c[0], c[1], c[2];
  const double step = 1e-7;
  const double gradient_scale = std::max(1e-300, gradient.cwiseAbs().maxCoeff());
  const double hessian_scale = std::max(1e-300, hessian.cwiseAbs().maxCoeff());
  for (int i = 0; i < 9; ++i) {
    detail::Vector9 up = x, down = x, g_up, g_down;
    up[i] += step;
    down[i] -= step;
    const double numeric = (at(up, g_up) - at(down, g_down)) / (2 * step);
    EXPECT_NEAR(gradient[i], numeric, 1e-5 * gradient_scale) << to_string(energy) << " gradient " << i;
    const detail::Vector9 column = (g_up - g_down) / (2 * step);
    for (int j = 0; j < 9; ++j)
      EXPECT_NEAR(hessian(j, i), column[j], 1e-5 * hessian_scale) << to_string(energy) << " hessian " << j << "," << i;
  }
}

TEST(ObjectiveEnergy, GradientsAndHessiansMatchFiniteDifferences) {
  const auto rest = detail::rest_triangle({0, 0, 0}, {1, 0.1, 0}, {0.3, 0.8, 0.1}, 0.02, 1e-3);
  // A triangle larger than its target, one smaller (both sides of ln(S/A) = 0 and of its convexity).
  const Vec3 a = unit(0.1, 0.05, 1), b = unit(0.25, 0.02, 1), c = unit(0.12, 0.22, 1);
  const Vec3 d = unit(0.1, 0.05, 1), e = unit(0.13, 0.06, 1), f = unit(0.11, 0.09, 1);
  for (const auto energy : {SphereEnergy::kLogAreaRatio, SphereEnergy::kConformal})
    for (const double w : {energy == SphereEnergy::kConformal ? kCollapseBarrierWeight : kShapeWeight, 0.01}) {
      check_derivatives(energy, w, rest, a, b, c);
      check_derivatives(energy, w, rest, d, e, f);
    }
}

TEST(ObjectiveEnergy, ThresholdedCollapseBarrier) {
  const Vec3 a = unit(0.1, 0.05, 1), b = unit(0.13, 0.06, 1), c = unit(0.11, 0.09, 1);
  const double s = detail::half_det(a, b, c);
  const auto rest = detail::rest_triangle({0, 0, 0}, {1, 0.1, 0}, {0.3, 0.8, 0.1}, 0.02, 1e-3);
  // Below the threshold (S/A at 0.4 of it): the barrier's derivatives, and it adds to the MIPS term.
  const detail::SecondTerm below(1e4, s / (0.4 * rest.area));
  check_derivatives(SphereEnergy::kConformal, below, rest, a, b, c);
  const double mips = detail::conformal(rest, detail::SecondTerm(0, 1), a, b, c);
  EXPECT_GT(detail::conformal(rest, below, a, b, c), mips + 1e3 * rest.area);
  // Above it: nothing but the MIPS term, and a triangle at the threshold costs what it would without.
  const detail::SecondTerm above(1e4, s / (2.5 * rest.area));
  EXPECT_EQ(detail::conformal(rest, above, a, b, c), mips);
  check_derivatives(SphereEnergy::kConformal, above, rest, a, b, c);
  EXPECT_NEAR(detail::conformal(rest, detail::SecondTerm(1e4, s / rest.area * (1 - 1e-9)), a, b, c), mips,
              1e-12 * mips);
  EXPECT_EQ(detail::conformal(rest, below, a, c, b), INFINITY);  // folded
}

TEST(ObjectiveEnergy, MinimaAndBarriers) {
  // An equilateral rest triangle and its image of the same shape and area (the target).
  const Vec3 a = unit(0, 0, 1), b = unit(0.01, 0, 1), c = unit(0.005, 0.005 * std::sqrt(3.0), 1);
  const double area = detail::half_det(a, b, c);
  const auto rest = detail::rest_triangle({0, 0, 0}, {1, 0, 0}, {0.5, std::sqrt(3.0) / 2, 0}, area, 1e-3);
  // ln(S/A) = 0 and N/S = 2 at a similarity: the area energy is the shape term's 2·w·A.
  EXPECT_NEAR(detail::log_area_ratio(rest, kShapeWeight, a, b, c), 2 * kShapeWeight * area, 1e-4 * area);
  // The conformal energy is 2A at any similarity, whatever its scale (but for the collapse barrier).
  const Vec3 b2 = unit(0.001, 0, 1), c2 = unit(0.0005, 0.0005 * std::sqrt(3.0), 1);
  EXPECT_NEAR(detail::conformal(rest, kCollapseBarrierWeight, a, b, c), 2 * area, 1e-4 * area);
  const double small = detail::half_det(a, b2, c2);
  EXPECT_NEAR(detail::conformal(rest, kCollapseBarrierWeight, a, b2, c2),
              2 * area + kCollapseBarrierWeight * area * std::pow(area / small, 2), 1e-3 * area);
  // A sheared image of the same area costs more.
  const Vec3 sheared = unit(0.015, 0.005 * std::sqrt(3.0), 1);
  EXPECT_GT(detail::conformal(rest, kCollapseBarrierWeight, a, b, sheared), 2.1 * area);
  for (const auto energy : {SphereEnergy::kLogAreaRatio, SphereEnergy::kConformal}) {
    EXPECT_EQ(detail::triangle_energy(energy, kShapeWeight, rest, a, c, b), INFINITY) << to_string(energy);  // folded
    EXPECT_EQ(detail::triangle_energy(energy, kShapeWeight, rest, a, a, b), INFINITY) << to_string(energy);  // flat
  }
}

// Mean |ln ratio| of the triangles' shares of the sphere to their shares of the surface.
double mean_log_area_ratio(const Mesh& surface, const std::vector<Vec3>& sphere) {
  double total = 0, sum = 0;
  for (const auto& t : surface.triangles)
    total += triangle_area(surface.positions[t[0]], surface.positions[t[1]], surface.positions[t[2]]);
  for (const auto& t : surface.triangles) {
    const double share =
        triangle_area(surface.positions[t[0]], surface.positions[t[1]], surface.positions[t[2]]) / total;
    sum += std::abs(
        std::log(signed_solid_angle(sphere[t[0]], sphere[t[1]], sphere[t[2]]) / (4 * std::numbers::pi) / share));
  }
  return sum / static_cast<double>(surface.triangles.size());
}

// Mean |angle on the sphere's chord triangles - angle on the surface|, in degrees.
double mean_angle_error(const Mesh& surface, const std::vector<Vec3>& sphere) {
  auto angle = [](const Vec3& p, const Vec3& q, const Vec3& r) {
    return std::atan2(norm(cross(q - p, r - p)), dot(q - p, r - p));
  };
  double sum = 0;
  for (const auto& t : surface.triangles)
    for (int k = 0; k < 3; ++k) {
      const auto i = t[k], j = t[(k + 1) % 3], l = t[(k + 2) % 3];
      sum += std::abs(angle(sphere[i], sphere[j], sphere[l]) -
                      angle(surface.positions[i], surface.positions[j], surface.positions[l]));
    }
  return sum / (3.0 * static_cast<double>(surface.triangles.size())) * 180 / std::numbers::pi;
}

// A perturbed, stretched icosphere mapped by the round icosphere seen from an interior point off its
// centre: a valid start far from every optimum (areas tenfold apart, angles sheared).
TEST(ObjectiveOptimization, EachEnergyDescendsAndStaysValid) {
  const Mesh ico = make_icosphere(3);
  Mesh rest = perturb_vertices(ico, 0.15, 7);
  for (auto& p : rest.positions) p = Vec3{2.5 * p[0], p[1], 0.6 * p[2]};
  for (const auto energy : {SphereEnergy::kSymmetricDirichlet, SphereEnergy::kLogAreaRatio, SphereEnergy::kConformal}) {
    std::vector<Vec3> points;
    for (const auto& p : ico.positions) points.push_back(normalized(p + Vec3{0, 0, 0.6}));
    const auto start = points;
    std::vector<char> fixed(points.size(), 0);
    fixed[0] = 1;
    SphereOptimizeOptions options;
    options.energy = energy;
    const auto report = optimize_on_sphere(rest.positions, rest.triangles, points, fixed, options);
    EXPECT_GT(report.iterations, 0) << to_string(energy);
    EXPECT_LT(report.energy_after, report.energy_before) << to_string(energy);
    EXPECT_TRUE(certify_sphere_map(rest, points).certified()) << to_string(energy);
    EXPECT_EQ(points[0], start[0]) << to_string(energy);
    for (const auto& p : points) EXPECT_NEAR(norm(p), 1, 1e-14);
    if (energy == SphereEnergy::kLogAreaRatio)
      EXPECT_LT(mean_log_area_ratio(rest, points), 0.2 * mean_log_area_ratio(rest, start));
    if (energy == SphereEnergy::kConformal)
      EXPECT_LT(mean_angle_error(rest, points), 0.5 * mean_angle_error(rest, start));
  }
}

Mesh prepared(const Mesh& mesh) { return prepare_mesh(mesh).mesh; }

// The area term is concave in S above S = eA: with its exact curvature (projected to 0) a triangle far
// too large on the sphere asks for a step as long as its shape term's curvature allows, and the first
// steps from the paper's map were cut to a few thousandths (the 3,002-vertex dumbbell took 36 steps to
// converge at the first shape weight). The secant curvature asks each triangle for its target area:
// full steps from the start.
// The area energy optimized from the paper's map of the 3,002-vertex dumbbell, its poles fixed.
struct AreaRun {
  Mesh mesh;
  std::vector<Vec3> points;
  SphereOptimizeReport report;
};

AreaRun area_run_from_the_papers_map() {
  AreaRun run{prepared(make_dumbbell(3.0, 0.4, 60, 50)), {}, {}};
  const SphereMap paper = map_to_sphere(run.mesh);
  EXPECT_TRUE(paper.certificate.certified());
  run.points = paper.sphere;
  std::vector<char> fixed(run.points.size(), 0);
  fixed[paper.poles.north] = fixed[paper.poles.south] = 1;
  SphereOptimizeOptions options;
  options.energy = SphereEnergy::kLogAreaRatio;
  run.report = optimize_on_sphere(run.mesh.positions, run.mesh.triangles, run.points, fixed, options);
  return run;
}

TEST(ObjectiveOptimization, AreaStepsFromThePapersMapAreFullSteps) {
  const AreaRun run = area_run_from_the_papers_map();
  EXPECT_EQ(run.report.stop_reason, OptimizeStop::kConverged);
  EXPECT_LE(run.report.iterations, 16);
  EXPECT_TRUE(certify_sphere_map(run.mesh, run.points).certified());
  EXPECT_LT(mean_log_area_ratio(run.mesh, run.points), 0.2);
}

// Far from the minimum the exact Hessian is not positive definite: it is tried only after a step that
// gained less than 5% of the energy, so that the steps from the paper's map do not each spend a
// factorization on a try that fails (before that rule this run took 21 factorizations for 16 steps; now
// 16 for 15).
TEST(ObjectiveOptimization, ExactHessianIsTriedOnlyNearTheMinimum) {
  const AreaRun run = area_run_from_the_papers_map();
  EXPECT_EQ(run.report.stop_reason, OptimizeStop::kConverged);
  EXPECT_GE(run.report.factorizations, run.report.iterations);
  EXPECT_LE(run.report.factorizations, run.report.iterations + 2);
  EXPECT_TRUE(certify_sphere_map(run.mesh, run.points).certified());
}

// The area energy's full steps fall short where the paper's map crushes triangles (a 1-D Newton step in
// S takes a triangle at e^-3 of its target only to e^-1.6): a full step is doubled (up to 8 times) while
// that lowers the energy further and keeps the map valid.
TEST(ObjectiveOptimization, AreaFullStepsAreLengthened) {
  // A 4-segment U tube: its paper's map crushes the limbs. 69 steps over its three stages with full
  // steps as they come, 46 with the doubling.
  MapOptions options;
  options.objective = MapObjective::kArea;
  const SphereMap map = map_to_sphere(prepared(make_bent_tube(TubeBend::kU, 4, 30)), options);
  const auto& objective = map.diagnostics.objective;
  EXPECT_EQ(objective.outcome, ObjectiveOutcome::kOptimized);
  EXPECT_TRUE(map.certificate.certified());
  EXPECT_GT(objective.optimization.iterations, 0);
  EXPECT_LE(objective.optimization.iterations, 55);
}

// The objective's stages share one optimizer (its pattern and CHOLMOD's analysis): two runs at two
// shape weights give the points of two separate optimize_on_sphere calls, to the bit, and the same reports.
TEST(ObjectiveOptimization, OneOptimizerForSeveralStagesMatchesSeparateRuns) {
  const Mesh mesh = prepared(make_dumbbell(3.0, 0.4, 24, 16));
  const SphereMap paper = map_to_sphere(mesh);
  ASSERT_TRUE(paper.certificate.certified());
  std::vector<char> fixed(paper.sphere.size(), 0);
  fixed[paper.poles.north] = fixed[paper.poles.south] = 1;
  SphereOptimizeOptions first, second;
  first.energy = second.energy = SphereEnergy::kLogAreaRatio;
  second.shape_weight = 0.03;
  second.relative_tolerance = 1e-8;
  std::vector<Vec3> separate = paper.sphere, shared = paper.sphere;
  const auto a1 = optimize_on_sphere(mesh.positions, mesh.triangles, separate, fixed, first);
  const auto a2 = optimize_on_sphere(mesh.positions, mesh.triangles, separate, fixed, second);
  detail::SphereOptimizer optimizer(mesh.positions, mesh.triangles, fixed, first);
  const auto b1 = optimizer.run(shared, first);
  const auto b2 = optimizer.run(shared, second);
  EXPECT_GT(a2.iterations, 0);
  EXPECT_EQ(a1.iterations, b1.iterations);
  EXPECT_EQ(a2.iterations, b2.iterations);
  EXPECT_EQ(a2.energy_after, b2.energy_after);
  EXPECT_EQ(separate, shared);
  // A start that is not a valid map is refused on a run of a shared optimizer too.
  std::vector<Vec3> folded = paper.sphere;
  const auto& t = mesh.triangles[0];
  std::swap(folded[t[0]], folded[t[1]]);
  EXPECT_THROW(optimizer.run(folded, first), std::invalid_argument);
}

// map_to_sphere with each objective: certified, the optimization reported, and (with `distortion`) the
// distortion the objective is for lower than the paper's map's. Not on coarse meshes: the energies
// compare chord triangles, the metrics spherical ones, and a coarse conformal map has triangles so large
// on the sphere that their spherical angles are far from their chords'.
void check_objectives(const Mesh& mesh, const std::string& what, bool distortion = true) {
  const SphereMap paper = map_to_sphere(mesh);
  ASSERT_TRUE(paper.certificate.certified()) << what;
  EXPECT_EQ(paper.diagnostics.objective.outcome, ObjectiveOutcome::kNone) << what;
  for (const auto objective : {MapObjective::kArea, MapObjective::kConformal, MapObjective::kBalanced}) {
    MapOptions options;
    options.objective = objective;
    const SphereMap map = map_to_sphere(mesh, options);
    const auto& report = map.diagnostics.objective;
    const std::string name = what + " " + to_string(objective);
    EXPECT_TRUE(map.certificate.certified()) << name;
    EXPECT_EQ(report.outcome, ObjectiveOutcome::kOptimized) << name;
    EXPECT_GT(report.optimization.iterations, 0) << name;
    EXPECT_LT(report.optimization.energy_after, report.optimization.energy_before) << name;
    std::int64_t negative = 0;
    for (const auto& t : mesh.triangles)
      negative += orientation_sign(map.sphere[t[0]], map.sphere[t[1]], map.sphere[t[2]]) <= 0;
    EXPECT_EQ(negative, 0) << name;
    // The poles stayed put.
    EXPECT_NEAR(map.theta[map.poles.north], paper.theta[paper.poles.north], 1e-12) << name;
    EXPECT_NEAR(map.theta[map.poles.south], paper.theta[paper.poles.south], 1e-12) << name;
    if (!distortion) continue;
    if (objective == MapObjective::kArea)
      EXPECT_LT(mean_log_area_ratio(mesh, map.sphere), 0.5 * mean_log_area_ratio(mesh, paper.sphere)) << name;
    if (objective == MapObjective::kConformal)
      EXPECT_LT(mean_angle_error(mesh, map.sphere), 0.5 * mean_angle_error(mesh, paper.sphere)) << name;
  }
}

TEST(MapObjectives, PerturbedEllipsoid) {
  check_objectives(prepared(perturb_vertices(make_ellipsoid(3, 2.0, 1.0, 0.5), 0.05, 3)), "ellipsoid");
}

TEST(MapObjectives, Dumbbell) { check_objectives(prepared(make_dumbbell(3.0, 0.4, 24, 16)), "dumbbell"); }

TEST(MapObjectives, CoarseBentTube) {
  // A hard case: a 4-segment U tube, where the plain map and its repair collapse limbs.
  check_objectives(prepared(make_bent_tube(TubeBend::kU, 4, 30)), "U tube", false);
}

// Issue 26's goal for --objective area: mean |ln area ratio| <= 0.15 and octant RMS <= 1.5%, certified.
void expect_area_goal(const Mesh& mesh, const SphereMap& map, const std::string& name) {
  EXPECT_TRUE(map.certificate.certified()) << name;
  EXPECT_EQ(map.diagnostics.objective.outcome, ObjectiveOutcome::kOptimized) << name;
  const auto metrics = measure_distortion(mesh, map.sphere);
  EXPECT_LE(metrics.area_log_ratio_mean, 0.15) << name;
  EXPECT_LE(metrics.octant_rms_deviation_percent, 1.5) << name;
}

TEST(MapObjectives, AreaGoalMetOnAThinNeckedDumbbell) {
  // The shape term's first weight (0.1) stops at 0.154 here: a second stage at a smaller weight is needed.
  const Mesh mesh = prepared(make_dumbbell(3.0, 0.4, 60, 50));
  MapOptions options;
  options.objective = MapObjective::kArea;
  const SphereMap map = map_to_sphere(mesh, options);
  expect_area_goal(mesh, map, "dumbbell");
  EXPECT_EQ(map.diagnostics.objective.stages, 2);
  EXPECT_LT(map.diagnostics.objective.shape_weight, kShapeWeight);
  // Each stage stops once a step gains less than 1e-4 of the energy: 15 steps here; at 1e-6 25, the
  // slow tails of both stages, for the same area figures.
  EXPECT_LE(map.diagnostics.objective.optimization.iterations, 17);
}

TEST(MapObjectives, AreaStopsAtTheFirstStageWhenTheGoalIsMet) {
  // Lysozyme-like round shapes meet the goal at the first weight: no second stage changes their maps.
  const Mesh mesh = prepared(perturb_vertices(make_ellipsoid(3, 2.0, 1.0, 0.5), 0.05, 3));
  MapOptions options;
  options.objective = MapObjective::kArea;
  const SphereMap map = map_to_sphere(mesh, options);
  expect_area_goal(mesh, map, "ellipsoid");
  EXPECT_EQ(map.diagnostics.objective.stages, 1);
  EXPECT_EQ(map.diagnostics.objective.shape_weight, kShapeWeight);
}

// Shared meshes on which the first weight alone missed the area goal (coarse, or with long limbs).
class DataAreaObjective : public testing::TestWithParam<std::string> {};

TEST_P(DataAreaObjective, MeetsTheGoal) {
  const auto path = std::filesystem::path(SPHEREMAP_SHARED_DATA_DIR) / "meshes" / GetParam();
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data not found: " << path << " (skipped on purpose)";
  MapJobOptions options;
  options.map.objective = MapObjective::kArea;
  const auto result = run_map_job(path, options);
  expect_area_goal(result.prepared.mesh, result.map, GetParam());
  EXPECT_LE(result.metrics.area_log_ratio_mean, 0.15) << GetParam();
}

INSTANTIATE_TEST_SUITE_P(Data, DataAreaObjective,
                         testing::Values("gc_fox.ply", "libigl_decimated-knight.off", "libigl_horse_quad.obj",
                                         "ajc_homer.obj"));

// Issue 26's goal for --objective conformal on armadillo: mean |Δangle| <= 5°, certified (the power-law
// barrier alone stops at 6.49°: it holds every thin limb about 7 times above the collapse floor).
TEST(LongConformalObjective, ArmadilloWithinFiveDegrees) {
  const auto path = std::filesystem::path(SPHEREMAP_SHARED_DATA_DIR) / "meshes" / "libigl_armadillo.obj";
  if (!std::filesystem::exists(path)) GTEST_SKIP() << "shared data not found: " << path << " (skipped on purpose)";
  MapJobOptions options;
  options.map.objective = MapObjective::kConformal;
  const auto result = run_map_job(path, options);
  EXPECT_TRUE(result.map.certificate.certified());
  EXPECT_EQ(result.map.diagnostics.objective.outcome, ObjectiveOutcome::kOptimized);
  EXPECT_EQ(result.map.diagnostics.objective.stages, 2);
  EXPECT_LE(result.metrics.angle_distortion_mean_degrees, 5.0);
}

TEST(MapObjectives, NamesParseAndBadNamesAreRefused) {
  for (const auto objective :
       {MapObjective::kPaper, MapObjective::kArea, MapObjective::kConformal, MapObjective::kBalanced})
    EXPECT_EQ(parse_map_objective(to_string(objective)), objective);
  EXPECT_THROW(parse_map_objective("equal-area"), InputError);
}

}  // namespace
}  // namespace spheremap
