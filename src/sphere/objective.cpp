#include "objective.hpp"

#include <stdexcept>
#include <utility>
#include <vector>

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
  optimize.max_iterations = options.objective_max_iterations;
  try {
    report.optimization = optimize_on_sphere(mesh.positions, mesh.triangles, sphere, fixed, optimize);
  } catch (const std::invalid_argument&) {
    // Rotating back rounded a certified but nearly flat triangle to a non-positive orientation.
    report.outcome = ObjectiveOutcome::kStartNotCertified;
    timer.lap("objective");
    return;
  }
  MapOptions plain = options;
  plain.repair = false;  // an optimized map that does not certify is dropped, not untangled
  auto candidate = finish_map(mesh, input, std::move(sphere), plain);
  if (candidate.certificate.certified()) {
    finished = std::move(candidate);
    report.outcome = ObjectiveOutcome::kOptimized;
  } else {
    report.outcome = ObjectiveOutcome::kResultNotCertified;
  }
  timer.lap("objective");
}

}  // namespace spheremap::detail
