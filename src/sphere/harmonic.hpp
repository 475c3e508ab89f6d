// Private to the sphere stage: weighted graph Laplacian systems with Dirichlet values.
#pragma once

#include <cstdint>
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

}  // namespace spheremap::detail
