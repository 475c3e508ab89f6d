#include <cholmod.h>
#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>
#include <algorithm>
#include <atomic>
#include <cmath>
#include <cstdint>
#include <limits>
#include <memory>
#include <numbers>
#include <stdexcept>
#include <string>

#include "../util/parallel.hpp"
#include "harmonic.hpp"
#include "solver_section.hpp"
#include "sphere_optimizer.hpp"
#include "spheremap/geometry/predicates.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/sphere/optimize.hpp"
#include "triangle_energy.hpp"

namespace spheremap {

const char* to_string(SphereEnergy energy) {
  switch (energy) {
    case SphereEnergy::kSymmetricDirichlet: return "symmetric-dirichlet";
    case SphereEnergy::kLogAreaRatio: return "log-area-ratio";
    case SphereEnergy::kConformal: return "conformal-mips";
  }
  return "?";
}

const char* to_string(OptimizeStop stop) {
  switch (stop) {
    case OptimizeStop::kNone: return "";
    case OptimizeStop::kConverged: return "converged";
    case OptimizeStop::kIterations: return "iterations";
    case OptimizeStop::kLineSearch: return "line-search";
    case OptimizeStop::kFactorization: return "factorization";
  }
  return "?";
}

namespace {

using Matrix6 = Eigen::Matrix<double, 6, 6>;
using Vector6 = Eigen::Matrix<double, 6, 1>;
using SparseMatrix = Eigen::SparseMatrix<double>;

// Armijo's sufficient decrease, the backtracking factor and how far it may go, and the largest tangent
// step of one vertex per iteration (radians, about; keeps the retraction p + t -> (p + t)/|p + t| tame).
constexpr double kArmijo = 1e-4;
constexpr double kBacktrack = 0.5;
constexpr int kMaxBacktracks = 60;
constexpr double kMaxVertexStep = 0.5;
// The longest wait between tries of the exact Hessian (see run).
constexpr int kMaxExactSkip = 2;
// The exact Hessian is tried only after a step that lowered the energy by less than this fraction of
// it: far from the minimum it is not positive definite (the 100k dumbbell's tries after steps that gained
// a third of the energy all failed, each a factorization spent for nothing: 4 of its 26).
constexpr double kExactTryDrop = 0.05;
// How often a full step of the area energy may be doubled (run). Its model asks each triangle for its
// target area as a 1-D Newton step in S does; for a triangle much smaller than its target that step
// gets only part of the way (S -> S/(1 - ln(S/A)): from e^-3 of the target to e^-1.6), so on the paper's
// maps, where the poles' regions are crushed, the first steps fell short: doubling them took armadillo
// from 26 steps to 20, the fox and the knight from 46 and 47 to 32, and the 100k dumbbell from 20 to 18.
constexpr int kMaxExtensions = 3;
// The Newton system's first shift μ over its mean diagonal (see solve).
constexpr double kFirstRelativeShift = 1e-9;

// Orthonormal tangent basis at the unit vector p (right-handed with p).
void tangent_basis(const Vec3& p, Vec3& e1, Vec3& e2) {
  const Vec3 helper = std::abs(p[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  e1 = normalized(cross(helper, p));
  e2 = cross(p, e1);
}

// Triangles per chunk of the parallel loops: the chunks are fixed whatever the thread count, and the
// results are combined chunk by chunk in order, so sums are the same on any number of threads.
constexpr std::int64_t kChunk = 2048;

// A triangle's share of the Newton system in its corners' tangent coordinates: the gradient (6) and the
// lower triangle of the projected Hessian (21, row by row: (0,0), (1,0), (1,1), (2,0), ...).
struct LocalTerms {
  double gradient[6];
  double hessian[21];
};

constexpr int lower_index(int row, int column) { return row * (row + 1) / 2 + column; }

// The second term of `options`' energy.
detail::SecondTerm second_term(const SphereOptimizeOptions& options) {
  return options.energy == SphereEnergy::kConformal
             ? detail::SecondTerm(options.collapse_barrier_weight, options.collapse_threshold)
             : detail::SecondTerm(options.shape_weight);
}

// The rest positions times the power of two that brings the largest coordinate into [0.5, 1). Exact, so
// the energy is the same to the bit; but surfaces of coordinates near 1e±300, whose areas would overflow
// or underflow, give the same map as any other size. Throws std::invalid_argument on a coordinate that
// is not finite.
std::vector<Vec3> unit_scaled(const std::vector<Vec3>& rest) {
  double largest = 0;
  for (std::size_t v = 0; v < rest.size(); ++v)
    for (const double x : rest[v]) {
      if (!std::isfinite(x))
        throw std::invalid_argument("optimize_on_sphere: rest position " + std::to_string(v) + " is not finite");
      largest = std::max(largest, std::abs(x));
    }
  if (largest == 0) return rest;
  int exponent = 0;
  std::frexp(largest, &exponent);
  std::vector<Vec3> scaled(rest.size());
  for (std::size_t v = 0; v < rest.size(); ++v)
    for (int k = 0; k < 3; ++k) scaled[v][k] = std::ldexp(rest[v][k], -exponent);
  return scaled;
}

}  // namespace

namespace detail {

class SphereOptimizer::Optimizer {
 public:
  Optimizer(const std::vector<Vec3>& rest, const std::vector<Triangle>& triangles, const std::vector<char>& fixed,
            const SphereOptimizeOptions& options)
      : triangles_(triangles),
        options_(options),
        dof_(fixed.size(), -1),
        threads_(detail::surface_threads(options.threads)),
        term_(second_term(options)) {
    const auto scaled = unit_scaled(rest);
    number_unknowns(scaled, fixed);
    auto& common = cholesky_.cholmod();
    common.print = 0;  // a matrix that is not positive definite is an answer here, not an error
    // The unknowns come in geometric nested-dissection order (number_unknowns): CHOLMOD compares it, as
    // it stands, with AMD and keeps the better by its own measure (on smooth shapes the geometric order,
    // on molecular surfaces and armadillo AMD's). Its default search took 0.55 s longer on 100k vertices.
    // With the natural order, no postorder and the upper triangle, CHOLMOD factorizes the matrix in place
    // instead of transposing it first, every step.
    common.nmethods = 2;
    common.method[0].ordering = CHOLMOD_NATURAL;
    common.method[1].ordering = CHOLMOD_AMD;
    common.postorder = 0;
    build_rest(scaled);
  }

  // One optimization from `sphere` with `stage`'s weights, tolerance and iteration cap (the energy and
  // the rest scaling stay the constructor's); the pattern and CHOLMOD's analysis serve every call.
  SphereOptimizeReport run(std::vector<Vec3>& sphere, const SphereOptimizeOptions& stage) {
    options_.shape_weight = stage.shape_weight;
    options_.collapse_barrier_weight = stage.collapse_barrier_weight;
    options_.collapse_threshold = stage.collapse_threshold;
    options_.max_iterations = stage.max_iterations;
    options_.relative_tolerance = stage.relative_tolerance;
    term_ = second_term(options_);
    relative_shift_ = kFirstRelativeShift;
    if (sphere.size() != dof_.size())
      throw std::invalid_argument("optimize_on_sphere: " + std::to_string(sphere.size()) + " sphere points for " +
                                  std::to_string(dof_.size()) + " vertices");
    if (!valid(sphere) || !std::isfinite(energy(sphere)))
      throw std::invalid_argument(
          "optimize_on_sphere: the start is not a valid map (a triangle is not positively oriented)");
    sphere_.swap(sphere);
    const auto report = run();
    sphere_.swap(sphere);
    return report;
  }

  double unit_energy(const std::vector<Vec3>& points) const {
    if (points.size() != dof_.size())
      throw std::invalid_argument("SphereOptimizer::energy: " + std::to_string(points.size()) + " points for " +
                                  std::to_string(dof_.size()) + " vertices");
    return energy(points) / total_area_;
  }

  double energy(const std::vector<Vec3>& points) const {
    const auto count = static_cast<std::int64_t>(triangles_.size());
    std::vector<double> partial(static_cast<std::size_t>((count + kChunk - 1) / kChunk), 0.0);
    detail::parallel_ranges(count, kChunk, threads_, [&](std::int64_t first, std::int64_t last) {
      double sum = 0;
      for (auto t = first; t < last && std::isfinite(sum); ++t) {
        const auto& tri = triangles_[static_cast<std::size_t>(t)];
        sum += detail::triangle_energy(options_.energy, term_, rest_[static_cast<std::size_t>(t)], points[tri[0]],
                                       points[tri[1]], points[tri[2]]);
      }
      partial[static_cast<std::size_t>(first / kChunk)] = sum;
    });
    double total = 0;
    for (const double sum : partial) total += sum;
    return total;
  }

  bool valid(const std::vector<Vec3>& points) const {
    std::atomic<bool> ok{true};
    detail::parallel_ranges(static_cast<std::int64_t>(triangles_.size()), kChunk, threads_,
                            [&](std::int64_t first, std::int64_t last) {
                              for (auto t = first; t < last && ok.load(std::memory_order_relaxed); ++t) {
                                const auto& tri = triangles_[static_cast<std::size_t>(t)];
                                if (orientation_sign(points[tri[0]], points[tri[1]], points[tri[2]]) <= 0)
                                  ok.store(false, std::memory_order_relaxed);
                              }
                            });
    return ok.load();
  }

  SphereOptimizeReport run() {
    SphereOptimizeReport report;
    factorizations_ = 0;
    double current = energy(sphere_);
    report.energy_before = report.energy_after = current / total_area_;
    report.stop_reason = OptimizeStop::kIterations;
    if (free_count_ == 0) {
      report.stop_reason = OptimizeStop::kConverged;
      return report;
    }
    if (!analysed_) build_pattern();
    std::vector<Vec3> e1(sphere_.size()), e2(sphere_.size()), trial(sphere_), longer;
    // Near the minimum the per-triangle projection throws away curvature the sum has, and the steps
    // converge only linearly: after a full, uncut step the next one tries the Hessian as it is, and
    // keeps it if CHOLMOD factorizes it (positive definite) and its step descends; else the projected one.
    bool exact = false;
    // After a failed try the exact Hessian waits for 1, then 2 full steps (kMaxExactSkip at most): on
    // 5hr7's surface it failed on every one of 52 tries, each a factorization spent for nothing.
    int exact_skip = 0, exact_wait = 0;
    for (int iteration = 0; iteration < options_.max_iterations; ++iteration) {
      for (std::size_t v = 0; v < sphere_.size(); ++v)
        if (dof_[v] >= 0) tangent_basis(sphere_[v], e1[v], e2[v]);
      Eigen::VectorXd gradient;
      assemble(e1, e2, gradient, exact);
      Eigen::VectorXd step;
      bool solved = solve(gradient, step, exact ? 1 : 12);
      if (exact && (!solved || !(gradient.dot(step) < 0))) {
        exact = false;
        exact_skip = std::min(std::max(1, 2 * exact_skip), kMaxExactSkip);
        exact_wait = exact_skip;
        assemble(e1, e2, gradient, exact);
        solved = solve(gradient, step, 12);
      }
      if (!solved) {
        report.stop_reason = OptimizeStop::kFactorization;
        break;
      }
      double slope = gradient.dot(step);
      if (!(slope < 0)) step = -gradient, slope = -gradient.squaredNorm();
      if (slope == 0) {
        report.stop_reason = OptimizeStop::kConverged;
        break;
      }
      double largest = 0;
      for (Eigen::Index i = 0; i + 1 < step.size(); i += 2)
        largest = std::max(largest, std::hypot(step[i], step[i + 1]));
      double alpha = largest > kMaxVertexStep ? kMaxVertexStep / largest : 1.0;
      const double first_alpha = alpha;
      // The points at `length` times the step.
      auto place = [&](double length, std::vector<Vec3>& out) {
        detail::parallel_ranges(static_cast<std::int64_t>(sphere_.size()), 4 * kChunk, threads_,
                                [&](std::int64_t first, std::int64_t last) {
                                  for (auto v = static_cast<std::size_t>(first); v < static_cast<std::size_t>(last);
                                       ++v) {
                                    if (dof_[v] < 0) continue;
                                    const double u = length * step[dof_[v]], w = length * step[dof_[v] + 1];
                                    out[v] = normalized(sphere_[v] + u * e1[v] + w * e2[v]);
                                  }
                                });
      };
      bool accepted = false;
      double trial_energy = current;
      for (int k = 0; k < kMaxBacktracks && !accepted; ++k, alpha *= kBacktrack) {
        place(alpha, trial);
        trial_energy = energy(trial);
        accepted = trial_energy <= current + kArmijo * alpha * slope && valid(trial);
      }
      const bool full = accepted && alpha / kBacktrack == 1.0 && first_alpha == 1.0;
      // The area energy's full steps are often short (see kMaxExtensions): twice as long, while that
      // lowers the energy further and keeps the map valid.
      if (full && options_.energy == SphereEnergy::kLogAreaRatio) {
        if (longer.empty()) longer = sphere_;
        for (double length = 2; length <= (1 << kMaxExtensions) && length * largest <= kMaxVertexStep; length *= 2) {
          place(length, longer);
          const double longer_energy = energy(longer);
          if (!(longer_energy < trial_energy) || !valid(longer)) break;
          trial.swap(longer);
          trial_energy = longer_energy;
        }
      }
      if (!accepted) {
        report.stop_reason = OptimizeStop::kLineSearch;
        break;
      }
      sphere_.swap(trial);
      // A full Newton step taken uncut, near the minimum (kExactTryDrop): the next step tries the Hessian
      // as it is (see exact above), unless it waits after a failed try.
      if (exact) exact_skip = 0;  // it worked: try it again after the next full step
      exact = false;
      const double drop = current - trial_energy;
      if (full && drop < kExactTryDrop * current && exact_wait-- <= 0) exact = true;
      ++report.iterations;
      current = trial_energy;
      if (drop < options_.relative_tolerance * current) {
        report.stop_reason = OptimizeStop::kConverged;
        break;
      }
    }
    report.energy_after = current / total_area_;
    report.factorizations = factorizations_;
    return report;
  }

 private:
  // Each free vertex's two tangent coordinates are consecutive unknowns, the vertices in the geometric
  // nested-dissection order of the surface (harmonic.hpp): the factorization's fill-reducing order.
  void number_unknowns(const std::vector<Vec3>& rest, const std::vector<char>& fixed) {
    const VertexRings graph = build_vertex_rings(static_cast<std::int32_t>(fixed.size()), triangles_);
    for (const auto v : geometric_elimination_order(graph, rest, fixed).vertices) dof_[v] = 2 * free_count_++;
  }

  // Target areas: each triangle's share of the surface's area (tiny ones raised to
  // min_rest_area_fraction of the mean) as a solid angle, expressed as the ½·det of an equilateral
  // spherical triangle of that solid angle (½·det is the solid angle for small triangles, less for large).
  void build_rest(const std::vector<Vec3>& rest) {
    const auto count = triangles_.size();
    std::vector<double> area(count);
    double surface_total = 0;
    for (std::size_t t = 0; t < count; ++t) {
      const auto& tri = triangles_[t];
      area[t] = triangle_area(rest[tri[0]], rest[tri[1]], rest[tri[2]]);
      surface_total += area[t];
    }
    const double mean = surface_total / static_cast<double>(std::max<std::size_t>(count, 1));
    const double floor = options_.min_rest_area_fraction * mean;
    double clamped_total = 0;
    for (auto& a : area) clamped_total += (a = std::max(a, floor));
    if (!(clamped_total > 0)) {  // a surface of no area: every triangle alike
      std::fill(area.begin(), area.end(), 1.0);
      clamped_total = static_cast<double>(count);
    }
    rest_.resize(count);
    total_area_ = 0;
    for (std::size_t t = 0; t < count; ++t) {
      const auto& tri = triangles_[t];
      const double target = detail::equilateral_half_det(4 * std::numbers::pi * area[t] / clamped_total);
      rest_[t] = detail::rest_triangle(rest[tri[0]], rest[tri[1]], rest[tri[2]], target, options_.min_rest_angle);
      total_area_ += target;
    }
  }

  // The Hessian's sparsity pattern (upper triangle of the free vertices' 2×2 blocks, diagonal always
  // present for the regularization), fixed for every iteration, and where each triangle's local entries
  // go in its value array: the assembly then adds into place, and CHOLMOD's analysis holds for all steps.
  void build_pattern() {
    const Eigen::Index size = 2 * free_count_;
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(triangles_.size() * 21 + static_cast<std::size_t>(size));
    for (const auto& tri : triangles_)
      for_each_local_entry(tri,
                           [&](int, Eigen::Index row, Eigen::Index column) { entries.emplace_back(row, column, 0.0); });
    for (Eigen::Index i = 0; i < size; ++i) entries.emplace_back(i, i, 0.0);
    hessian_.resize(size, size);
    hessian_.setFromTriplets(entries.begin(), entries.end());
    hessian_.makeCompressed();
    auto slot_of = [&](Eigen::Index row, Eigen::Index column) {
      const auto* begin = hessian_.innerIndexPtr() + hessian_.outerIndexPtr()[column];
      const auto* end = hessian_.innerIndexPtr() + hessian_.outerIndexPtr()[column + 1];
      return static_cast<std::int64_t>(std::lower_bound(begin, end, static_cast<int>(row)) - hessian_.innerIndexPtr());
    };
    slots_.assign(triangles_.size() * 21, -1);
    for (std::size_t t = 0; t < triangles_.size(); ++t)
      for_each_local_entry(triangles_[t], [&](int local, Eigen::Index row, Eigen::Index column) {
        slots_[21 * t + static_cast<std::size_t>(local)] = slot_of(row, column);
      });
    diagonal_slots_.resize(static_cast<std::size_t>(size));
    for (Eigen::Index i = 0; i < size; ++i) diagonal_slots_[static_cast<std::size_t>(i)] = slot_of(i, i);
    locals_.resize(triangles_.size());
  }

  // Calls f(local, row, column) for each entry of the triangle's local lower triangle (local index as in
  // LocalTerms::hessian) whose two corners are free, with its place in the global matrix's upper
  // triangle (row <= column: CHOLMOD factorizes the upper triangle without transposing it).
  template <typename F>
  void for_each_local_entry(const Triangle& tri, F&& f) const {
    for (int p = 0; p < 6; ++p)
      for (int q = 0; q <= p; ++q) {
        const auto a = dof_[tri[p / 2]], b = dof_[tri[q / 2]];
        if (a < 0 || b < 0) continue;
        const Eigen::Index row = a + p % 2, column = b + q % 2;
        f(lower_index(p, q), std::min(row, column), std::max(row, column));
      }
  }

  // One triangle's gradient and projected Hessian in the tangent coordinates of its free corners:
  // u_v along e1[v], w_v along e2[v], p_v(u, w) = (p_v + u e1 + w e2)/|…| (a fixed corner's are 0).
  void local_terms(std::size_t t, const std::vector<Vec3>& e1, const std::vector<Vec3>& e2, bool exact,
                   LocalTerms& out) const {
    const auto& tri = triangles_[t];
    detail::Vector9 g;
    detail::Matrix9 h;
    detail::triangle_energy(options_.energy, term_, rest_[t], sphere_[tri[0]], sphere_[tri[1]], sphere_[tri[2]], g, h,
                            !exact);
    // (!exact: the area energy's model Hessian, its area term at least as curved as its secant.)
    Eigen::Matrix<double, 3, 2> basis[3];
    for (int k = 0; k < 3; ++k) {
      const auto v = tri[k];
      if (dof_[v] < 0) {
        basis[k].setZero();
        continue;
      }
      for (int i = 0; i < 3; ++i) basis[k](i, 0) = e1[v][i], basis[k](i, 1) = e2[v][i];
    }
    Vector6 local_gradient;
    Matrix6 local;
    for (int k = 0; k < 3; ++k) {
      local_gradient.segment<2>(2 * k) = basis[k].transpose() * g.segment<3>(3 * k);
      for (int l = 0; l <= k; ++l) {
        local.block<2, 2>(2 * k, 2 * l) = basis[k].transpose() * h.block<3, 3>(3 * k, 3 * l) * basis[l];
        if (l < k) local.block<2, 2>(2 * l, 2 * k) = local.block<2, 2>(2 * k, 2 * l).transpose();
      }
    }
    // The retraction's curvature: d²/dt² of E(p + t e - ½t²p) adds -(∇E·p) to each tangent direction.
    for (int k = 0; k < 3; ++k) {
      const auto& p = sphere_[tri[k]];
      const double radial = g[3 * k] * p[0] + g[3 * k + 1] * p[1] + g[3 * k + 2] * p[2];
      if (dof_[tri[k]] >= 0) local(2 * k, 2 * k) -= radial, local(2 * k + 1, 2 * k + 1) -= radial;
    }
    // Projected Newton: the local Hessian with its negative eigenvalues set to 0 (only when it is not
    // positive definite already, which a Cholesky factorization tells cheaply).
    if (!exact && Eigen::LLT<Matrix6>(local).info() != Eigen::Success) {
      Eigen::SelfAdjointEigenSolver<Matrix6> eigen(local);
      const Vector6 clamped = eigen.eigenvalues().cwiseMax(0.0);
      local = eigen.eigenvectors() * clamped.asDiagonal() * eigen.eigenvectors().transpose();
    }
    for (int p = 0; p < 6; ++p) {
      out.gradient[p] = local_gradient[p];
      for (int q = 0; q <= p; ++q) out.hessian[lower_index(p, q)] = local(p, q);
    }
  }

  // Gradient and projected Hessian (into hessian_'s fixed pattern): the triangles' local terms on every
  // thread, then added in triangle order on one, so the sums are the same on any number of threads.
  void assemble(const std::vector<Vec3>& e1, const std::vector<Vec3>& e2, Eigen::VectorXd& gradient, bool exact) {
    detail::parallel_ranges(static_cast<std::int64_t>(triangles_.size()), kChunk, threads_,
                            [&](std::int64_t first, std::int64_t last) {
                              for (auto t = static_cast<std::size_t>(first); t < static_cast<std::size_t>(last); ++t)
                                local_terms(t, e1, e2, exact, locals_[t]);
                            });
    gradient = Eigen::VectorXd::Zero(2 * free_count_);
    double* values = hessian_.valuePtr();
    std::fill(values, values + hessian_.nonZeros(), 0.0);
    for (std::size_t t = 0; t < triangles_.size(); ++t) {
      const auto& tri = triangles_[t];
      const auto& local = locals_[t];
      for (int k = 0; k < 3; ++k) {
        const auto row = dof_[tri[k]];
        if (row < 0) continue;
        gradient[row] += local.gradient[2 * k];
        gradient[row + 1] += local.gradient[2 * k + 1];
      }
      const std::int64_t* slot = &slots_[21 * t];
      for (int i = 0; i < 21; ++i)
        if (slot[i] >= 0) values[slot[i]] += local.hessian[i];
    }
  }

  // Newton's step: H d = -g with H + μI, μ raised until the factorization succeeds (the projected
  // Hessian is only semi-definite: rotations about the fixed poles' axis cost nothing). Each step of a
  // run starts from the μ (relative to the mean diagonal) that last worked: each failed try costs a
  // factorization.
  bool solve(const Eigen::VectorXd& gradient, Eigen::VectorXd& step, int attempts) {
    double* values = hessian_.valuePtr();
    std::vector<double> diagonal(diagonal_slots_.size());
    double trace = 0;
    for (std::size_t i = 0; i < diagonal_slots_.size(); ++i) trace += (diagonal[i] = values[diagonal_slots_[i]]);
    const double scale = std::max(trace / static_cast<double>(hessian_.rows()), 1e-300);
    double mu = relative_shift_ * scale;
    const detail::SolverSection section;  // the analysis, factorizations and solves below
    if (!analysed_) {
      cholesky_.analyzePattern(hessian_);
      analysed_ = true;
    }
    for (int attempt = 0; attempt < attempts; ++attempt, mu *= 100) {
      for (std::size_t i = 0; i < diagonal_slots_.size(); ++i) values[diagonal_slots_[i]] = diagonal[i] + mu;
      cholesky_.factorize(hessian_);
      ++factorizations_;
      if (cholesky_.info() != Eigen::Success) continue;
      step = cholesky_.solve(-gradient);
      if (cholesky_.info() == Eigen::Success && step.allFinite()) {
        relative_shift_ = mu / scale;
        return true;
      }
    }
    return false;
  }

  const std::vector<Triangle>& triangles_;
  std::vector<Vec3> sphere_;  // the points of the run under way
  SphereOptimizeOptions options_;
  std::vector<Eigen::Index> dof_;  // first tangent coordinate of each free vertex, -1 if fixed
  Eigen::Index free_count_ = 0;
  int threads_;
  detail::SecondTerm term_;  // the energy's second term
  std::vector<detail::RestTriangle> rest_;
  double total_area_ = 0;
  SparseMatrix hessian_;             // fixed pattern, values refilled every iteration
  std::vector<std::int64_t> slots_;  // 21 per triangle: where its local entries go in hessian_ (-1: none)
  std::vector<std::int64_t> diagonal_slots_;
  std::vector<LocalTerms> locals_;
  Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Upper> cholesky_;
  bool analysed_ = false;
  int factorizations_ = 0;                       // in the run under way
  double relative_shift_ = kFirstRelativeShift;  // μ over the mean diagonal that last factorized
};

SphereOptimizer::SphereOptimizer(const std::vector<Vec3>& rest, const std::vector<Triangle>& triangles,
                                 const std::vector<char>& fixed, const SphereOptimizeOptions& options) {
  if (rest.size() != fixed.size())
    throw std::invalid_argument("optimize_on_sphere: " + std::to_string(rest.size()) + " rest positions and " +
                                std::to_string(fixed.size()) + " fixed flags");
  optimizer_ = std::make_unique<Optimizer>(rest, triangles, fixed, options);
}

SphereOptimizer::~SphereOptimizer() = default;

SphereOptimizeReport SphereOptimizer::run(std::vector<Vec3>& sphere, const SphereOptimizeOptions& options) {
  return optimizer_->run(sphere, options);
}

double SphereOptimizer::energy(const std::vector<Vec3>& sphere) const { return optimizer_->unit_energy(sphere); }

}  // namespace detail

SphereOptimizeReport optimize_on_sphere(const std::vector<Vec3>& rest, const std::vector<Triangle>& triangles,
                                        std::vector<Vec3>& sphere, const std::vector<char>& fixed,
                                        const SphereOptimizeOptions& options) {
  if (rest.size() != sphere.size() || fixed.size() != sphere.size())
    throw std::invalid_argument("optimize_on_sphere: " + std::to_string(rest.size()) + " rest positions, " +
                                std::to_string(sphere.size()) + " sphere points and " + std::to_string(fixed.size()) +
                                " fixed flags");
  detail::SphereOptimizer optimizer(rest, triangles, fixed, options);
  return optimizer.run(sphere, options);
}

}  // namespace spheremap
