// Point and residue location on the globe (see locate.hpp).
#include "spheremap/render/locate.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>

#include "spheremap/render/map_picture.hpp"

namespace spheremap {

PointLocation locate_point(const Globe& globe, const SphereLocator& locator, const GeoPoint& point) {
  PointLocation at;
  at.hit = locate_on_sphere(locator, direction_of(point));
  if (at.hit.triangle < 0) return at;
  const Triangle& t = globe.triangles[at.hit.triangle];
  at.vertex = t[at.hit.nearest_corner()];
  if (!globe.vertex_residue.empty()) {
    at.residue = globe.vertex_residue[at.vertex];
    for (const std::int32_t v : t)
      if (globe.vertex_residue[v] >= 0) at.corner_residues.push_back(globe.vertex_residue[v]);
    std::sort(at.corner_residues.begin(), at.corner_residues.end());
    at.corner_residues.erase(std::unique(at.corner_residues.begin(), at.corner_residues.end()),
                             at.corner_residues.end());
  }
  const std::array<float, 3> weights{static_cast<float>(at.hit.weights[0]), static_cast<float>(at.hit.weights[1]),
                                     static_cast<float>(at.hit.weights[2])};
  for (const SurfaceProperty& property : globe.properties)
    at.values.push_back(value_at(globe, property, at.hit.triangle, weights));
  return at;
}

std::optional<ResidueExtent> residue_extent(const Globe& globe, std::int32_t residue) {
  std::vector<Vec3> points;
  for (std::size_t v = 0; v < globe.vertex_residue.size(); ++v)
    if (globe.vertex_residue[v] == residue) points.push_back(globe.sphere[v]);
  if (points.empty()) return std::nullopt;
  Vec3 sum{0, 0, 0};
  for (const Vec3& p : points)
    for (int k = 0; k < 3; ++k) sum[k] += p[k];
  ResidueExtent extent;
  extent.vertices = static_cast<std::int64_t>(points.size());
  const double norm = std::sqrt(sum[0] * sum[0] + sum[1] * sum[1] + sum[2] * sum[2]);
  const Vec3 centre = norm > 0 ? Vec3{sum[0] / norm, sum[1] / norm, sum[2] / norm} : points.front();
  extent.centre = geo_point_of(centre);
  std::vector<double> longitudes;
  extent.latitude_lo = std::numbers::pi, extent.latitude_hi = -std::numbers::pi;
  for (const Vec3& p : points) {
    const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    const double cosine = std::clamp((p[0] * centre[0] + p[1] * centre[1] + p[2] * centre[2]) / n, -1.0, 1.0);
    extent.radius = std::max(extent.radius, std::acos(cosine));
    const GeoPoint g = geo_point_of(p);
    extent.latitude_lo = std::min(extent.latitude_lo, g.latitude);
    extent.latitude_hi = std::max(extent.latitude_hi, g.latitude);
    longitudes.push_back(g.longitude);
  }
  // The narrowest longitude range holding them all: the complement of the widest gap between neighbours.
  std::sort(longitudes.begin(), longitudes.end());
  double widest_gap = longitudes.front() + 2 * std::numbers::pi - longitudes.back();
  extent.longitude_lo = longitudes.front(), extent.longitude_hi = longitudes.back();
  for (std::size_t k = 1; k < longitudes.size(); ++k)
    if (longitudes[k] - longitudes[k - 1] > widest_gap) {
      widest_gap = longitudes[k] - longitudes[k - 1];
      extent.longitude_lo = longitudes[k], extent.longitude_hi = longitudes[k - 1];
    }
  return extent;
}

}  // namespace spheremap
