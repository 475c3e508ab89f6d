// Private to the sphere stage: moves points on the sphere until no triangle is folded or collapsed.
#pragma once

#include <cstdint>
#include <vector>

#include "spheremap/mesh.hpp"
#include "spheremap/topology/connectivity.hpp"

namespace spheremap::detail {

/// Normalized target area of each triangle: surface area / total surface area * 4π (degenerate surface
/// triangles get a tiny positive target so they are only required to keep their orientation).
std::vector<double> target_solid_angles(const Mesh& surface);

/// Each sweep visits (in index order) every vertex of a folded or collapsed triangle and moves it to the
/// point of its one-ring's kernel that maximizes the smallest ratio (solid angle / target) of its
/// triangles, found in a gnomonic chart where great circles are straight lines. A move is kept only if
/// it raises that smallest ratio. When a sweep stalls, the next one also moves the neighbours.
/// Returns the number of moves made. `sphere` holds unit vectors and is updated in place.
std::int64_t untangle_on_sphere(const Mesh& surface, const VertexRings& rings, std::vector<Vec3>& sphere,
                                double collapse_floor, int max_sweeps);

}  // namespace spheremap::detail
