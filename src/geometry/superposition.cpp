#include "spheremap/geometry/superposition.hpp"

// GCC's -Wmaybe-uninitialized misfires inside Eigen's tridiagonalization of the 4x4 matrix.
#pragma GCC diagnostic push
#pragma GCC diagnostic ignored "-Wmaybe-uninitialized"
#include <Eigen/Eigenvalues>
#pragma GCC diagnostic pop

#include <algorithm>
#include <cmath>
#include <stdexcept>
#include <string>

#include "spheremap/geometry/vec.hpp"

namespace spheremap {
namespace {

// The 4x4 matrices of quaternion multiplication: p q = left(p) q and q p = right(p) q.
Eigen::Matrix4d left_multiplication(const Vec3& p) {
  Eigen::Matrix4d m;
  m << 0, -p[0], -p[1], -p[2],  //
      p[0], 0, -p[2], p[1],     //
      p[1], p[2], 0, -p[0],     //
      p[2], -p[1], p[0], 0;
  return m;
}
Eigen::Matrix4d right_multiplication(const Vec3& p) {
  Eigen::Matrix4d m;
  m << 0, -p[0], -p[1], -p[2],  //
      p[0], 0, p[2], -p[1],     //
      p[1], -p[2], 0, p[0],     //
      p[2], p[1], -p[0], 0;
  return m;
}

// The superposition computed on the surface points divided by `unit` (scale and rmsd given back in the
// surface's units): unit 1 for ordinary surfaces; larger where squares of the coordinates overflow.
Superposition superpose_in_units(const std::vector<Vec3>& surface_points, const std::vector<Vec3>& sphere_points,
                                 double unit) {
  const auto n = static_cast<double>(surface_points.size());
  Superposition result;
  for (const auto& p : surface_points) result.centroid = result.centroid + (1 / unit) * p;
  result.centroid = (1 / n) * result.centroid;
  double squared_spread = 0;
  for (const auto& p : surface_points) squared_spread += squared_distance((1 / unit) * p, result.centroid);
  const double scale = std::sqrt(squared_spread / n);

  // Kearsley 1989: for a unit quaternion q with R x = q x q̄, |R x - y| = |q x - y q| =
  // |(right(x) - left(y)) q|, so Σ|R x_i - y_i|² = qᵀ M q with M = Σ AᵢᵀAᵢ, and the best rotation is
  // the eigenvector of M's smallest eigenvalue (which equals the minimal sum of squared residuals).
  Eigen::Matrix4d m = Eigen::Matrix4d::Zero();
  for (std::size_t i = 0; i < surface_points.size(); ++i) {
    const Vec3 x = scale * sphere_points[i];
    const Vec3 y = (1 / unit) * surface_points[i] - result.centroid;
    const Eigen::Matrix4d a = right_multiplication(x) - left_multiplication(y);
    m += a.transpose() * a;
  }
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix4d> solver(m);
  const Eigen::Vector4d q = solver.eigenvectors().col(0).normalized();  // eigenvalues ascend
  const double w = q[0], x = q[1], y = q[2], z = q[3];
  result.rotation = {1 - 2 * (y * y + z * z), 2 * (x * y - w * z),     2 * (x * z + w * y),
                     2 * (x * y + w * z),     1 - 2 * (x * x + z * z), 2 * (y * z - w * x),
                     2 * (x * z - w * y),     2 * (y * z + w * x),     1 - 2 * (x * x + y * y)};

  double squared_residual = 0;
  for (std::size_t i = 0; i < surface_points.size(); ++i)
    squared_residual += squared_distance(scale * rotate(result.rotation, sphere_points[i]),
                                         (1 / unit) * surface_points[i] - result.centroid);
  result.rmsd = unit * std::sqrt(squared_residual / n);
  result.scale = unit * scale;
  result.centroid = unit * result.centroid;
  return result;
}

bool finite(const Superposition& s) {
  for (const double r : s.rotation)
    if (!std::isfinite(r)) return false;
  return std::isfinite(s.scale) && std::isfinite(s.rmsd);
}

}  // namespace

Superposition superpose_sphere_on_surface(const std::vector<Vec3>& surface_points,
                                          const std::vector<Vec3>& sphere_points) {
  if (surface_points.size() != sphere_points.size() || surface_points.size() < 3)
    throw std::invalid_argument("superpose_sphere_on_surface: needs two equally long lists of at least 3 points, got " +
                                std::to_string(surface_points.size()) + " and " + std::to_string(sphere_points.size()));
  Superposition result = superpose_in_units(surface_points, sphere_points, 1);
  if (finite(result)) return result;
  // Coordinates whose squares overflow (1e200): the same in units of the largest coordinate.
  double largest = 0;
  for (const auto& p : surface_points)
    for (const double c : p) largest = std::max(largest, std::abs(c));
  if (largest > 0 && std::isfinite(largest)) result = superpose_in_units(surface_points, sphere_points, largest);
  return result;
}

Vec3 rotate(const std::array<double, 9>& rotation, const Vec3& v) {
  return {rotation[0] * v[0] + rotation[1] * v[1] + rotation[2] * v[2],
          rotation[3] * v[0] + rotation[4] * v[1] + rotation[5] * v[2],
          rotation[6] * v[0] + rotation[7] * v[1] + rotation[8] * v[2]};
}

std::array<double, 9> transposed(const std::array<double, 9>& r) {
  return {r[0], r[3], r[6], r[1], r[4], r[7], r[2], r[5], r[8]};
}

}  // namespace spheremap
