// Which triangle of a sphere map lies under a point of the globe (stage: render): a bucket grid over the
// sphere and an exact-enough point-in-spherical-triangle test, for the pictures and for `locate`.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// Triangles of a map on the unit sphere, bucketed by the cells of a grid: rows of equal colatitude
/// width, each cut into about as many cells of equal longitude width as keeps cells near square. Each
/// triangle is listed (in index order) in every cell its bounding cap meets, so that the triangle under any
/// point is among the candidates of the point's cell, also at the poles and across longitude 0/2π.
struct SphereLocator {
  std::vector<Vec3> vertices;  // unit vectors
  std::vector<Triangle> triangles;
  int rows = 1;
  std::vector<std::int32_t> row_columns;     // cells in each row
  std::vector<std::int32_t> row_first_cell;  // rows + 1 entries
  std::vector<std::int32_t> cell_first;      // cells + 1 entries into cell_triangles
  std::vector<std::int32_t> cell_triangles;
  /// Per triangle (a, b, c): b × c, c × a, a × b, whose dot products with a point are its unnormalized
  /// barycentric weights (one read of 72 contiguous bytes per candidate instead of three scattered corners).
  std::vector<std::array<double, 9>> edge_normals;
  /// Per half-edge (3 * triangle + corner), the half-edge across its edge, -1 where the edge is not shared
  /// by exactly two triangles in opposite directions (opposite_half_edges): the hinted search walks across
  /// them to the triangle half-edge / 3.
  std::vector<std::int32_t> opposite;
};

/// The triangle under a point and the point's barycentric weights in it (>= 0, summing to 1): the weights of
/// the point where the ray from the centre through it meets the triangle's plane.
struct SphereHit {
  std::int32_t triangle = -1;  // -1: no triangle (a map with holes, or an empty one)
  std::array<double, 3> weights{0, 0, 0};

  /// The corner (0, 1, 2) of largest weight, the first of equals: the vertex nearest the point.
  [[nodiscard]] int nearest_corner() const {
    return weights[1] > weights[0] ? (weights[2] > weights[1] ? 2 : 1) : (weights[2] > weights[0] ? 2 : 0);
  }
};

/// The locator of a map: `vertices` on (or near: they are normalized) the unit sphere, `triangles`
/// counter-clockwise seen from outside. About one cell per two triangles. Runs on `threads` threads (0: all;
/// the locator does not depend on it).
/// Preconditions: indices in range, no zero vertex. Throws std::invalid_argument if an index is out of range.
SphereLocator make_sphere_locator(const std::vector<Vec3>& vertices, const std::vector<Triangle>& triangles,
                                  int threads = 0);

/// The triangle under `direction` (any non-zero length): the first candidate, in index order, that contains
/// it (edges and corners included). Where rounding leaves a point on an edge outside every candidate, the
/// candidate it is least outside, its weights clamped to the triangle: so a map that covers the sphere once
/// leaves no gap and no seam. Never throws.
SphereHit locate_on_sphere(const SphereLocator& locator, const Vec3& direction);

/// The same for the point at `colatitude` (0 at +z, π at -z) and `azimuth` (radians, any turn) whose
/// direction the caller has already: saves the trigonometry of finding its cell when sampling a map. The
/// result is that of locate_on_sphere(locator, direction) but where a point on a cell's border meets no
/// candidate (rounding) and the nearest one is chosen among another cell's candidates. Never throws.
SphereHit locate_on_sphere(const SphereLocator& locator, const Vec3& direction, double colatitude, double azimuth);

/// The same, trying triangle `hint` first (-1: none; e.g. the previous pixel's, which most pixels share), then
/// walking from it across the edge the point lies farthest beyond, a few triangles at most: where the point lies
/// inside one of them by more than rounding (each weight at least 1e-6 of their sum), that triangle. On a map that
/// covers the sphere once no other triangle contains such a point, so the result is the one above; where triangles
/// overlap (a folded map) it may be another that contains the point. Precondition: hint < triangles.size().
/// Never throws.
SphereHit locate_on_sphere(const SphereLocator& locator, const Vec3& direction, double colatitude, double azimuth,
                           std::int32_t hint);

}  // namespace spheremap
