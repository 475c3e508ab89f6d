// Mollweide, equirectangular and sinusoidal projections (see projection.hpp); formulas from Snyder,
// "Map Projections: A Working Manual" (USGS Professional Paper 1395, 1987), §16 (Mollweide) and §30
// (sinusoidal), on the unit sphere.
#include "spheremap/render/projection.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

namespace spheremap {
namespace {

constexpr double kPi = std::numbers::pi;
constexpr double kSqrt2 = std::numbers::sqrt2;
// Points this close outside a map's edge (in plane units) still belong to it, so that pixel centres on the
// edge itself do not fall off through rounding.
constexpr double kEdgeTolerance = 1e-12;

// The auxiliary angle t = 2θ of Mollweide: t + sin t = π sin(latitude), by Newton's method. The root is
// double at the poles, where Newton converges slowly from a poor start: there t = ±(π - u) with
// u³/6 ≈ π (1 - |sin latitude|) is the starting point.
double mollweide_auxiliary(double latitude) {
  const double target = kPi * std::sin(latitude);
  const double s = std::abs(std::sin(latitude));
  if (s >= 1) return std::copysign(kPi, latitude);
  double t = s > 0.9 ? std::copysign(kPi - std::cbrt(6 * kPi * (1 - s)), latitude) : 2 * latitude;
  for (int iteration = 0; iteration < 60; ++iteration) {
    const double slope = 1 + std::cos(t);
    if (!(slope > 0)) break;
    const double step = (t + std::sin(t) - target) / slope;
    t = std::clamp(t - step, -kPi, kPi);
    if (std::abs(step) < 1e-15) break;
  }
  return t;
}

std::optional<GeoPoint> mollweide_inverse(const PlanePoint& p) {
  const double ex = p.x / (2 * kSqrt2), ey = p.y / kSqrt2;
  if (ex * ex + ey * ey > 1 + kEdgeTolerance) return std::nullopt;
  const double theta = std::asin(std::clamp(ey, -1.0, 1.0));
  const double t = 2 * theta;
  const double latitude = std::asin(std::clamp((t + std::sin(t)) / kPi, -1.0, 1.0));
  const double c = std::cos(theta);
  const double longitude = c > 0 ? std::clamp(kPi * p.x / (2 * kSqrt2 * c), -kPi, kPi) : 0.0;
  return GeoPoint{latitude, longitude};
}

}  // namespace

std::string_view to_string(Projection projection) {
  switch (projection) {
    case Projection::mollweide: return "mollweide";
    case Projection::equirectangular: return "equirectangular";
    case Projection::sinusoidal: return "sinusoidal";
  }
  return "mollweide";
}

std::optional<Projection> parse_projection(std::string_view name) {
  if (name == "mollweide") return Projection::mollweide;
  if (name == "equirectangular" || name == "plate-carree") return Projection::equirectangular;
  if (name == "sinusoidal" || name == "flamsteed") return Projection::sinusoidal;
  return std::nullopt;
}

PlanePoint projection_half_extent(Projection projection) {
  return projection == Projection::mollweide ? PlanePoint{2 * kSqrt2, kSqrt2} : PlanePoint{kPi, kPi / 2};
}

PlanePoint project(Projection projection, const GeoPoint& point) {
  const double latitude = std::clamp(point.latitude, -kPi / 2, kPi / 2);
  switch (projection) {
    case Projection::mollweide: {
      const double theta = mollweide_auxiliary(latitude) / 2;
      return {2 * kSqrt2 / kPi * point.longitude * std::cos(theta), kSqrt2 * std::sin(theta)};
    }
    case Projection::sinusoidal: return {point.longitude * std::cos(latitude), latitude};
    case Projection::equirectangular: break;
  }
  return {point.longitude, latitude};
}

std::optional<GeoPoint> unproject(Projection projection, const PlanePoint& point) {
  if (projection == Projection::mollweide) return mollweide_inverse(point);
  if (std::abs(point.y) > kPi / 2 + kEdgeTolerance) return std::nullopt;
  const double latitude = std::clamp(point.y, -kPi / 2, kPi / 2);
  if (projection == Projection::equirectangular) {
    if (std::abs(point.x) > kPi + kEdgeTolerance) return std::nullopt;
    return GeoPoint{latitude, std::clamp(point.x, -kPi, kPi)};
  }
  const double c = std::cos(latitude);
  if (std::abs(point.x) > kPi * c + kEdgeTolerance) return std::nullopt;
  return GeoPoint{latitude, c > 0 ? std::clamp(point.x / c, -kPi, kPi) : 0.0};
}

RowUnprojection::RowUnprojection(Projection projection, double y) : projection_(projection), y_(y) {
  // The same expressions as mollweide_inverse and unproject, in the same order: the same bits.
  if (projection == Projection::mollweide) {
    const double ey = y / kSqrt2;
    on_map_ = ey * ey <= 1 + kEdgeTolerance;
    const double theta = std::asin(std::clamp(ey, -1.0, 1.0));
    const double t = 2 * theta;
    latitude_ = std::asin(std::clamp((t + std::sin(t)) / kPi, -1.0, 1.0));
    scale_ = std::cos(theta);
  } else {
    on_map_ = std::abs(y) <= kPi / 2 + kEdgeTolerance;
    latitude_ = std::clamp(y, -kPi / 2, kPi / 2);
    scale_ = std::cos(latitude_);
  }
  cos_latitude_ = std::cos(latitude_);
  sin_latitude_ = std::sin(latitude_);
}

std::optional<GeoPoint> RowUnprojection::operator()(double x) const {
  if (!on_map_) return std::nullopt;
  switch (projection_) {
    case Projection::mollweide: {
      const double ex = x / (2 * kSqrt2), ey = y_ / kSqrt2;
      if (ex * ex + ey * ey > 1 + kEdgeTolerance) return std::nullopt;
      const double c = scale_;
      return GeoPoint{latitude_, c > 0 ? std::clamp(kPi * x / (2 * kSqrt2 * c), -kPi, kPi) : 0.0};
    }
    case Projection::equirectangular:
      if (std::abs(x) > kPi + kEdgeTolerance) return std::nullopt;
      return GeoPoint{latitude_, std::clamp(x, -kPi, kPi)};
    case Projection::sinusoidal: break;
  }
  const double c = scale_;
  if (std::abs(x) > kPi * c + kEdgeTolerance) return std::nullopt;
  return GeoPoint{latitude_, c > 0 ? std::clamp(x / c, -kPi, kPi) : 0.0};
}

Vec3 RowUnprojection::direction(double longitude) const {
  const double c = cos_latitude_;
  return {c * std::cos(longitude), c * std::sin(longitude), sin_latitude_};
}

Vec3 direction_of(const GeoPoint& point) {
  const double c = std::cos(point.latitude);
  return {c * std::cos(point.longitude), c * std::sin(point.longitude), std::sin(point.latitude)};
}

GeoPoint geo_point_of(const Vec3& d) {
  const double horizontal = std::hypot(d[0], d[1]);
  return {std::atan2(d[2], horizontal), horizontal > 0 ? std::atan2(d[1], d[0]) : 0.0};
}

}  // namespace spheremap
