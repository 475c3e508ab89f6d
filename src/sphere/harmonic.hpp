// Private to the sphere stage: weighted graph Laplacian systems with Dirichlet values.
#pragma once

#include <cstdint>
#include <memory>
#include <stdexcept>
#include <vector>

#include "spheremap/sphere/map.hpp"
#include "spheremap/topology/connectivity.hpp"

namespace spheremap::detail {

/// weights[offsets[v] + k] is the weight of the k-th neighbour of v (VertexRings order).
struct EdgeWeights {
  std::vector<double> values;
  bool symmetric = true;  // w(v, w) == w(w, v) for every edge
  std::int64_t fallback_rows = 0;
};

EdgeWeights compute_weights(const VertexRings& rings, const std::vector<Vec3>& positions, Weights kind);

/// Solves Σ_j w_ij (x_i - value_j) = 0 for every unknown vertex i (fixed[i] == false), where value_j is
/// x_j for unknowns and neighbour_value(i, k) for the fixed k-th neighbour of i.
/// `x` holds the fixed values on entry (read through neighbour_value) and the solution on exit.
struct HarmonicProblem {
  const VertexRings* rings;
  const EdgeWeights* weights;
  const std::vector<Vec3>* positions;  // of the vertices, for the fill-reducing order
  std::vector<char> fixed;
  /// For fixed neighbours whose value depends on the side they are seen from (the meridian), a value per
  /// (vertex, neighbour slot); NaN means "use x[j]".
  std::vector<double> slot_value;  // empty or size rings->neighbors.size()
};

struct SolveStats {
  LinearSolver solver = LinearSolver::kNone;
  std::int64_t sweeps = 0;
  bool converged = true;
};

/// A harmonic system that the sparse LU factorization finds singular: mean-value or cotangent weights
/// that cancel or underflow on extreme geometry (coordinates of 1e61 beside ones of 1). The callers
/// fall back to uniform weights (plain map) or reject the round (re-weighting); it never escapes a map.
struct SingularSystem : std::runtime_error {
  using std::runtime_error::runtime_error;
};

/// Solves `problem` for its free vertices into x (fixed ones keep their values). Throws SingularSystem
/// when the LU factorization fails, std::runtime_error when CHOLMOD or the LU solve fails.
SolveStats solve_harmonic(const HarmonicProblem& problem, std::vector<double>& x, Solver solver, double tolerance,
                          std::int64_t max_sweeps);

/// The order in which a sparse Cholesky factorization eliminates the unknowns of one mesh's harmonic
/// systems: every vertex not in `always_fixed`, first eliminated first. One order serves every system
/// of a map (z and φ of the plain map, every re-weighting round), whatever else they fix.
struct EliminationOrder {
  std::vector<std::int32_t> vertices;
  FillReducingOrder method = FillReducingOrder::kGeometric;
  /// Floating-point operations of a factorization in this order as the ordering itself counted them
  /// (AMD's), without CHOLMOD's symbolic analysis; 0 where the ordering does not count them.
  double flops = 0;
};

/// Geometric nested dissection: split across the longest bounding-box axis near the median (in the
/// widest coordinate gap of the middle tenth, on meshes of 5,000 vertices or more), the vertices of one
/// half touching the other as separator, recursively. Cheap and the best on smooth, convex-ish shapes
/// (a subdivided cube, perturbed or not), but a plane cuts a convoluted surface along long curves: on
/// molecular surfaces its factor needs several times the flops of AMD's or METIS's.
/// Preconditions: always_fixed.size() == positions.size() == rings.vertex_count().
EliminationOrder geometric_elimination_order(const VertexRings& rings, const std::vector<Vec3>& positions,
                                             const std::vector<char>& always_fixed);

/// Approximate minimum degree (CHOLMOD's AMD on the symmetric pattern): about as cheap to compute as the
/// geometric order and close to METIS's flops on molecular surfaces; more flops than the geometric order
/// on smooth shapes. Deterministic. Returns the geometric order if AMD fails.
EliminationOrder amd_elimination_order(const VertexRings& rings, const std::vector<Vec3>& positions,
                                       const std::vector<char>& always_fixed);

/// METIS's nested dissection (METIS_NodeND through CHOLMOD), postordered: the fewest flops, but several
/// times dearer to compute than AMD's, which its factorizations do not win back on molecular surfaces
/// (BENCHMARKS.md); kept for the benchmarks and tests. Deterministic (METIS's fixed seed). Returns the
/// geometric order if METIS fails.
EliminationOrder metis_elimination_order(const VertexRings& rings, const std::vector<Vec3>& positions,
                                         const std::vector<char>& always_fixed);

/// A sparse Cholesky factorization that is analysed once and refactorized for new weights: the
/// re-weighting rounds solve systems with one sparsity pattern (every vertex that is not always fixed),
/// so the fill-reducing order and CHOLMOD's symbolic analysis are computed once and each round only
/// redoes the numeric factorization.
/// Vertices that a problem fixes beyond `always_fixed` keep their place in the pattern as decoupled
/// rows (diagonal 1, zero couplings), which gives the same solution as eliminating them. The vertices
/// of `last` are ordered last, so the leading block of the factor is also the factor of the system in
/// which they are fixed: z (meridian free) and φ (meridian fixed) are solved with one factorization.
class ReusableCholesky {
 public:
  /// Preconditions: `rings` outlives the object; always_fixed.size() == vertex count; `last` holds
  /// distinct vertices that are not always fixed. Throws std::bad_alloc, or std::runtime_error if
  /// CHOLMOD's analysis fails.
  ReusableCholesky(const VertexRings& rings, const std::vector<Vec3>& positions, const std::vector<char>& always_fixed,
                   const std::vector<std::int32_t>& last = {});
  /// The same with a given order of the unknowns (the vertices not always fixed; `last` moved to the end).
  /// Preconditions: `rings` outlives the object; `order` is a permutation of the vertices that are not
  /// always fixed; `last` is a subset of them.
  ReusableCholesky(const VertexRings& rings, const EliminationOrder& order, const std::vector<std::int32_t>& last = {});
  ~ReusableCholesky();
  ReusableCholesky(const ReusableCholesky&) = delete;
  ReusableCholesky& operator=(const ReusableCholesky&) = delete;

  /// The numeric factorization of `problem`'s matrix. Preconditions: problem.rings is the object's,
  /// problem.fixed ⊇ always_fixed, the weights are positive and exactly symmetric (w(i, j) == w(j, i)
  /// bit for bit: the lower triangle is read from the row vertex's slot). Returns false if the matrix
  /// is not positive definite (then solve must not be called).
  bool factorize(const HarmonicProblem& problem);

  /// Solves `problem` with the last factorization, like solve_harmonic with the direct solver.
  /// last_fixed == false: `problem` fixes what the factorized one did. last_fixed == true: it also
  /// fixes every vertex of last() (and nothing else), whose values it reads from x.
  /// Throws std::logic_error without a successful factorize, std::runtime_error if CHOLMOD fails.
  void solve(const HarmonicProblem& problem, std::vector<double>& x, bool last_fixed = false);

  [[nodiscard]] const std::vector<std::int32_t>& last() const;
  /// Floating-point operations of one numeric factorization (CHOLMOD's count from the analysis).
  [[nodiscard]] double flops() const;
  /// Whether CHOLMOD chose a supernodal factorization (LL') rather than a simplicial one (LDL'): it does
  /// when flops per nonzero of the factor are many (large, poorly ordered systems).
  [[nodiscard]] bool supernodal() const;

 private:
  void analyse(const VertexRings& rings, std::vector<std::int32_t> vertex_of_row,
               const std::vector<std::int32_t>& last);
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace spheremap::detail
