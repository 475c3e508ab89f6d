// Principal curvatures of a triangle mesh at its vertices (stage: geometry).
#pragma once

#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// Per vertex, the principal curvatures k1 >= k2 (1 / length), positive where the surface bends away from its
/// normal (a convex bump: a sphere of radius R with outward normals has k1 = k2 = 1/R).
struct PrincipalCurvatures {
  std::vector<double> k1, k2;
};

/// Rusinkiewicz's estimate ("Estimating curvatures and their derivatives on triangle meshes", 3DPVT 2004):
/// a second fundamental form per triangle, fitted by least squares to the change of the vertex normals
/// (by Max's 1999 weights, exact on a sphere, as Rusinkiewicz's trimesh2) along its three edges, then averaged into
/// each vertex's tangent frame with the vertex's mixed Voronoi share of the triangle (Meyer et al. 2003) as weight.
/// Linear in the mesh size. Vertices in no triangle (or whose normal is zero) get NaN. Preconditions: triangles
/// counter-clockwise seen from outside (for the sign), indices valid. Never throws (but std::bad_alloc).
PrincipalCurvatures principal_curvatures(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles);

}  // namespace spheremap
