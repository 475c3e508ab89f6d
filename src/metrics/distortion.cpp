#include "spheremap/metrics/distortion.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <string>

#include "spheremap/geometry/vec.hpp"
#include "spheremap/sphere/certify.hpp"

namespace spheremap {
namespace {

constexpr double kDegreesPerRadian = 180.0 / std::numbers::pi;

// Angle between two vectors; atan2 of |u×v| and u·v stays accurate for angles near 0 and π, where
// acos of the normalized dot product loses half the digits.
std::optional<double> angle_between(const Vec3& u, const Vec3& v) {
  if (norm(u) == 0 || norm(v) == 0) return std::nullopt;
  return std::atan2(norm(cross(u, v)), dot(u, v));
}

// Direction of the great-circle arc from a towards b, in the tangent plane at a. Written with
// d = b - a, which is the accurate form when b is close to a (a·d = -|d|²/2 carries no cancellation).
Vec3 arc_tangent(const Vec3& a, const Vec3& b) {
  const Vec3 d = b - a;
  return d - dot(a, d) * a;
}

// The triangle's edges p1 - p0 and p2 - p0 in an orthonormal frame of its own plane, as the columns
// of an upper-triangular 2x2 matrix [[e1x, e2x], [0, e2y]]; nullopt when the triangle is degenerate.
struct PlanarEdges {
  double e1x, e2x, e2y;
};
std::optional<PlanarEdges> planar_edges(const Vec3& p0, const Vec3& p1, const Vec3& p2) {
  const Vec3 e1 = p1 - p0;
  const Vec3 e2 = p2 - p0;
  const double e1_length = norm(e1);
  const double doubled_area = norm(cross(e1, e2));
  if (e1_length == 0 || doubled_area == 0) return std::nullopt;
  return PlanarEdges{e1_length, dot(e1, e2) / e1_length, doubled_area / e1_length};
}

// K = σ_max/σ_min of the linear part of the affine map taking the surface triangle onto the chord
// triangle; nullopt when the surface triangle is degenerate, +inf when the chord triangle is.
std::optional<double> dilatation(const Vec3& p0, const Vec3& p1, const Vec3& p2, const Vec3& s0, const Vec3& s1,
                                 const Vec3& s2) {
  const auto from = planar_edges(p0, p1, p2);
  if (!from) return std::nullopt;
  const auto to = planar_edges(s0, s1, s2);
  if (!to) return std::numeric_limits<double>::infinity();
  // J = To * From^-1, both upper triangular.
  const double inverse11 = 1 / from->e1x;
  const double inverse22 = 1 / from->e2y;
  const double inverse12 = -from->e2x * inverse11 * inverse22;
  const double a = to->e1x * inverse11;
  const double b = to->e1x * inverse12 + to->e2x * inverse22;
  const double c = 0;
  const double d = to->e2y * inverse22;
  // Closed-form singular values of [[a, b], [c, d]]: σ = q ± r (Blinn's decomposition).
  const double q = std::hypot((a + d) / 2, (c - b) / 2);
  const double r = std::hypot((a - d) / 2, (c + b) / 2);
  const double smallest = std::fabs(q - r);
  return smallest > 0 ? (q + r) / smallest : std::numeric_limits<double>::infinity();
}

// Octant index in the order of DistortionMetrics::octant_area_percent; a zero coordinate counts as +.
int octant_of(const Vec3& direction) {
  return (direction[0] < 0 ? 1 : 0) + (direction[1] < 0 ? 2 : 0) + (direction[2] < 0 ? 4 : 0);
}

struct RunningStatistics {
  double sum = 0;
  double sum_of_squares = 0;
  double max = 0;
  std::int64_t count = 0;
  void add(double value) {
    sum += value;
    sum_of_squares += value * value;
    max = std::max(max, value);
    ++count;
  }
  [[nodiscard]] double mean() const { return count > 0 ? sum / static_cast<double>(count) : 0.0; }
  [[nodiscard]] double rms() const { return count > 0 ? std::sqrt(sum_of_squares / static_cast<double>(count)) : 0.0; }
};

}  // namespace

DistortionMetrics measure_distortion(const Mesh& surface, const std::vector<Vec3>& sphere) {
  if (sphere.size() != surface.positions.size())
    throw std::invalid_argument("measure_distortion: " + std::to_string(sphere.size()) + " sphere points for " +
                                std::to_string(surface.positions.size()) + " surface vertices");

  double total_surface_area = 0;
  for (const auto& t : surface.triangles)
    total_surface_area += triangle_area(surface.positions[t[0]], surface.positions[t[1]], surface.positions[t[2]]);

  RunningStatistics area_deviation, area_log_ratio, angle_deviation;
  RunningStatistics finite_dilatation;
  double dilatation_max = 0;
  std::array<double, 8> octant_area{};
  for (const auto& t : surface.triangles) {
    const std::array<Vec3, 3> p{surface.positions[t[0]], surface.positions[t[1]], surface.positions[t[2]]};
    const std::array<Vec3, 3> s{sphere[t[0]], sphere[t[1]], sphere[t[2]]};
    const double area = triangle_area(p[0], p[1], p[2]);

    if (area > 0) {
      // Folded triangles contribute their unsigned spherical area.
      const double spherical_area = std::fabs(signed_solid_angle(s[0], s[1], s[2]));
      const double ratio = (spherical_area / (4 * std::numbers::pi)) / (area / total_surface_area);
      area_deviation.add(std::fabs(ratio - 1));
      area_log_ratio.add(std::fabs(std::log(std::max(ratio, std::numeric_limits<double>::min()))));
    }

    for (int corner = 0; corner < 3; ++corner) {
      const int next = (corner + 1) % 3, previous = (corner + 2) % 3;
      const auto sphere_angle = angle_between(arc_tangent(s[corner], s[next]), arc_tangent(s[corner], s[previous]));
      const auto surface_angle = angle_between(p[next] - p[corner], p[previous] - p[corner]);
      if (sphere_angle && surface_angle)
        angle_deviation.add(std::fabs(*sphere_angle - *surface_angle) * kDegreesPerRadian);
    }

    if (const auto k = dilatation(p[0], p[1], p[2], s[0], s[1], s[2])) {
      dilatation_max = std::max(dilatation_max, *k);
      if (std::isfinite(*k)) finite_dilatation.add(*k);
    }

    octant_area[octant_of(s[0] + s[1] + s[2])] += area;
  }

  DistortionMetrics metrics;
  metrics.area_distortion_mean_percent = 100 * area_deviation.mean();
  metrics.area_distortion_max_percent = 100 * area_deviation.max;
  metrics.area_log_ratio_mean = area_log_ratio.mean();
  metrics.angle_distortion_mean_degrees = angle_deviation.mean();
  metrics.angle_distortion_rms_degrees = angle_deviation.rms();
  metrics.angle_distortion_max_degrees = angle_deviation.max;
  metrics.dilatation_mean = finite_dilatation.mean();
  metrics.dilatation_max = dilatation_max;
  double squared_deviation = 0;
  for (int octant = 0; octant < 8; ++octant) {
    metrics.octant_area_percent[octant] = total_surface_area > 0 ? 100 * octant_area[octant] / total_surface_area : 0;
    squared_deviation += std::pow(metrics.octant_area_percent[octant] - 12.5, 2);
  }
  metrics.octant_rms_deviation_percent = std::sqrt(squared_deviation / 8);
  return metrics;
}

}  // namespace spheremap
