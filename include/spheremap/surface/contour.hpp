// Iso-surfaces of sampled fields as closed 2-manifold triangle meshes (stage: surface).
#pragma once

#include "spheremap/mesh.hpp"
#include "spheremap/surface/grid.hpp"

namespace spheremap {

/// Default of contour_isosurface's `minimum_fraction`: where the surface passes within this fraction of a
/// step of a sample, its vertex is kept at this fraction. Vertices closer to a sample make sliver
/// triangles of almost no area, whose area ratios dominate any distortion statistic of a map. The shift
/// is at most a tenth of a step; it biases areas upwards (see BENCHMARKS.md, "Solvent-excluded surface").
inline constexpr double kContourMinimumFraction = 0.1;

/// The surface field == level of the piecewise-linear interpolant of `field` on the Freudenthal
/// subdivision of each grid cell into six tetrahedra (marching tetrahedra). Every cell uses the same
/// diagonals, so neighbouring cells agree on shared faces and no case is ambiguous: with the samples
/// classified strictly (inside: value > level), the result is a closed, consistently oriented 2-manifold
/// whenever every sample on the grid's outer layer is outside. Triangles face outward (towards
/// decreasing values). Vertices sit on grid edges; interpolation parameters are kept in
/// [minimum_fraction, 1 - minimum_fraction] (0: the plain linear interpolation, which can make sliver
/// triangles; the default 0.1 moves a vertex by at most a tenth of a step and makes none; 0.5 puts every
/// vertex at its edge's midpoint, i.e. contours the binary inside/outside field at 1/2, as the paper does).
/// Vertices are numbered by their grid edge (lower sample index, then edge direction: +x, +y, +z,
/// +x+y, +x+z, +y+z, +x+y+z); triangles come cell by cell in grid order. The output is the same for
/// any `threads` (0: one per hardware thread). Memory: the mesh, allocated once at its exact size, plus
/// a few planes of the grid per thread.
/// Throws std::invalid_argument if a sample of the outer layer is inside, the grid is smaller than 2³, or
/// minimum_fraction is outside [0, 0.5].
Mesh contour_isosurface(const Grid3<double>& field, double level, int threads = 0,
                        double minimum_fraction = kContourMinimumFraction);
Mesh contour_isosurface(const Grid3<float>& field, double level, int threads = 0,
                        double minimum_fraction = kContourMinimumFraction);

}  // namespace spheremap
