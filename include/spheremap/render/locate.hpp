// What lies where on the globe (stage: render), for `spheremap locate`: the residue under a point of the
// globe, and where a residue lies on it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "spheremap/render/globe.hpp"
#include "spheremap/render/projection.hpp"
#include "spheremap/render/sphere_locator.hpp"

namespace spheremap {

/// The globe under a point: the triangle, its nearest vertex, that vertex's residue (-1: none), the
/// residues of the triangle's corners (sorted, each once) and every property's value there (value_at).
struct PointLocation {
  SphereHit hit;
  std::int32_t vertex = -1;
  std::int32_t residue = -1;
  std::vector<std::int32_t> corner_residues;
  std::vector<double> values;  // one per globe.properties
};

/// Locates `point` on `globe` (whose locator is `locator`). Never throws (but std::bad_alloc).
PointLocation locate_point(const Globe& globe, const SphereLocator& locator, const GeoPoint& point);

/// Where a residue lies on the globe: the direction of the mean of its vertices' globe points, the largest
/// angle from there to one of them (radians), the latitude and longitude ranges of its vertices (longitude
/// range the narrowest that holds them, so that it may cross ±180°: then lo > hi), and its vertex count.
struct ResidueExtent {
  GeoPoint centre;
  double radius = 0;
  double latitude_lo = 0, latitude_hi = 0, longitude_lo = 0, longitude_hi = 0;
  std::int64_t vertices = 0;
};

/// The extent of residue `residue` (an index into globe.residues), or none if no vertex has it (it is
/// buried). Never throws (but std::bad_alloc).
std::optional<ResidueExtent> residue_extent(const Globe& globe, std::int32_t residue);

}  // namespace spheremap
