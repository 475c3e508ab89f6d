// Map projections of the whole globe (stage: render): latitude and longitude to a point of the plane and
// back, on the unit sphere (radius 1, as PROJ's +R=1), central meridian at longitude 0.
//
// Latitude and longitude are those of the superposed globe: the positions of sphere.ply (the map after the
// rotation that lays it over the surface), so the globe's axes are the structure's x, y, z axes. Latitude is
// asin(z) (north, +z, up), longitude atan2(y, x) (0 on +x, 90° east on +y, east to the right on every map).
#pragma once

#include <optional>
#include <string_view>

#include "spheremap/mesh.hpp"

namespace spheremap {

enum class Projection {
  mollweide,        // equal-area, an ellipse twice as wide as high (the default)
  equirectangular,  // plate carrée: x = longitude, y = latitude
  sinusoidal,       // Sanson-Flamsteed, equal-area: x = longitude cos(latitude), y = latitude (SURFMAP's)
};

/// "mollweide", "equirectangular" or "sinusoidal". Never throws.
std::string_view to_string(Projection projection);

/// The projection named `name` (as to_string writes it; also "plate-carree" and "flamsteed"), or none.
/// Never throws.
std::optional<Projection> parse_projection(std::string_view name);

/// A point of the globe in radians: latitude in [-π/2, π/2], longitude in [-π, π].
struct GeoPoint {
  double latitude = 0;
  double longitude = 0;
};

/// A point of the projection plane (unit sphere), x east, y north.
struct PlanePoint {
  double x = 0;
  double y = 0;
};

/// The half-width and half-height of the rectangle around a projection's whole map: mollweide 2√2 × √2,
/// the others π × π/2. Never throws.
PlanePoint projection_half_extent(Projection projection);

/// The plane point of `point`. Latitude is clamped to [-π/2, π/2]; longitude is taken as given (values in
/// [-π, π] stay on the map). Mollweide solves 2θ + sin 2θ = π sin(latitude) by Newton's method to 1e-15.
/// Never throws.
PlanePoint project(Projection projection, const GeoPoint& point);

/// The globe point at `point`, or none when `point` is outside the map (beyond the ellipse, the sinusoid or
/// the rectangle). On the map's edge the longitude is ±π. Never throws.
std::optional<GeoPoint> unproject(Projection projection, const PlanePoint& point);

/// unproject along one row of the plane (y fixed), with what depends on y alone computed once, for sampling
/// a map: row(x) equals unproject(projection, {x, y}) bit for bit, and so does direction(x) direction_of of
/// it. Never throws.
class RowUnprojection {
 public:
  RowUnprojection(Projection projection, double y);
  [[nodiscard]] std::optional<GeoPoint> operator()(double x) const;
  /// The unit vector of the point at x. Precondition: (*this)(x) is a point.
  [[nodiscard]] Vec3 direction(double longitude) const;

 private:
  Projection projection_;
  double y_;
  bool on_map_ = false;  // some point of the row may be on the map
  double latitude_ = 0, cos_latitude_ = 0, sin_latitude_ = 0;
  double scale_ = 0;  // mollweide: 2√2 cos θ; sinusoidal: cos(latitude)
};

/// The unit vector of a globe point, and back (the direction need not be of unit length but must not be
/// zero; longitude 0 at the poles). Never throw.
Vec3 direction_of(const GeoPoint& point);
GeoPoint geo_point_of(const Vec3& direction);

/// Degrees to radians and back.
constexpr double kDegree = 3.14159265358979323846 / 180;

}  // namespace spheremap
