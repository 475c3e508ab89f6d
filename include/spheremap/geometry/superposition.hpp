// The rotation that lays the sphere map over its surface (Kearsley's quaternion superposition), so that
// the globe faces the way the surface does.
#pragma once

#include <array>
#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// Rigid rotation R (row-major 3x3) minimizing Σ |R s_i * scale - (p_i - centroid)|² over rotations,
/// where s_i are unit sphere points and p_i the surface points (Kearsley 1989 quaternion method).
struct Superposition {
  std::array<double, 9> rotation{1, 0, 0, 0, 1, 0, 0, 0, 1};  // row-major
  Vec3 centroid{0, 0, 0};                                     // centroid of the surface vertices
  double scale = 1;                                           // RMS distance of surface vertices to their centroid
  double rmsd = 0;  // sqrt(mean |R s_i * scale - (p_i - centroid)|²), in surface units
};

/// The superposition of `sphere_points` (unit vectors) onto `surface_points`, point i onto point i.
/// Preconditions: same sizes, at least 3 points, all finite.
/// Throws std::invalid_argument if the sizes differ or there are fewer than 3 points.
Superposition superpose_sphere_on_surface(const std::vector<Vec3>& surface_points,
                                          const std::vector<Vec3>& sphere_points);

/// rotation * v, for a row-major 3x3 matrix. Never throws.
Vec3 rotate(const std::array<double, 9>& rotation, const Vec3& v);

/// The transpose of a row-major 3x3 matrix: the inverse of a rotation. Never throws.
std::array<double, 9> transposed(const std::array<double, 9>& rotation);

}  // namespace spheremap
