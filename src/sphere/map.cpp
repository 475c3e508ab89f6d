#include "spheremap/sphere/map.hpp"

#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>
#include <utility>

#include <fmt/format.h>

#include "../util/stage_timer.hpp"
#include "finish.hpp"
#include "harmonic.hpp"
#include "objective.hpp"
#include "planar.hpp"
#include "reweighting.hpp"
#include "spheremap/error.hpp"
#include "spheremap/geometry/superposition.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/sphere/fallback.hpp"
#include "spheremap/sphere/poles.hpp"
#include "spheremap/topology/connectivity.hpp"
#include "spheremap/topology/subdivide.hpp"

namespace spheremap {

const char* to_string(Weights weights) {
  switch (weights) {
    case Weights::kUniform: return "uniform";
    case Weights::kCotangent: return "cotan";
    case Weights::kMeanValue: return "mean-value";
  }
  return "?";
}
const char* to_string(MapObjective objective) {
  switch (objective) {
    case MapObjective::kPaper: return "paper";
    case MapObjective::kArea: return "area";
    case MapObjective::kConformal: return "conformal";
    case MapObjective::kBalanced: return "balanced";
  }
  return "?";
}
const char* to_string(ObjectiveOutcome outcome) {
  switch (outcome) {
    case ObjectiveOutcome::kNone: return "";
    case ObjectiveOutcome::kOptimized: return "optimized";
    case ObjectiveOutcome::kStartNotCertified: return "start-not-certified";
    case ObjectiveOutcome::kResultNotCertified: return "result-not-certified";
  }
  return "?";
}
MapObjective parse_map_objective(const std::string& name) {
  for (const auto objective :
       {MapObjective::kPaper, MapObjective::kArea, MapObjective::kConformal, MapObjective::kBalanced})
    if (name == to_string(objective)) return objective;
  throw InputError(fmt::format("objective '{}': expected paper, area, conformal or balanced", name));
}
const char* to_string(Solver solver) { return solver == Solver::kDirect ? "direct" : "gauss-seidel"; }
const char* to_string(MapMethod method) {
  switch (method) {
    case MapMethod::kPolesAndRings: return "poles-and-rings";
    case MapMethod::kRefinedPolesAndRings: return "refined-poles-and-rings";
    case MapMethod::kFallbackProgressive: return "fallback-progressive";
  }
  return "?";
}
const char* to_string(MeridianMethod method) {
  switch (method) {
    case MeridianMethod::kNone: return "";
    case MeridianMethod::kSteepestDescent: return "steepest-descent";
    case MeridianMethod::kShortestPath: return "shortest-path";
  }
  return "?";
}
const char* to_string(LinearSolver solver) {
  switch (solver) {
    case LinearSolver::kNone: return "none";
    case LinearSolver::kCholmodLlt: return "cholmod-llt";
    case LinearSolver::kUmfpackLu: return "umfpack-lu";
    case LinearSolver::kGaussSeidel: return "gauss-seidel";
  }
  return "?";
}
const char* to_string(FillReducingOrder order) {
  switch (order) {
    case FillReducingOrder::kNone: return "";
    case FillReducingOrder::kGeometric: return "geometric";
    case FillReducingOrder::kAmd: return "amd";
    case FillReducingOrder::kMetis: return "metis";
  }
  return "?";
}

namespace {

using detail::WorkingMesh;

// The poles given in the options (checked), or the two vertices farthest apart; and their graph distance.
MapPoles choose_poles(const Mesh& mesh, const VertexRings& rings, const MapOptions& options) {
  const auto n = static_cast<std::int32_t>(mesh.positions.size());
  MapPoles poles;
  if (options.poles) {
    const auto [a, b] = *options.poles;
    if (a < 0 || b < 0 || a >= n || b >= n || a == b)
      throw InputError(fmt::format("poles {},{} must be two different vertices in [0, {})", a, b, n));
    poles.north = a;
    poles.south = b;
    poles.from_options = true;
  } else {
    std::tie(poles.north, poles.south) = farthest_pair(mesh.positions);
  }
  poles.graph_distance = graph_distances(rings, poles.north)[poles.south];
  if (poles.from_options && poles.graph_distance < 2)
    throw InputError(
        fmt::format("poles {},{} are joined by an edge, which cannot join two antipodal points; choose "
                    "poles at least 2 edges apart (or leave --poles out)",
                    poles.north, poles.south));
  return poles;
}

// Too few edges between the poles: below 3 the rings are not disjoint (tetrahedron, octahedron,
// bipyramids); at 3 an edge can join the two rings and land on antipodal points. Maps a midpoint
// subdivision instead, whose original vertices keep their indices, and returns only those, in the
// inner map's pole-aligned frame. The input's triangles are then checked and repaired like any map.
std::vector<Vec3> map_refined(const Mesh& mesh, const VertexRings& rings, const MapOptions& options,
                              const MapPoles& poles, MapConstruction& construction, SolveDiagnostics& solve) {
  const auto n = static_cast<std::int32_t>(mesh.positions.size());
  const auto north = poles.north;
  construction.method = MapMethod::kRefinedPolesAndRings;
  Mesh refined = mesh;
  // Adjacent poles (every pair of a tetrahedron is an edge) would put an edge between antipodal
  // points: the inner south pole is then the refined vertex farthest from N (in edges, then in space)
  // that is not N nor an original neighbour of N.
  std::vector<char> excluded(n, 0);
  excluded[north] = 1;
  if (poles.graph_distance < 2)
    for (auto w : rings.ring(north)) excluded[w] = 1;
  std::int32_t inner_south = poles.south;
  std::int32_t inner_distance = 0;
  do {
    refined = subdivide_midpoint(refined, 1);
    ++construction.refinement_levels;
    const auto count = static_cast<std::int32_t>(refined.positions.size());
    const auto distance = graph_distances(build_vertex_rings(count, refined.triangles), north);
    if (poles.graph_distance < 2) {
      inner_south = -1;
      for (std::int32_t v = 0; v < count; ++v) {
        if (v < n && excluded[v]) continue;
        const auto& p = refined.positions;
        if (inner_south < 0 || distance[v] > distance[inner_south] ||
            (distance[v] == distance[inner_south] &&
             squared_distance(p[v], p[north]) > squared_distance(p[inner_south], p[north])))
          inner_south = v;
      }
    }
    inner_distance = distance[inner_south];
  } while (inner_distance < 4);
  MapOptions inner = options;
  inner.poles = std::make_pair(north, inner_south);
  inner.fallback = false;                  // the fallback, if needed, maps the input itself (map_to_sphere)
  inner.objective = MapObjective::kPaper;  // the input's map is optimized, not the subdivision's
  const SphereMap refined_map = map_to_sphere(refined, inner);
  // Back to the inner map's pole-aligned frame: θ, φ and the superposition are taken from there.
  const auto undo = transposed(refined_map.superposition.rotation);
  std::vector<Vec3> sphere(n);
  for (std::int32_t v = 0; v < n; ++v) sphere[v] = rotate(undo, refined_map.sphere[v]);
  solve.solver = refined_map.diagnostics.solve.solver;
  solve.singular_systems = refined_map.diagnostics.solve.singular_systems;
  solve.uniform_weights_instead = refined_map.diagnostics.solve.uniform_weights_instead;
  construction.theta0 = refined_map.diagnostics.construction.theta0;
  construction.mercator_c = refined_map.diagnostics.construction.mercator_c;
  return sphere;
}

// The plain map of the paper's construction, and what re-weighting needs of it.
struct PlainMap {
  detail::PlanarCoordinates planar;
  std::vector<Vec3> sphere;  // of the input's vertices
  detail::EdgeWeights weights;
  detail::OrderChoice order;
};

// The paper's construction on `work` (the input): dividing edges split, circumpolar rings, weights,
// z, the meridian and φ, and the Mercator scaling onto the sphere. Laps "rings" and "solve".
PlainMap map_poles_and_rings(WorkingMesh& work, std::int32_t input_vertices, const MapOptions& options,
                             const MapPoles& poles, SphereMap& result, detail::StageTimer& timer) {
  auto& construction = result.diagnostics.construction;
  auto& solve = result.diagnostics.solve;
  const auto north = poles.north, south = poles.south;
  construction.method = MapMethod::kPolesAndRings;
  detail::split_dividing_edges(work, north, 'N', construction.split_edges);
  detail::split_dividing_edges(work, south, 'S', construction.split_edges);
  if (!construction.split_edges.empty())
    work.rings = build_vertex_rings(static_cast<std::int32_t>(work.positions.size()), work.triangles);
  construction.north_ring_size = work.rings.degree(north);
  construction.south_ring_size = work.rings.degree(south);
  construction.theta0 = std::numbers::pi / poles.graph_distance;
  construction.ring_z = detail::kRingZ;
  construction.mercator_c =
      detail::kRingZ / std::log((1 + std::cos(construction.theta0)) / std::sin(construction.theta0));
  PlainMap plain;
  plain.weights = detail::compute_weights(work.rings, work.positions, options.weights);
  solve.weight_fallback_rows = plain.weights.fallback_rows;
  auto& order = plain.order;
  order.always_fixed.assign(work.positions.size(), 0);
  order.always_fixed[north] = order.always_fixed[south] = 1;
  for (auto v : work.rings.ring(north)) order.always_fixed[v] = 1;
  for (auto v : work.rings.ring(south)) order.always_fixed[v] = 1;
  timer.lap("rings");
  // z and φ of the plain map from one analysis (φ's meridian as decoupled rows); re-weighting
  // factorizes in the same order (its systems have the same unknowns).
  const auto solve_plain = [&] {
    std::unique_ptr<detail::ReusableCholesky> factor;
    if (options.solver == Solver::kDirect && plain.weights.symmetric) {
      factor = detail::plain_map_factor(work, order);
      solve.elimination_order = order.chosen ? order.chosen->method : FillReducingOrder::kGeometric;
    }
    plain.planar = detail::solve_planar(work, north, south, plain.weights, options, factor.get());
  };
  try {
    solve_plain();
  } catch (const detail::SingularSystem&) {
    // Uniform weights are positive and symmetric: with the poles and rings fixed, their system on a
    // connected mesh is positive definite, never singular. Re-weighting then starts from them.
    if (options.weights == Weights::kUniform) throw;
    ++solve.singular_systems;
    solve.uniform_weights_instead = true;
    plain.weights = detail::compute_weights(work.rings, work.positions, Weights::kUniform);
    solve_plain();
  }
  solve.solver = plain.planar.z_stats.solver;
  solve.gauss_seidel_sweeps = plain.planar.z_stats.sweeps + plain.planar.phi_stats.sweeps;
  solve.gauss_seidel_converged = plain.planar.z_stats.converged && plain.planar.phi_stats.converged;
  plain.sphere = detail::to_sphere(plain.planar, north, south, construction.mercator_c, input_vertices);
  timer.lap("solve");
  return plain;
}

// θ and φ of every vertex from its sphere point, before the superposition.
void set_angles(SphereMap& result, const std::vector<Vec3>& sphere) {
  const auto n = sphere.size();
  result.theta.resize(n);
  result.phi.resize(n);
  const auto inverse = transposed(result.superposition.rotation);
  for (std::size_t v = 0; v < n; ++v) {
    const Vec3 u = rotate(inverse, sphere[v]);
    // atan2, not acos(u_z): rotating back rounds a pole's z to 1 - 2^-53 at worst, where acos is
    // 2e-8 away from 0; atan2 keeps full precision near the poles.
    result.theta[v] = std::atan2(std::hypot(u[0], u[1]), u[2]);
    double phi = std::atan2(u[1], u[0]);
    if (phi < 0) phi += 2 * std::numbers::pi;
    if (phi >= 2 * std::numbers::pi) phi = 0;  // -0 and tiny negatives round up to 2π
    result.phi[v] = phi;
  }
}

// The fallback (sphere/fallback.hpp) for a map the repair left uncertified, with the same poles: its map
// replaces `finished` if it is certified or has fewer bad triangles. Laps "fallback".
void run_fallback(const Mesh& mesh, detail::InputStars& input, const MapOptions& options, SphereMap& result,
                  detail::Finished& finished, detail::StageTimer& timer) {
  auto& diagnostics = result.diagnostics;
  auto sphere = fallback_map(mesh, result.poles.north, result.poles.south, diagnostics.fallback);
  if (diagnostics.fallback.embedding.valid) {
    auto candidate = detail::finish_map(mesh, input, std::move(sphere), options);
    const auto& before = finished.certificate;
    const auto& after = candidate.certificate;
    if (after.certified() || after.folded + after.collapsed < before.folded + before.collapsed) {
      finished = std::move(candidate);
      diagnostics.construction.method = MapMethod::kFallbackProgressive;
    }
  }
  timer.lap("fallback");
}

}  // namespace

SphereMap map_to_sphere(const Mesh& mesh, const MapOptions& options) {
  SphereMap result;
  auto& diagnostics = result.diagnostics;
  detail::StageTimer timer("map", &diagnostics.timings);
  const auto n = static_cast<std::int32_t>(mesh.positions.size());
  if (n < 4) throw MeshRefused("the mesh has fewer than 4 vertices; a closed triangle mesh needs at least 4");

  WorkingMesh work{mesh.positions, mesh.triangles, build_vertex_rings(n, mesh.triangles)};
  result.poles = choose_poles(mesh, work.rings, options);
  timer.lap("poles");

  const bool refined = result.poles.graph_distance < 4;
  PlainMap plain;
  if (refined) {
    plain.sphere = map_refined(mesh, work.rings, options, result.poles, diagnostics.construction, diagnostics.solve);
    timer.lap("solve");
  } else {
    plain = map_poles_and_rings(work, n, options, result.poles, result, timer);
  }
  std::vector<double> plain_solid_angles;
  auto& repair = diagnostics.repair;
  repair.plain_certificate = certify_sphere_map(mesh, plain.sphere, options.collapse_floor, &plain_solid_angles);
  timer.lap("certify-plain");

  std::optional<VertexRings> unsplit_rings;
  detail::InputStars input(
      mesh, work.rings.vertex_count() == n ? work.rings : unsplit_rings.emplace(build_vertex_rings(n, mesh.triangles)));
  std::optional<detail::Finished> finished;
  if (options.repair && !refined && repair.plain_certificate.collapsed > 0) {
    auto outcome = detail::reweight_against_collapse(
        mesh, work, result.poles.north, result.poles.south, diagnostics.construction.mercator_c, plain.weights, options,
        input, detail::Candidate{plain.planar, plain.sphere, repair.plain_certificate, std::move(plain_solid_angles)},
        plain.order);
    plain.planar = std::move(outcome.best.planar);
    plain.sphere = std::move(outcome.best.sphere);
    finished = std::move(outcome.finished);
    repair.reweighting_rounds = outcome.rounds;
    repair.equalizing_rounds = outcome.equalizing_rounds;
    diagnostics.solve.singular_systems += outcome.singular_systems;
    diagnostics.solve.solver = plain.planar.z_stats.solver;
    timer.lap("reweight");
  }
  if (!finished) finished = detail::finish_map(mesh, input, std::move(plain.sphere), options, &timer);
  if (options.repair && options.fallback && !finished->certificate.certified() && n >= 5)
    run_fallback(mesh, input, options, result, *finished, timer);
  if (options.objective != MapObjective::kPaper) {
    const auto south = diagnostics.fallback.ran && diagnostics.construction.method == MapMethod::kFallbackProgressive
                           ? diagnostics.fallback.south
                           : result.poles.south;
    detail::optimize_for_objective(mesh, input, result.poles.north, south, options, *finished, diagnostics.objective,
                                   timer);
  }
  result.superposition = finished->superposition;
  repair.untangling_moves = finished->untangling_moves;
  result.certificate = std::move(finished->certificate);
  set_angles(result, finished->sphere);
  if (!refined) {
    auto& construction = diagnostics.construction;
    construction.meridian = plain.planar.meridian;
    construction.meridian_method =
        plain.planar.meridian_by_descent ? MeridianMethod::kSteepestDescent : MeridianMethod::kShortestPath;
    construction.meridian_round = plain.planar.meridian_round;
  }
  result.sphere = std::move(finished->sphere);
  return result;
}

}  // namespace spheremap
