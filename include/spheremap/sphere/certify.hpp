// Certification of a sphere map: is every triangle positively oriented and non-collapsed, and does
// the image cover the sphere exactly once? (stage: sphere)
#pragma once

#include <cstdint>
#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// Default floor of the normalized area ratio below which a triangle counts as collapsed.
/// ratio(t) = (spherical area of t / 4π) / (surface area of t / total surface area).
/// 1e-6 means: a triangle that keeps less than a millionth of its fair share of the sphere is
/// invisible on any picture and numerically fragile, so the map is not certified.
inline constexpr double kDefaultCollapseFloor = 1e-6;

struct Certificate {
  std::int64_t triangle_count = 0;
  std::int64_t folded = 0;           // det[a,b,c] <= 0 (exact sign); zero counts as folded
  std::int64_t collapsed = 0;        // positively oriented but normalized area ratio < floor;
                                     // a triangle of zero surface area has ratio +inf, never collapsed
  std::int64_t decided_exactly = 0;  // orientation signs the floating-point filter could not decide
  double total_solid_angle = 0;      // signed sum of the triangles' solid angles
  double coverage = 0;               // total_solid_angle / 4π; 1 for a one-to-one map
  double min_area_ratio = 0;         // smallest normalized area ratio over positive triangles;
                                     // 0 when there is none, +inf when all have zero surface area
  double collapse_floor = kDefaultCollapseFloor;
  std::vector<std::int32_t> folded_triangles;     // indices, ascending
  std::vector<std::int32_t> collapsed_triangles;  // indices, ascending
  /// True when folded == 0, collapsed == 0 and |coverage - 1| < 1e-9.
  [[nodiscard]] bool certified() const;
};

/// Checks `sphere` (one unit vector per vertex of `surface`, same triangles) triangle by triangle.
/// Preconditions: sphere.size() == surface.positions.size(); triangle indices valid; finite values.
/// Throws std::invalid_argument if the sizes disagree. `solid_angles`, if given, receives each
/// triangle's signed_solid_angle (the terms of total_solid_angle), for callers that need them too.
/// The triangles are checked on every hardware thread; the result does not depend on how many there are.
Certificate certify_sphere_map(const Mesh& surface, const std::vector<Vec3>& sphere,
                               double collapse_floor = kDefaultCollapseFloor,
                               std::vector<double>* solid_angles = nullptr);

/// Whether every triangle of `triangles` is positively oriented on `sphere` (exact orientation_sign > 0):
/// the first condition of certify_sphere_map, alone, stopping at the first that is not.
/// Preconditions: triangle indices valid for `sphere`. Never throws.
bool positively_oriented(const std::vector<Triangle>& triangles, const std::vector<Vec3>& sphere);

/// Signed solid angle of the spherical triangle abc (unit vectors), Van Oosterom & Strackee 1983.
/// Never throws.
double signed_solid_angle(const Vec3& a, const Vec3& b, const Vec3& c);

}  // namespace spheremap
