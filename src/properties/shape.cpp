#include "spheremap/properties/shape.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <numbers>
#include <stdexcept>

#include "spheremap/geometry/vec.hpp"
#include "spheremap/sphere/certify.hpp"

namespace spheremap {

double shape_index(double k1, double k2) {
  if (k1 < k2) std::swap(k1, k2);
  if (k1 == 0 && k2 == 0) return std::numeric_limits<double>::quiet_NaN();
  // k1 == k2 != 0 gives ±infinity inside atan: ±1, an umbilic cap or cup.
  return (2 / std::numbers::pi) * std::atan((k1 + k2) / (k1 - k2));
}

double curvedness(double k1, double k2) { return std::sqrt((k1 * k1 + k2 * k2) / 2); }

std::vector<double> vertex_log_area_ratios(const Mesh& surface, const std::vector<Vec3>& sphere) {
  if (sphere.size() != surface.vertex_count())
    throw std::invalid_argument("vertex_log_area_ratios: the sphere has another number of vertices");
  std::vector<double> surface_area(sphere.size(), 0.0), sphere_area(sphere.size(), 0.0);
  double total = 0;
  for (const auto& t : surface.triangles) {
    const double a = triangle_area(surface.positions[t[0]], surface.positions[t[1]], surface.positions[t[2]]);
    // Folded triangles count with their unsigned area, as in the distortion metrics.
    const double s = std::abs(signed_solid_angle(sphere[t[0]], sphere[t[1]], sphere[t[2]]));
    total += a;
    for (const auto v : t) surface_area[v] += a, sphere_area[v] += s;
  }
  std::vector<double> ratios(sphere.size(), std::numeric_limits<double>::quiet_NaN());
  for (std::size_t v = 0; v < sphere.size(); ++v) {
    if (!(surface_area[v] > 0 && total > 0)) continue;
    // A vertex whose triangles all collapsed gets ln of the smallest normal double (about -708), not -infinity.
    const double ratio = (sphere_area[v] / (4 * std::numbers::pi)) / (surface_area[v] / total);
    ratios[v] = std::log(std::max(ratio, std::numeric_limits<double>::min()));
  }
  return ratios;
}

int octant_of(const Vec3& point) { return (point[0] < 0) + 2 * (point[1] < 0) + 4 * (point[2] < 0); }

const std::array<std::string, 8>& octant_names() {
  static const std::array<std::string, 8> names{"+x+y+z", "-x+y+z", "+x-y+z", "-x-y+z",
                                                "+x+y-z", "-x+y-z", "+x-y-z", "-x-y-z"};
  return names;
}

}  // namespace spheremap
