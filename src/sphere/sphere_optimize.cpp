#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>
#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "solver_section.hpp"
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

// Orthonormal tangent basis at the unit vector p (right-handed with p).
void tangent_basis(const Vec3& p, Vec3& e1, Vec3& e2) {
  const Vec3 helper = std::abs(p[0]) < 0.9 ? Vec3{1, 0, 0} : Vec3{0, 1, 0};
  e1 = normalized(cross(helper, p));
  e2 = cross(p, e1);
}

class Optimizer {
 public:
  Optimizer(const std::vector<Vec3>& rest, const std::vector<Triangle>& triangles, std::vector<Vec3>& sphere,
            const std::vector<char>& fixed, const SphereOptimizeOptions& options)
      : triangles_(triangles), sphere_(sphere), options_(options), dof_(sphere.size(), -1) {
    for (std::size_t v = 0; v < sphere.size(); ++v)
      if (!fixed[v]) dof_[v] = 2 * free_count_++;
    build_rest(rest);
  }

  double energy(const std::vector<Vec3>& points) const {
    double total = 0;
    for (std::size_t t = 0; t < triangles_.size(); ++t) {
      const auto& tri = triangles_[t];
      total += detail::triangle_energy(options_.energy, rest_[t], points[tri[0]], points[tri[1]], points[tri[2]]);
      if (!std::isfinite(total)) return total;
    }
    return total;
  }

  bool valid(const std::vector<Vec3>& points) const {
    for (const auto& tri : triangles_)
      if (orientation_sign(points[tri[0]], points[tri[1]], points[tri[2]]) <= 0) return false;
    return true;
  }

  SphereOptimizeReport run() {
    SphereOptimizeReport report;
    double current = energy(sphere_);
    report.energy_before = report.energy_after = current / total_area_;
    report.stop_reason = OptimizeStop::kIterations;
    if (free_count_ == 0) {
      report.stop_reason = OptimizeStop::kConverged;
      return report;
    }
    for (int iteration = 0; iteration < options_.max_iterations; ++iteration) {
      std::vector<Vec3> e1(sphere_.size()), e2(sphere_.size());
      for (std::size_t v = 0; v < sphere_.size(); ++v)
        if (dof_[v] >= 0) tangent_basis(sphere_[v], e1[v], e2[v]);
      Eigen::VectorXd gradient;
      SparseMatrix hessian;
      assemble(e1, e2, gradient, hessian);
      Eigen::VectorXd step;
      if (!solve(hessian, gradient, step)) {
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
      bool accepted = false;
      std::vector<Vec3> trial(sphere_);
      double trial_energy = current;
      for (int k = 0; k < kMaxBacktracks && !accepted; ++k, alpha *= kBacktrack) {
        for (std::size_t v = 0; v < sphere_.size(); ++v) {
          if (dof_[v] < 0) continue;
          const double u = alpha * step[dof_[v]], w = alpha * step[dof_[v] + 1];
          trial[v] = normalized(sphere_[v] + u * e1[v] + w * e2[v]);
        }
        trial_energy = energy(trial);
        accepted = trial_energy <= current + kArmijo * alpha * slope && valid(trial);
      }
      if (!accepted) {
        report.stop_reason = OptimizeStop::kLineSearch;
        break;
      }
      sphere_.swap(trial);
      ++report.iterations;
      const double drop = current - trial_energy;
      current = trial_energy;
      if (drop < options_.relative_tolerance * current) {
        report.stop_reason = OptimizeStop::kConverged;
        break;
      }
    }
    report.energy_after = current / total_area_;
    return report;
  }

 private:
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

  // Gradient and projected (positive semi-definite per triangle) Hessian in the tangent coordinates of
  // the free vertices: u_v along e1[v], w_v along e2[v], p_v(u, w) = (p_v + u e1 + w e2)/|…|.
  void assemble(const std::vector<Vec3>& e1, const std::vector<Vec3>& e2, Eigen::VectorXd& gradient,
                SparseMatrix& hessian) const {
    const Eigen::Index size = 2 * free_count_;
    gradient = Eigen::VectorXd::Zero(size);
    std::vector<Eigen::Triplet<double>> entries;
    entries.reserve(triangles_.size() * 36 + static_cast<std::size_t>(size));
    detail::Vector9 g;
    detail::Matrix9 h;
    for (std::size_t t = 0; t < triangles_.size(); ++t) {
      const auto& tri = triangles_[t];
      detail::triangle_energy(options_.energy, rest_[t], sphere_[tri[0]], sphere_[tri[1]], sphere_[tri[2]], g, h);
      Eigen::Matrix<double, 9, 6> basis = Eigen::Matrix<double, 9, 6>::Zero();
      for (int k = 0; k < 3; ++k) {
        const auto v = tri[k];
        if (dof_[v] < 0) continue;
        for (int i = 0; i < 3; ++i) basis(3 * k + i, 2 * k) = e1[v][i], basis(3 * k + i, 2 * k + 1) = e2[v][i];
      }
      const Vector6 local_gradient = basis.transpose() * g;
      Matrix6 local = basis.transpose() * h * basis;
      // The retraction's curvature: d²/dt² of E(p + t e - ½t²p) adds -(∇E·p) to each tangent direction.
      for (int k = 0; k < 3; ++k) {
        const auto& p = sphere_[tri[k]];
        const double radial = g[3 * k] * p[0] + g[3 * k + 1] * p[1] + g[3 * k + 2] * p[2];
        if (dof_[tri[k]] >= 0) local(2 * k, 2 * k) -= radial, local(2 * k + 1, 2 * k + 1) -= radial;
      }
      // Projected Newton: the local Hessian with its negative eigenvalues set to 0 (only when it is not
      // positive definite already, which a Cholesky factorization tells cheaply).
      if (Eigen::LLT<Matrix6>(local).info() != Eigen::Success) {
        Eigen::SelfAdjointEigenSolver<Matrix6> eigen(local);
        const Vector6 clamped = eigen.eigenvalues().cwiseMax(0.0);
        local = eigen.eigenvectors() * clamped.asDiagonal() * eigen.eigenvectors().transpose();
      }
      for (int k = 0; k < 3; ++k) {
        const auto row = dof_[tri[k]];
        if (row < 0) continue;
        gradient[row] += local_gradient[2 * k];
        gradient[row + 1] += local_gradient[2 * k + 1];
        for (int l = 0; l < 3; ++l) {
          const auto column = dof_[tri[l]];
          if (column < 0) continue;
          for (int i = 0; i < 2; ++i)
            for (int j = 0; j < 2; ++j)
              if (row + i >= column + j) entries.emplace_back(row + i, column + j, local(2 * k + i, 2 * l + j));
        }
      }
    }
    for (Eigen::Index i = 0; i < size; ++i) entries.emplace_back(i, i, 0.0);  // the regularization's slots
    hessian.resize(size, size);
    hessian.setFromTriplets(entries.begin(), entries.end());
  }

  // Newton's step: H d = -g with H + μI, μ raised until the factorization succeeds (the projected
  // Hessian is only semi-definite: rotations about the fixed poles' axis cost nothing).
  bool solve(SparseMatrix& hessian, const Eigen::VectorXd& gradient, Eigen::VectorXd& step) {
    double trace = 0;
    for (Eigen::Index i = 0; i < hessian.rows(); ++i) trace += hessian.coeff(i, i);
    double mu = 1e-9 * std::max(trace / static_cast<double>(hessian.rows()), 1e-300);
    const detail::SolverSection section;  // the analysis, factorizations and solves below
    if (!analysed_) {
      cholesky_.analyzePattern(hessian);
      analysed_ = true;
    }
    for (int attempt = 0; attempt < 12; ++attempt, mu *= 100) {
      SparseMatrix shifted = hessian;
      for (Eigen::Index i = 0; i < shifted.rows(); ++i) shifted.coeffRef(i, i) += mu;
      cholesky_.factorize(shifted);
      if (cholesky_.info() != Eigen::Success) continue;
      step = cholesky_.solve(-gradient);
      if (cholesky_.info() == Eigen::Success && step.allFinite()) return true;
    }
    return false;
  }

  const std::vector<Triangle>& triangles_;
  std::vector<Vec3>& sphere_;
  const SphereOptimizeOptions& options_;
  std::vector<Eigen::Index> dof_;  // first tangent coordinate of each free vertex, -1 if fixed
  Eigen::Index free_count_ = 0;
  std::vector<detail::RestTriangle> rest_;
  double total_area_ = 0;
  Eigen::CholmodSupernodalLLT<SparseMatrix, Eigen::Lower> cholesky_;
  bool analysed_ = false;
};

}  // namespace

SphereOptimizeReport optimize_on_sphere(const std::vector<Vec3>& rest, const std::vector<Triangle>& triangles,
                                        std::vector<Vec3>& sphere, const std::vector<char>& fixed,
                                        const SphereOptimizeOptions& options) {
  if (rest.size() != sphere.size() || fixed.size() != sphere.size())
    throw std::invalid_argument("optimize_on_sphere: " + std::to_string(rest.size()) + " rest positions, " +
                                std::to_string(sphere.size()) + " sphere points and " + std::to_string(fixed.size()) +
                                " fixed flags");
  Optimizer optimizer(rest, triangles, sphere, fixed, options);
  if (!optimizer.valid(sphere) || !std::isfinite(optimizer.energy(sphere)))
    throw std::invalid_argument(
        "optimize_on_sphere: the start is not a valid map (a triangle is not positively oriented)");
  return optimizer.run();
}

}  // namespace spheremap
