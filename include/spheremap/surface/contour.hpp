// Iso-surfaces of sampled fields as closed 2-manifold triangle meshes (stage: surface).
#pragma once

#include "spheremap/mesh.hpp"
#include "spheremap/surface/grid.hpp"

namespace spheremap {

/// The surface field == level of the piecewise-linear interpolant of `field` on the Freudenthal
/// subdivision of each grid cell into six tetrahedra (marching tetrahedra). Every cell uses the same
/// diagonals, so neighbouring cells agree on shared faces and no case is ambiguous: with the samples
/// classified strictly (inside: value > level), the result is a closed, consistently oriented 2-manifold
/// whenever every sample on the grid's outer layer is outside. Triangles face outward (towards
/// decreasing values). Vertices sit on grid edges; interpolation parameters are kept in [0.1, 0.9]
/// (a vertex moves by at most a tenth of a step) so that no sliver triangles appear.
/// Vertices are numbered by their grid edge (lower sample index, then edge direction: +x, +y, +z,
/// +x+y, +x+z, +y+z, +x+y+z); triangles come cell by cell in grid order. The output is the same for
/// any `threads` (0: one per hardware thread). Memory: the mesh, allocated once at its exact size, plus
/// a few planes of the grid per thread.
/// Throws std::invalid_argument if a sample of the outer layer is inside or the grid is smaller than 2³.
Mesh contour_isosurface(const Grid3<double>& field, double level, int threads = 0);
Mesh contour_isosurface(const Grid3<float>& field, double level, int threads = 0);

}  // namespace spheremap
