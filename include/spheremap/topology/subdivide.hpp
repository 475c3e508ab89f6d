// Loop-free 1-to-4 midpoint subdivision (stage: topology): the sphere map refines meshes whose poles are
// too close; the generated shapes refine an icosahedron.
#pragma once

#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// Midpoint subdivision (positions not smoothed), `levels` times: each triangle becomes four, every
/// original vertex keeps its index, and the midpoint of edge e (number_edges's numbering of the mesh
/// being split) becomes vertex (vertex count before the split + e). Orientation is kept. Attributes are
/// not carried over (there is no one right way to interpolate labels onto midpoints).
/// Preconditions: every triangle index in [0, positions.size()).
/// Throws std::invalid_argument if levels < 0, an index is out of range, or the result would exceed
/// 2^31 - 1 vertices.
Mesh subdivide_midpoint(const Mesh& mesh, int levels);

/// One split of subdivide_midpoint, in place; with `project_to_unit_sphere` each midpoint is normalized
/// (the original vertices are left as they are).
/// Preconditions: every triangle index in [0, positions.size()) (not checked).
/// Throws std::invalid_argument if the result would exceed 2^31 - 1 vertices.
void subdivide_midpoint_in_place(std::vector<Vec3>& positions, std::vector<Triangle>& triangles,
                                 bool project_to_unit_sphere = false);

}  // namespace spheremap
