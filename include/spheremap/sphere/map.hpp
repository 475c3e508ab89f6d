// The map of a closed genus-0 triangle mesh onto the unit sphere (paper §2.3), with the cases the paper
// leaves out, followed by certification (stage: sphere).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "spheremap/geometry/superposition.hpp"
#include "spheremap/mesh.hpp"
#include "spheremap/sphere/certify.hpp"
#include "spheremap/sphere/fallback.hpp"
#include "spheremap/sphere/optimize.hpp"
#include "spheremap/timing.hpp"

namespace spheremap {

enum class Weights {
  kUniform,    // the paper: every neighbour weighs 1 (provably one-to-one in the (z, φ) plane)
  kCotangent,  // ½(cot α + cot β): the paper's comparison; can be negative, so it may fold
  kMeanValue,  // Floater 2003: (tan(α/2) + tan(β/2)) / |e|, always positive, closer to conformal
};
/// What the certified map is optimized for afterwards (report.json: options.objective, map.objective).
enum class MapObjective {
  kPaper,      // "paper": the paper's map as it is (no optimization)
  kArea,       // "area": (almost) equal area, SphereEnergy::kLogAreaRatio
  kConformal,  // "conformal": angle-preserving as far as a certified map allows, SphereEnergy::kConformal
  kBalanced,   // "balanced": area and angles together, SphereEnergy::kSymmetricDirichlet
};

enum class Solver {
  kDirect,       // sparse Cholesky (CHOLMOD) for symmetric systems, sparse LU (UMFPACK) otherwise
  kGaussSeidel,  // the paper's relaxation, to numerical precision (or the iteration cap)
};

struct MapOptions {
  Weights weights = Weights::kUniform;
  Solver solver = Solver::kDirect;
  /// Pole vertices (north, south) as indices of the mapped mesh; by default the two vertices farthest
  /// apart. (run_map_job takes them as indices of the input file and translates them.)
  std::optional<std::pair<std::int32_t, std::int32_t>> poles;
  /// Repair what the planar guarantee does not cover (folds and collapse on the sphere): reweighting
  /// of the harmonic weights (positive, so the planar map stays one-to-one) against collapse, then local
  /// untangling on the sphere. When false, the plain algorithm's result is returned as is.
  bool repair = true;
  double collapse_floor = kDefaultCollapseFloor;
  /// Gauss-Seidel: stop when the largest change in a sweep is below tolerance * Z, or after max sweeps.
  double gauss_seidel_tolerance = 1e-13;
  std::int64_t gauss_seidel_max_sweeps = 200000;
  int max_reweighting_rounds = 40;
  /// After re-weighting has made the map certified: at most this many further rounds that equalize
  /// area ratios, each kept only if the map stays certified and its mean area distortion drops
  /// (0: none; the map is then the first certified one, with limbs small on the sphere).
  int max_equalizing_rounds = 12;
  int max_untangling_sweeps = 200;
  /// With repair: when the map is still not certified, build one by progressive embedding and
  /// optimization on the sphere (sphere/fallback.hpp), with the same poles.
  bool fallback = true;
  /// After the map is certified: optimize its points on the sphere for this objective, keeping every
  /// triangle positively oriented and the poles fixed; the result replaces the map only if it certifies.
  MapObjective objective = MapObjective::kPaper;
  int objective_max_iterations = 300;
};

struct SplitEdge {
  std::int32_t a, b;  // ring vertices joined by a dividing edge
  char pole;          // 'N' or 'S': the ring they belong to
};

/// Which construction made the map (report.json: map.method).
enum class MapMethod {
  kPolesAndRings,         // "poles-and-rings": the paper's
  kRefinedPolesAndRings,  // "refined-poles-and-rings": a midpoint subdivision mapped (poles < 4 edges apart)
  /// "fallback-progressive": neither ended certified and the fallback's map (MapDiagnostics::fallback)
  /// replaced theirs; the rest of MapConstruction still describes the construction it replaced.
  kFallbackProgressive,
};

/// How the boundary meridian was found (report.json: map.meridian_method).
enum class MeridianMethod {
  kNone,             // "": no meridian on this mesh (a refined map's is on the subdivision)
  kSteepestDescent,  // "steepest-descent": the paper's
  /// "shortest-path": every descent stalled at an interior minimum of z, which only weights that can be
  /// negative (cotangent) allow.
  kShortestPath,
};

/// The solver of the linear systems (report.json: map.solver).
enum class LinearSolver {
  kNone,         // "none": nothing to solve (every vertex fixed)
  kCholmodLlt,   // "cholmod-llt": sparse Cholesky, symmetric weights
  kUmfpackLu,    // "umfpack-lu": sparse LU, weights that are not symmetric
  kGaussSeidel,  // "gauss-seidel": the paper's relaxation
};

/// Fill-reducing order of the Cholesky factorizations (report.json: map.elimination_order).
enum class FillReducingOrder {
  kNone,       // "": no Cholesky factorization
  kGeometric,  // "geometric": our nested dissection (best on smooth, convex-ish shapes)
  kAmd,        // "amd": CHOLMOD's approximate minimum degree (fewer flops on molecular surfaces)
  kMetis,      // "metis": METIS's nested dissection (benchmarks and tests only)
};

/// The poles of the map.
struct MapPoles {
  std::int32_t north = -1, south = -1;
  bool from_options = false;        // given by MapOptions::poles (otherwise farthest_pair)
  std::int32_t graph_distance = 0;  // d_s: edges between them
};

/// The paper's construction on the mesh mapped (poles-and-rings). A refined map reports the refinement
/// and takes theta0 and mercator_c from its subdivision's map; the rest keep their defaults.
struct MapConstruction {
  MapMethod method = MapMethod::kPolesAndRings;
  int refinement_levels = 0;          // midpoint subdivisions mapped instead of the mesh
  double theta0 = 0;                  // π / d_s
  double mercator_c = 0, ring_z = 1;  // C and Z of the Mercator scaling
  std::int32_t north_ring_size = 0, south_ring_size = 0;
  std::vector<SplitEdge> split_edges;
  std::vector<std::int32_t> meridian;  // boundary meridian, north ring to south ring
  MeridianMethod meridian_method = MeridianMethod::kNone;
  /// The re-weighting round whose z the meridian was found for (0: the plain map's). Rounds keep the
  /// meridian of the best map so far while their z strictly decreases along it (a chord-free path from
  /// ring to ring, so Floater's theorem applies as to a fresh one), and find a new one otherwise.
  int meridian_round = 0;
};

/// How the linear systems were solved.
struct SolveDiagnostics {
  LinearSolver solver = LinearSolver::kNone;  // of the final map's z
  /// Geometric, or AMD where it needs fewer flops (as on molecular surfaces); kNone without Cholesky.
  FillReducingOrder elimination_order = FillReducingOrder::kNone;
  std::int64_t gauss_seidel_sweeps = 0;
  bool gauss_seidel_converged = true;
  std::int64_t weight_fallback_rows = 0;  // vertices whose mean-value/cotangent weights were not finite
  /// Systems the sparse LU found singular (extreme geometry under mean-value or cotangent weights): a
  /// plain map's, then solved again with uniform weights (uniform_weights_instead), or a re-weighting
  /// round's, then rejected.
  int singular_systems = 0;
  bool uniform_weights_instead = false;
};

/// What the repair (MapOptions::repair) did to the paper's algorithm's result.
struct RepairDiagnostics {
  Certificate plain_certificate;  // the paper's algorithm alone (before any repair)
  int reweighting_rounds = 0;
  int equalizing_rounds = 0;  // of reweighting_rounds, the rounds kept by equalizing after certification
  std::int64_t untangling_moves = 0;
};

/// What the objective's optimization did (report.json: map.objective, when options.objective is not paper).
enum class ObjectiveOutcome {
  kNone,                // "": not run (objective paper)
  kOptimized,           // "optimized": the optimized map certified and replaced the map
  kStartNotCertified,   // "start-not-certified": the map was not certified, so nothing was optimized
  kResultNotCertified,  // "result-not-certified": the optimized map did not certify; the map is the start
};

struct ObjectiveReport {
  MapObjective objective = MapObjective::kPaper;
  ObjectiveOutcome outcome = ObjectiveOutcome::kNone;
  SphereEnergy energy = SphereEnergy::kSymmetricDirichlet;
  SphereOptimizeReport optimization;  // energies per unit of the map's area
  /// The optimization's stages run (the area objective's each with a smaller shape weight, while its
  /// goal is missed; 1 for the others) and, for the area objective, the last stage's shape weight.
  int stages = 0;
  double shape_weight = 0;
  /// The area objective's coarse start on large meshes (0 when none was made): the vertices of the
  /// coarse mesh optimized first, the coarse levels, their Newton steps (not in `optimization`).
  std::int64_t coarse_vertices = 0;
  int coarse_levels = 0;
  int coarse_iterations = 0;
};

/// How the map was made: for the report and for tuning, not needed to use the map.
struct MapDiagnostics {
  MapConstruction construction;
  SolveDiagnostics solve;
  RepairDiagnostics repair;
  FallbackReport fallback;  // ran only when the map ended uncertified after the repair
  ObjectiveReport objective;
  std::vector<StageTime> timings;  // "poles", "rings" or "solve", "certify-plain", "reweight", ..., "fallback"
};

/// The map and its certificate, then how it was made.
struct SphereMap {
  /// One unit vector per input vertex, rotated by the superposition so the globe faces like the surface.
  std::vector<Vec3> sphere;
  /// Map coordinates before the superposition: θ in [0, π] from the north pole, φ in [0, 2π).
  std::vector<double> theta, phi;
  Superposition superposition;
  MapPoles poles;
  Certificate certificate;  // of `sphere`
  MapDiagnostics diagnostics;
};

/// The objective named `name` ("paper", "area", "conformal", "balanced").
/// Throws InputError naming the choices otherwise.
MapObjective parse_map_objective(const std::string& name);

/// Maps `mesh` one-to-one onto the unit sphere, then optimizes it for options.objective.
/// Preconditions: `mesh` is closed, 2-manifold, connected, genus 0 and oriented outward, as produced by
/// prepare_mesh; at least 4 vertices. options.poles, if set, are indices of `mesh`'s vertices.
/// Throws InputError if options.poles are out of range, equal, or joined by an edge, and MeshRefused if
/// the mesh has fewer than 4 vertices.
/// The result is always returned, certified or not: check result.certificate.certified().
SphereMap map_to_sphere(const Mesh& mesh, const MapOptions& options = {});

/// The names report.json and the command line use (e.g. "mean-value", "direct", "poles-and-rings").
/// Never throw.
const char* to_string(Weights weights);
const char* to_string(MapObjective objective);
const char* to_string(ObjectiveOutcome outcome);
const char* to_string(Solver solver);
const char* to_string(MapMethod method);
const char* to_string(MeridianMethod method);
const char* to_string(LinearSolver solver);
const char* to_string(FillReducingOrder order);

}  // namespace spheremap
