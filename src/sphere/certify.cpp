#include "spheremap/sphere/certify.hpp"

#include <algorithm>
#include <cmath>
#include <cstdint>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <string>

#include "../util/parallel.hpp"
#include "spheremap/geometry/predicates.hpp"
#include "spheremap/geometry/vec.hpp"

namespace spheremap {
namespace {

// Neumaier's compensated sum: with millions of terms of both signs, plain summation would lose the
// ~1e-12 accuracy the coverage test needs.
class CompensatedSum {
 public:
  void add(double value) {
    const double sum = total_ + value;
    if (std::fabs(total_) >= std::fabs(value))
      compensation_ += (total_ - sum) + value;
    else
      compensation_ += (value - sum) + total_;
    total_ = sum;
  }
  [[nodiscard]] double value() const { return total_ + compensation_; }

 private:
  double total_ = 0;
  double compensation_ = 0;
};

}  // namespace

bool Certificate::certified() const { return folded == 0 && collapsed == 0 && std::fabs(coverage - 1) < 1e-9; }

bool positively_oriented(const std::vector<Triangle>& triangles, const std::vector<Vec3>& sphere) {
  return std::all_of(triangles.begin(), triangles.end(),
                     [&](const Triangle& t) { return orientation_sign(sphere[t[0]], sphere[t[1]], sphere[t[2]]) > 0; });
}

double signed_solid_angle(const Vec3& a, const Vec3& b, const Vec3& c) {
  // tan(Ω/2) = N / D with N = det[a, b, c] and D = 1 + a·b + b·c + c·a. Both are evaluated so that
  // they stay accurate when they are tiny, which happens for small triangles (N) and for thin
  // triangles with two nearly antipodal corners (N and D, Ω near ±2π); evaluated as written, those
  // lose up to half the digits and the coverage of a whole map drifts by 1e-9.
  // Rotate the corners (Ω is invariant under cyclic order) so that (u, w) is the most antipodal pair.
  const double ab = dot(a, b), bc = dot(b, c), ca = dot(c, a);
  const bool ab_lowest = ab <= bc && ab <= ca, bc_lowest = bc < ab && bc <= ca;
  const Vec3& u = ab_lowest ? b : (bc_lowest ? c : a);
  const Vec3& v = ab_lowest ? c : (bc_lowest ? a : b);
  const Vec3& w = ab_lowest ? a : (bc_lowest ? b : c);
  // det[u, v, w] = det[u ∓ w, v ∓ w, w]: subtracting (or adding) w leaves short rows near w (or -w).
  const Vec3 u_short = dot(u, w) >= 0 ? u - w : u + w;
  const Vec3 v_short = dot(v, w) >= 0 ? v - w : v + w;
  const double triple_product = dot(u_short, cross(v_short, w));
  // D = (1 + u·w) + v·(u + w). The short u + w carries the second term's cancellation exactly; the
  // first needs u·w to twice the working precision when it is close to -1. (Rewriting 1 + u·w as
  // |u + w|²/2 would not do: the inputs are unit only to within an ulp, and that ulp, divided by a
  // tiny D, is exactly the error to avoid.)
  double one_plus_uw = 1 + dot(u, w);
  if (one_plus_uw < 0.5) {
    // Sum of 1 and the exact products (std::fma yields each rounding error) with compensation:
    // accurate as if computed in twice the precision (Ogita, Rump & Oishi 2005, Dot2).
    double sum = 1, compensation = 0;
    for (int i = 0; i < 3; ++i) {
      const double product = u[i] * w[i];
      const double product_error = std::fma(u[i], w[i], -product);
      const double new_sum = sum + product;
      const double virtual_product = new_sum - sum;
      compensation += (sum - (new_sum - virtual_product)) + (product - virtual_product) + product_error;
      sum = new_sum;
    }
    one_plus_uw = sum + compensation;
  }
  const double denominator = one_plus_uw + dot(v, u + w);
  return 2 * std::atan2(triple_product, denominator);
}

Certificate certify_sphere_map(const Mesh& surface, const std::vector<Vec3>& sphere, double collapse_floor,
                               std::vector<double>* solid_angles) {
  if (sphere.size() != surface.positions.size())
    throw std::invalid_argument("certify_sphere_map: " + std::to_string(sphere.size()) + " sphere points for " +
                                std::to_string(surface.positions.size()) + " surface vertices");

  Certificate certificate;
  const std::size_t count = surface.triangles.size();
  certificate.triangle_count = static_cast<std::int64_t>(count);
  certificate.collapse_floor = collapse_floor;

  // The per-triangle work (solid angle, exact orientation, surface area) on every hardware thread, in
  // fixed chunks; the sums and lists after it in triangle order, so the result does not depend on the
  // thread count.
  std::vector<double> own_solid_angles;
  std::vector<double>& omega = solid_angles ? *solid_angles : own_solid_angles;
  omega.resize(count);
  std::vector<double> area(count);
  constexpr std::uint8_t kPositive = 1, kDecidedExactly = 2;
  std::vector<std::uint8_t> verdict(count);
  detail::parallel_ranges(
      static_cast<std::int64_t>(count), 16384, detail::surface_threads(0), [&](std::int64_t first, std::int64_t last) {
        for (auto index = static_cast<std::size_t>(first); index < static_cast<std::size_t>(last); ++index) {
          const auto& t = surface.triangles[index];
          const Vec3& a = sphere[t[0]];
          const Vec3& b = sphere[t[1]];
          const Vec3& c = sphere[t[2]];
          omega[index] = signed_solid_angle(a, b, c);
          bool decided_exactly = false;
          const int orientation = orientation_sign(a, b, c, &decided_exactly);
          verdict[index] =
              static_cast<std::uint8_t>((orientation > 0 ? kPositive : 0) | (decided_exactly ? kDecidedExactly : 0));
          area[index] = triangle_area(surface.positions[t[0]], surface.positions[t[1]], surface.positions[t[2]]);
        }
      });

  CompensatedSum surface_area;
  for (const double a : area) surface_area.add(a);
  const double total_surface_area = surface_area.value();

  constexpr double kInfinity = std::numeric_limits<double>::infinity();
  constexpr double kFullSphere = 4 * std::numbers::pi;
  CompensatedSum solid_angle;
  double min_area_ratio = kInfinity;
  bool any_positive = false;
  for (std::size_t index = 0; index < count; ++index) {
    solid_angle.add(omega[index]);
    if (verdict[index] & kDecidedExactly) ++certificate.decided_exactly;
    if (!(verdict[index] & kPositive)) {
      certificate.folded_triangles.push_back(static_cast<std::int32_t>(index));
      continue;
    }
    any_positive = true;
    // A triangle with no area on the surface has no fair share of the sphere to fall short of, so
    // its ratio is +inf and it is never collapsed (it also keeps this loop free of 0/0).
    const double ratio =
        area[index] > 0 ? (omega[index] / kFullSphere) / (area[index] / total_surface_area) : kInfinity;
    min_area_ratio = std::min(min_area_ratio, ratio);
    if (ratio < collapse_floor) certificate.collapsed_triangles.push_back(static_cast<std::int32_t>(index));
  }

  certificate.folded = static_cast<std::int64_t>(certificate.folded_triangles.size());
  certificate.collapsed = static_cast<std::int64_t>(certificate.collapsed_triangles.size());
  certificate.total_solid_angle = solid_angle.value();
  certificate.coverage = certificate.total_solid_angle / kFullSphere;
  // With no positively oriented triangle there is nothing to vouch for: report the worst ratio, 0.
  certificate.min_area_ratio = any_positive ? min_area_ratio : 0.0;
  return certificate;
}

}  // namespace spheremap
