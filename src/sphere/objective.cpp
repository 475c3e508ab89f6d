#include "objective.hpp"

#include <array>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <utility>
#include <vector>

#include "coarse_start.hpp"
#include "sphere_optimizer.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/sphere/optimize.hpp"

namespace spheremap::detail {
namespace {

SphereEnergy energy_of(MapObjective objective) {
  switch (objective) {
    case MapObjective::kArea: return SphereEnergy::kLogAreaRatio;
    case MapObjective::kConformal: return SphereEnergy::kConformal;
    case MapObjective::kBalanced:
    case MapObjective::kPaper: break;
  }
  return SphereEnergy::kSymmetricDirichlet;
}

// One stage of an optimization: the weights of its energy's second term (SphereOptimizeOptions).
struct Stage {
  double shape_weight = kShapeWeight;
  double collapse_barrier_weight = kCollapseBarrierWeight;
  double collapse_threshold = 0;
};

// The stages of each energy, each from where the last stopped.
// - area: shape weights 0.1, 0.03, 0.01; the first always runs, each later one only while the map misses
//   the area goal (below): a smaller weight lets the triangles shear further towards equal areas, at a
//   cost in angles, on the meshes that need it, and leaves the others' maps as the first weight makes them.
// - conformal: the power-law collapse barrier (which keeps the first steps away from the floor), then
//   the barrier that acts only below 2e-6 of a triangle's share, twice the certificate's collapse floor,
//   so that compressed limbs may go down to it, with weight 1e4 so that they do not go through it.
std::vector<Stage> stages_of(SphereEnergy energy) {
  switch (energy) {
    case SphereEnergy::kLogAreaRatio: return {Stage{}, Stage{0.03}, Stage{0.01}};
    case SphereEnergy::kConformal: return {Stage{}, Stage{kShapeWeight, 1e4, 2e-6}};
    case SphereEnergy::kSymmetricDirichlet: break;
  }
  return {Stage{}};
}

// Issue 26's goal for the area objective: mean |ln area ratio| <= 0.15 and octant RMS <= 1.5%, with the
// definitions of metrics/distortion (which this layer may not include): per triangle of non-zero area,
// its share of the sphere over its share of the surface; octants of the globe (the superposed map) by
// the sign of each corner sum's coordinates, weighted by surface area.
constexpr double kAreaGoalLogRatio = 0.15;
constexpr double kAreaRelativeTolerance = 1e-4;
// Where a later stage may follow: the tails of the stages it replaced were long and slow (5hr7: 35 steps
// from 1e-3 to 1e-4, 3% of the energy, before a stage that lowered it by two thirds).
constexpr double kAreaLooseTolerance = 1e-3;
constexpr double kAreaGoalOctantRms = 1.5;
// A large mesh whose start's mean |ln area ratio| is above this gets a coarse start (coarse_start.hpp):
// areas that far off are off over whole regions (the dumbbell's two bulbs: 3.5, 18 steps from the paper's
// map, 6 from the coarse start), which the coarse mesh moves in cheap steps; nearer, the distortion is
// mostly the triangles' own (5hr7's surface: 0.32, and 21 steps from a coarse start instead of 18).
constexpr double kCoarseStartLogRatio = 0.5;

// The area figures of `finished`, as the goal's definitions: mean |ln area ratio| and octant RMS (%).
struct AreaFigures {
  double mean_log_ratio = 0, octant_rms = 0;
};

AreaFigures area_figures(const Mesh& mesh, const Finished& finished) {
  double total = 0;
  for (const auto& t : mesh.triangles)
    total += triangle_area(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
  if (!(total > 0)) return {};
  double log_sum = 0;
  std::size_t counted = 0;
  std::array<double, 8> octant{};
  for (std::size_t i = 0; i < mesh.triangles.size(); ++i) {
    const auto& t = mesh.triangles[i];
    const double area = triangle_area(mesh.positions[t[0]], mesh.positions[t[1]], mesh.positions[t[2]]);
    const Vec3 centre = finished.sphere[t[0]] + finished.sphere[t[1]] + finished.sphere[t[2]];
    octant[(centre[0] < 0 ? 1 : 0) + (centre[1] < 0 ? 2 : 0) + (centre[2] < 0 ? 4 : 0)] += area;
    if (!(area > 0)) continue;
    const double ratio = (std::abs(finished.solid_angles[i]) / (4 * std::numbers::pi)) / (area / total);
    log_sum += std::abs(std::log(std::max(ratio, std::numeric_limits<double>::min())));
    ++counted;
  }
  double squared = 0;
  for (const double a : octant) squared += (100 * a / total - 12.5) * (100 * a / total - 12.5);
  return {log_sum / static_cast<double>(std::max<std::size_t>(counted, 1)), std::sqrt(squared / 8)};
}

bool area_goal_met(const Mesh& mesh, const Finished& finished) {
  const auto figures = area_figures(mesh, finished);
  return figures.mean_log_ratio <= kAreaGoalLogRatio && figures.octant_rms <= kAreaGoalOctantRms;
}

}  // namespace

void optimize_for_objective(const Mesh& mesh, InputStars& input, std::int32_t north, std::int32_t south,
                            const MapOptions& options, Finished& finished, ObjectiveReport& report, StageTimer& timer) {
  report = ObjectiveReport{};
  report.objective = options.objective;
  if (options.objective == MapObjective::kPaper) return;
  report.energy = energy_of(options.objective);
  if (!finished.certificate.certified()) {
    report.outcome = ObjectiveOutcome::kStartNotCertified;
    timer.lap("objective");
    return;
  }
  // Back to the frame of the construction (poles at ±z), where the optimization keeps them.
  const auto undo = transposed(finished.superposition.rotation);
  std::vector<Vec3> sphere(finished.sphere.size());
  for (std::size_t v = 0; v < sphere.size(); ++v) sphere[v] = normalized(rotate(undo, finished.sphere[v]));
  std::vector<char> fixed(sphere.size(), 0);
  fixed[north] = fixed[south] = 1;
  SphereOptimizeOptions optimize;
  optimize.energy = report.energy;
  // The area energy's last steps before the default tolerance (1e-6) each lowered it by a few millionths
  // and left the area figures as they were (bunny: 45 of its 59 steps, mean |ln area ratio| 0.0813 ->
  // 0.0810): its stages stop once a step gains less than 1e-4 of the energy.
  if (report.energy == SphereEnergy::kLogAreaRatio) optimize.relative_tolerance = kAreaRelativeTolerance;
  MapOptions plain = options;
  plain.repair = false;  // an optimized map that does not certify is dropped, not untangled
  const auto stages = stages_of(report.energy);
  report.outcome = ObjectiveOutcome::kResultNotCertified;
  // One optimizer for all stages: the Hessian's pattern and CHOLMOD's symbolic analysis are the same.
  SphereOptimizer optimizer(mesh.positions, mesh.triangles, fixed, optimize);
  const bool area = report.energy == SphereEnergy::kLogAreaRatio;
  // The energy of the start, when a coarse start replaces it (the report compares with the paper's map).
  double start_energy = -1;
  if (area && static_cast<std::int64_t>(mesh.vertex_count()) >= kCoarseStartMinVertices &&
      area_figures(mesh, finished).mean_log_ratio > kCoarseStartLogRatio) {
    SphereOptimizeOptions first = optimize;
    first.shape_weight = stages.front().shape_weight;
    first.relative_tolerance = stages.size() > 1 ? kAreaLooseTolerance : kAreaRelativeTolerance;
    first.max_iterations = options.objective_max_iterations;
    auto coarse_map = sphere;
    CoarseStart coarse;
    if (coarse_start(mesh, coarse_map, north, south, first, coarse)) {
      const double before = optimizer.energy(sphere);
      if (optimizer.energy(coarse_map) < before) {
        sphere.swap(coarse_map);
        start_energy = before;
        report.coarse_vertices = coarse.coarse_vertices;
        report.coarse_levels = coarse.levels;
        report.coarse_iterations = coarse.iterations;
      }
    }
  }
  // An area stage that a later one may follow first runs to a loose tolerance; if its map meets the goal it
  // runs on to the tight one (below), else the next stage takes over from there.
  bool resumed = false;
  std::size_t stage = 0;
  for (int run = 0; stage < stages.size(); ++run) {
    optimize.shape_weight = stages[stage].shape_weight;
    optimize.collapse_barrier_weight = stages[stage].collapse_barrier_weight;
    optimize.collapse_threshold = stages[stage].collapse_threshold;
    optimize.max_iterations = options.objective_max_iterations - report.optimization.iterations;
    const bool loose = area && !resumed && stage + 1 < stages.size();
    if (area) optimize.relative_tolerance = loose ? kAreaLooseTolerance : kAreaRelativeTolerance;
    if (run > 0 && optimize.max_iterations <= 0) break;
    SphereOptimizeReport step;
    try {
      step = optimizer.run(sphere, optimize);
    } catch (const std::invalid_argument&) {
      // Rotating back rounded a certified but nearly flat triangle to a non-positive orientation.
      if (run == 0) report.outcome = ObjectiveOutcome::kStartNotCertified;
      break;
    }
    auto candidate = finish_map(mesh, input, sphere, plain);
    if (!candidate.certificate.certified()) {  // the last certified stage's map stays
      if (run == 0) report.optimization = step;
      break;
    }
    finished = std::move(candidate);
    report.outcome = ObjectiveOutcome::kOptimized;
    const double before = run > 0             ? report.optimization.energy_before
                          : start_energy >= 0 ? start_energy
                                              : step.energy_before;
    step.iterations += report.optimization.iterations;
    step.factorizations += report.optimization.factorizations;
    report.optimization = step;
    report.optimization.energy_before = before;
    report.stages = static_cast<int>(stage) + 1;
    if (area) report.shape_weight = stages[stage].shape_weight;
    const bool met = area && area_goal_met(mesh, finished);
    resumed = met && loose && step.stop_reason == OptimizeStop::kConverged;
    if (met && !resumed) break;
    if (!resumed) ++stage;  // else the same stage again, to the tight tolerance
  }
  timer.lap("objective");
}

}  // namespace spheremap::detail
