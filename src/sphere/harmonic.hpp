// Private to the sphere stage: weighted graph Laplacian systems with Dirichlet values.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
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
  std::string solver;
  std::int64_t sweeps = 0;
  bool converged = true;
};

SolveStats solve_harmonic(const HarmonicProblem& problem, std::vector<double>& x, Solver solver, double tolerance,
                          std::int64_t max_sweeps);

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

 private:
  struct State;
  std::unique_ptr<State> state_;
};

}  // namespace spheremap::detail
