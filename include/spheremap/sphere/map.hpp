// The map of a closed genus-0 triangle mesh onto the unit sphere (paper §2.3), with the cases the paper
// leaves out, followed by certification (stage: sphere).
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "spheremap/mesh.hpp"
#include "spheremap/metrics/distortion.hpp"
#include "spheremap/sphere/certify.hpp"

namespace spheremap {

enum class Weights {
  kUniform,    // the paper: every neighbour weighs 1 (provably one-to-one in the (z, φ) plane)
  kCotangent,  // ½(cot α + cot β): the paper's comparison; can be negative, so it may fold
  kMeanValue,  // Floater 2003: (tan(α/2) + tan(β/2)) / |e|, always positive, closer to conformal
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
};

struct SplitEdge {
  std::int32_t a, b;       // ring vertices joined by a dividing edge
  char pole;               // 'N' or 'S': the ring they belong to
};

struct StageTime {
  std::string stage;
  double seconds;
};

struct SphereMap {
  /// One unit vector per input vertex, rotated by the superposition so the globe faces like the surface.
  std::vector<Vec3> sphere;
  /// Map coordinates before the superposition: θ in [0, π] from the north pole, φ in [0, 2π).
  std::vector<double> theta, phi;
  Superposition superposition;

  std::int32_t north = -1, south = -1;
  bool poles_from_options = false;
  std::string method;  // "poles-and-rings" (the paper's) or "refined-poles-and-rings" (poles < 4 edges apart)
  int refinement_levels = 0;  // midpoint subdivisions mapped instead of the mesh (poles < 4 edges apart)
  std::int32_t pole_graph_distance = 0;  // d_s
  double theta0 = 0;                     // π / d_s
  double mercator_c = 0, ring_z = 1;     // C and Z of the Mercator scaling
  std::int32_t north_ring_size = 0, south_ring_size = 0;
  std::vector<SplitEdge> split_edges;
  std::vector<std::int32_t> meridian;  // boundary meridian, north ring to south ring
  /// "steepest-descent" (the paper's), or "shortest-path" when every descent stalls at an interior
  /// minimum of z, which only weights that can be negative (cotangent) allow.
  std::string meridian_method;
  /// The re-weighting round whose z the meridian was found for (0: the plain map's). Rounds keep the
  /// meridian of the best map so far while their z strictly decreases along it (a chord-free path from
  /// ring to ring, so Floater's theorem applies as to a fresh one), and find a new one otherwise.
  int meridian_round = 0;

  std::string solver_used;  // e.g. "cholmod-llt", "umfpack-lu", "gauss-seidel"
  /// Fill-reducing order of the Cholesky factorizations: "geometric" (our nested dissection) or "amd"
  /// (CHOLMOD's AMD, where it needs fewer flops, as on molecular surfaces); empty without them.
  std::string elimination_order;
  std::int64_t gauss_seidel_sweeps = 0;
  bool gauss_seidel_converged = true;
  std::int64_t weight_fallback_rows = 0;  // vertices whose mean-value/cotangent weights were not finite

  Certificate plain_certificate;  // the paper's algorithm alone (before any repair)
  int reweighting_rounds = 0;
  int equalizing_rounds = 0;  // of reweighting_rounds, the rounds kept by equalizing after certification
  std::int64_t untangling_moves = 0;
  Certificate certificate;  // of the final map
  std::vector<StageTime> timings;
};

/// Maps `mesh` one-to-one onto the unit sphere.
/// Preconditions: `mesh` is closed, 2-manifold, connected, genus 0 and oriented outward, as produced by
/// prepare_mesh; at least 4 vertices. options.poles, if set, are indices of `mesh`'s vertices.
/// Throws InputError if options.poles are out of range, equal, or joined by an edge, and MeshRefused if
/// the mesh has fewer than 4 vertices.
/// The result is always returned, certified or not: check result.certificate.certified().
SphereMap map_to_sphere(const Mesh& mesh, const MapOptions& options = {});

/// The two vertices farthest apart (exact maximum of the squared distances as computed in double),
/// found with a k-d tree and branch-and-bound instead of all pairs. Ties go to the smallest index
/// pair. Precondition: at least 2 positions. The first index is smaller than the second.
std::pair<std::int32_t, std::int32_t> farthest_pair(const std::vector<Vec3>& positions);

const char* to_string(Weights weights);
const char* to_string(Solver solver);

}  // namespace spheremap
