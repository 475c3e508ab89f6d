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

/// What untangling needs of the surface alone, whatever the sphere points: each triangle's target solid
/// angle, and the triangle of each ring slot (slot k of v: triangle (v, ring[k], ring[k+1])). A map that
/// untangles several candidates builds it once.
/// Preconditions: `rings` are the rings of `surface` (build_vertex_rings); every slot has its triangle.
struct UntanglingFrame {
  std::vector<double> target;
  std::vector<std::int32_t> star_triangle;
};
UntanglingFrame untangling_frame(const Mesh& surface, const VertexRings& rings);

/// Each sweep visits (in index order) every vertex of a folded or collapsed triangle and moves it to the
/// point of its one-ring's kernel that maximizes the smallest ratio (solid angle / target) of its
/// triangles, found in a gnomonic chart where great circles are straight lines. A move is kept only if
/// it raises that smallest ratio. When a sweep stalls, the next one also moves the neighbours.
/// Returns the number of moves made. `sphere` holds unit vectors and is updated in place.
/// `frame` is untangling_frame(surface, rings). The vertices marked in `fixed` (empty: none; else one
/// flag per point) never move. Throws std::invalid_argument if `fixed` has another size.
std::int64_t untangle_on_sphere(const Mesh& surface, const VertexRings& rings, const UntanglingFrame& frame,
                                std::vector<Vec3>& sphere, double collapse_floor, int max_sweeps,
                                const std::vector<char>& fixed = {});

}  // namespace spheremap::detail
