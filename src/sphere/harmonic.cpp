#include "harmonic.hpp"

#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>
#include <Eigen/UmfPackSupport>
#include <cmath>
#include <stdexcept>

#include "spheremap/geometry/vec.hpp"

namespace spheremap::detail {

EdgeWeights compute_weights(const VertexRings& rings, const std::vector<Vec3>& positions, Weights kind) {
  EdgeWeights weights;
  weights.values.assign(rings.neighbors.size(), 1.0);
  weights.symmetric = kind != Weights::kMeanValue;
  if (kind == Weights::kUniform) return weights;
  const auto n = rings.vertex_count();
  for (std::int32_t v = 0; v < n; ++v) {
    const auto ring = rings.ring(v);
    const auto degree = static_cast<std::int64_t>(ring.size());
    const Vec3& p = positions[v];
    bool usable = true;
    for (std::int64_t k = 0; k < degree; ++k) {
      const Vec3& w = positions[ring[k]];
      const Vec3& next = positions[ring[(k + 1) % degree]];
      const Vec3& prev = positions[ring[(k + degree - 1) % degree]];
      double value;
      if (kind == Weights::kCotangent) {
        // Angles opposite the edge (v, w): at `next` in triangle (v, w, next), at `prev` in (v, prev, w).
        auto cotangent = [](const Vec3& apex, const Vec3& x, const Vec3& y) {
          const Vec3 a = x - apex, b = y - apex;
          return dot(a, b) / norm(cross(a, b));
        };
        value = 0.5 * (cotangent(next, p, w) + cotangent(prev, p, w));
      } else {
        // tan(δ/2) = |a × b| / (|a||b| + a·b), stable for every angle δ in (0, π).
        auto half_tangent = [](const Vec3& a, const Vec3& b) {
          return norm(cross(a, b)) / (norm(a) * norm(b) + dot(a, b));
        };
        const Vec3 e = w - p;
        value = (half_tangent(e, next - p) + half_tangent(prev - p, e)) / norm(e);
        if (!(value > 0)) usable = false;
      }
      if (!std::isfinite(value)) usable = false;
      weights.values[rings.offsets[v] + k] = value;
    }
    if (!usable) {
      // A degenerate corner (zero-length edge or zero angle): this row keeps uniform weights.
      for (std::int64_t k = 0; k < degree; ++k) weights.values[rings.offsets[v] + k] = 1.0;
      ++weights.fallback_rows;
      weights.symmetric = false;
    }
  }
  return weights;
}

namespace {

double neighbour_value(const HarmonicProblem& problem, const std::vector<double>& x, std::int64_t slot,
                       std::int32_t neighbour) {
  if (!problem.slot_value.empty() && !std::isnan(problem.slot_value[slot])) return problem.slot_value[slot];
  return x[neighbour];
}

SolveStats solve_gauss_seidel(const HarmonicProblem& problem, std::vector<double>& x, double tolerance,
                              std::int64_t max_sweeps) {
  const auto& rings = *problem.rings;
  const auto& w = problem.weights->values;
  const auto n = rings.vertex_count();
  SolveStats stats{"gauss-seidel", 0, false};
  // The paper starts from 0.
  for (std::int32_t v = 0; v < n; ++v)
    if (!problem.fixed[v]) x[v] = 0;
  double scale = 0;
  for (std::int32_t v = 0; v < n; ++v)
    if (problem.fixed[v]) scale = std::max(scale, std::abs(x[v]));
  for (std::int64_t k = 0; k < static_cast<std::int64_t>(problem.slot_value.size()); ++k)
    if (!std::isnan(problem.slot_value[k])) scale = std::max(scale, std::abs(problem.slot_value[k]));
  const double threshold = tolerance * std::max(scale, 1.0);
  while (stats.sweeps < max_sweeps) {
    ++stats.sweeps;
    double largest_change = 0;
    for (std::int32_t v = 0; v < n; ++v) {
      if (problem.fixed[v]) continue;
      double sum = 0, total = 0;
      const auto ring = rings.ring(v);
      for (std::size_t k = 0; k < ring.size(); ++k) {
        const auto slot = rings.offsets[v] + static_cast<std::int64_t>(k);
        sum += w[slot] * neighbour_value(problem, x, slot, ring[k]);
        total += w[slot];
      }
      const double updated = sum / total;
      largest_change = std::max(largest_change, std::abs(updated - x[v]));
      x[v] = updated;
    }
    if (largest_change < threshold) {
      stats.converged = true;
      break;
    }
  }
  return stats;
}

}  // namespace

SolveStats solve_harmonic(const HarmonicProblem& problem, std::vector<double>& x, Solver solver, double tolerance,
                          std::int64_t max_sweeps) {
  if (solver == Solver::kGaussSeidel) return solve_gauss_seidel(problem, x, tolerance, max_sweeps);
  const auto& rings = *problem.rings;
  const auto& w = problem.weights->values;
  const auto n = rings.vertex_count();
  std::vector<std::int32_t> unknown_index(n, -1);
  std::int32_t unknowns = 0;
  for (std::int32_t v = 0; v < n; ++v)
    if (!problem.fixed[v]) unknown_index[v] = unknowns++;
  SolveStats stats;
  if (unknowns == 0) {
    stats.solver = "none";
    return stats;
  }
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(rings.neighbors.size() + unknowns);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(unknowns);
  for (std::int32_t v = 0; v < n; ++v) {
    if (problem.fixed[v]) continue;
    const auto row = unknown_index[v];
    double total = 0;
    const auto ring = rings.ring(v);
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const auto slot = rings.offsets[v] + static_cast<std::int64_t>(k);
      total += w[slot];
      const auto j = ring[k];
      if (problem.fixed[j]) rhs[row] += w[slot] * neighbour_value(problem, x, slot, j);
      else entries.emplace_back(row, unknown_index[j], -w[slot]);
    }
    entries.emplace_back(row, row, total);
  }
  Eigen::SparseMatrix<double> matrix(unknowns, unknowns);
  matrix.setFromTriplets(entries.begin(), entries.end());
  Eigen::VectorXd solution;
  bool solved = false;
  if (problem.weights->symmetric) {
    Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> cholesky;
    cholesky.compute(matrix);
    if (cholesky.info() == Eigen::Success) {
      solution = cholesky.solve(rhs);
      solved = cholesky.info() == Eigen::Success;
      stats.solver = "cholmod-llt";
    }
  }
  if (!solved) {
    Eigen::UmfPackLU<Eigen::SparseMatrix<double>> lu;
    lu.compute(matrix);
    if (lu.info() != Eigen::Success) throw std::runtime_error("the sparse LU factorization failed (singular system)");
    solution = lu.solve(rhs);
    if (lu.info() != Eigen::Success) throw std::runtime_error("the sparse LU solve failed");
    stats.solver = "umfpack-lu";
  }
  for (std::int32_t v = 0; v < n; ++v)
    if (!problem.fixed[v]) x[v] = solution[unknown_index[v]];
  return stats;
}

}  // namespace spheremap::detail
