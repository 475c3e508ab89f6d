// Koenderink's shape descriptors of a surface from its principal curvatures (stage: properties), and the
// map's own per-vertex descriptors: local area distortion and octant.
#pragma once

#include <array>
#include <string>
#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// Koenderink & van Doorn (1992), "Surface shape and curvature scales", Image Vision Comput. 10:557-564:
/// S = (2/π) atan((k1 + k2) / (k1 - k2)) for k1 >= k2, in [-1, 1]: +1 a convex cap (sphere), +1/2 a ridge
/// (cylinder), 0 a symmetric saddle, -1/2 a rut, -1 a cup; NaN for a plane (k1 = k2 = 0) or NaN input.
/// Never throws.
double shape_index(double k1, double k2);

/// Koenderink's curvedness sqrt((k1² + k2²) / 2) (1 / length): how strongly the surface bends. Never throws.
double curvedness(double k1, double k2);

/// Per vertex, ln of the local area ratio of the map: (Σ spherical areas of its triangles / 4π) / (Σ surface
/// areas of its triangles / total surface area); 0 where the map keeps the area share, negative where it
/// shrinks it. NaN for a vertex in no triangle. `sphere` holds unit vectors.
/// Preconditions: sphere.size() == surface.vertex_count(); throws std::invalid_argument otherwise.
std::vector<double> vertex_log_area_ratios(const Mesh& surface, const std::vector<Vec3>& sphere);

/// The octant of a point of the sphere: (x < 0) + 2 (y < 0) + 4 (z < 0), in the order of the distortion
/// metrics' octant_area_percent (a zero coordinate counts as positive). Never throws.
int octant_of(const Vec3& point);

/// The names of the octants in that order: "+x+y+z", "-x+y+z", ... Never throws.
const std::array<std::string, 8>& octant_names();

}  // namespace spheremap
