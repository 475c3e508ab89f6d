// Per-vertex normals of a triangle mesh.
#pragma once

#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// Unit normal of every vertex: the sum of the cross products (b - a) x (c - a) of the triangles around it,
/// i.e. the area-weighted mean of their normals, normalized. Outward when the triangles are
/// counter-clockwise seen from outside (as prepared meshes and molecular surfaces are). A vertex in no
/// triangle, or whose triangles' normals cancel, gets the zero vector.
/// Preconditions: every triangle index is in [0, positions.size()). Never throws (but std::bad_alloc).
std::vector<Vec3> vertex_normals(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles);

/// positions[v] + distance * normals[v] for every vertex: points moved out along their normals (a vertex
/// with a zero normal stays where it is).
/// Preconditions: positions.size() == normals.size(); throws std::invalid_argument otherwise.
std::vector<Vec3> offset_along_normals(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals,
                                       double distance);

}  // namespace spheremap
