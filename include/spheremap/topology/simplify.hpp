// Fewer, better-shaped triangles for a closed surface, close to its shape, without changing its topology
// or moving a vertex (stage: topology).
#pragma once

#include <cstdint>
#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap {

struct SimplifyOptions {
  /// The edge length the result aims at (in the unit of the positions): edges shorter than 4/5 of it are
  /// collapsed, shortest first, and no collapse makes an edge longer than 4/3 of it (the thresholds of
  /// Botsch & Kobbelt's isotropic remeshing). 0 leaves the mesh as it is.
  double target_edge_length = 1.0;
  /// A collapse is refused when the vertex it removes lies farther than this from the triangles that
  /// replace its own; a flip when the two diagonals pass farther apart than this. Vertices never move, so
  /// every vertex of the result is a vertex of the input, at its input position.
  double max_error = 0.1;
  /// No collapse makes a triangle whose smallest corner angle is below both this and the smallest corner
  /// angle of the triangles it replaces.
  double min_angle_degrees = 20;
  /// Every triangle a collapse or flip makes faces within this angle of the vector area of the region it
  /// replaces (which the step does not change), so nothing folds over; below 90.
  double max_normal_change_degrees = 60;
  /// Rounds of (collapses over every short edge, shortest first; then angle-improving flips); stops
  /// earlier when a round removes fewer than 0.5% of the vertices left.
  int max_rounds = 12;
  /// Also compute SimplifyReport::max_vertex_distance (about a tenth of the time of the simplification).
  bool measure_distance = true;
  /// Threads (0: one per hardware thread; more than 2 are not used). The result does not depend on it.
  int threads = 0;
  /// Vertices that must stay (e.g. poles chosen by the user); indices into the input.
  std::vector<std::int32_t> kept_vertices;
  /// If not empty, one point per vertex (e.g. a map of the mesh onto the sphere) on which every input
  /// triangle is positively oriented (orientation_sign > 0): every collapse and flip keeps the triangles
  /// it makes so, and the points of the kept vertices are then a valid map of the result too.
  std::vector<Vec3> oriented_on;
};

struct SimplifyReport {
  std::int64_t vertices_before = 0, vertices_after = 0;
  std::int64_t triangles_before = 0, triangles_after = 0;
  std::int64_t collapses = 0, flips = 0;
  int rounds = 0;
  double area_before = 0, area_after = 0;
  double mean_edge_before = 0, mean_edge_after = 0;
  double min_angle_before_degrees = 0, min_angle_after_degrees = 0;
  /// An upper bound of the largest distance from an input vertex to the result (each removed vertex is
  /// measured against the triangles around the vertex it was merged into; the nearest point of the
  /// result can only be nearer). 0 when nothing was removed; -1 when options.measure_distance is false.
  double max_vertex_distance = 0;
  /// kept_vertex[i]: index in the input of output vertex i (ascending).
  std::vector<std::int32_t> kept_vertex;
};

/// Simplifies a closed, consistently oriented triangle 2-manifold (every component) by half-edge
/// collapses (a vertex merged into a neighbour that keeps its position, shortest edges first) and
/// angle-improving edge flips, towards options.target_edge_length and within options.max_error (see
/// SimplifyOptions).
/// - Topology is kept: every collapse passes the link condition, no component drops below 4 vertices (a
///   tetrahedron) and no vertex below degree 3, flips never duplicate an edge; so the number of
///   components and the genus of each stay the same, and the result is again closed, oriented and
///   2-manifold.
/// - The output's vertices are a subset of the input's, in ascending input order, at their input
///   positions, with exactly their per-vertex attributes (report->kept_vertex says which); its triangles
///   come in the order of the input triangles they descend from.
/// - Deterministic: the same input gives the same output.
/// Preconditions: the mesh is closed and 2-manifold with consistently oriented components (each edge in
/// exactly two triangles, in opposite directions; each vertex's triangles a single fan) and has no
/// unreferenced vertex. Throws std::invalid_argument otherwise, if an option is negative or not finite,
/// max_normal_change_degrees is not below 90, a kept vertex does not exist, or oriented_on is neither empty
/// nor one point per vertex with every triangle positively oriented on it.
/// The mesh is taken by value: a caller done with it moves it in, and its triangles become the working
/// copy instead of being copied (a fine molecular surface has tens of millions of triangles).
Mesh simplify_surface(Mesh mesh, const SimplifyOptions& options, SimplifyReport* report = nullptr);

}  // namespace spheremap
