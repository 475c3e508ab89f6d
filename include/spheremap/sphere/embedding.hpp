// Valid maps of any closed genus-0 triangle mesh onto the sphere, built without the paper's harmonic
// map: the fallback map_to_sphere uses when the plain map and its repair end uncertified (stage: sphere).
#pragma once

#include <cstdint>
#include <vector>

#include "spheremap/mesh.hpp"
#include "spheremap/sphere/optimize.hpp"

namespace spheremap {

/// Tutte's embedding of the mesh's graph in the plane with one triangle at `north` as the outer face
/// (uniform weights: every face convex), lifted by Maxwell–Cremona to a convex polyhedron, then
/// projected centrally from the midpoint of `north` and `south` onto the unit sphere and rotated so that
/// north = +z and south = -z exactly. Exact arithmetic would make every triangle positively oriented;
/// in double precision the tiny triangles of Tutte embeddings of deep meshes (long tubes, nested
/// stacked triangulations) can fold or collapse to a point, so the caller must check the result
/// (certify_sphere_map). The planar solve is polished by iterative refinement (residuals in long double).
/// Preconditions: `triangles` form a closed, oriented, genus-0 2-manifold on `vertex_count` >= 5
/// vertices; north and south are vertices not joined by an edge.
/// Throws std::invalid_argument if north or south are out of range, equal or adjacent, and
/// std::runtime_error if the sparse factorization fails.
std::vector<Vec3> convex_embedding(std::int32_t vertex_count, const std::vector<Triangle>& triangles,
                                   std::int32_t north, std::int32_t south);

struct ProgressiveEmbeddingOptions {
  /// Newton iterations of optimize_on_sphere after each level's re-insertions (where only wide kernels
  /// for the next level matter), and on the finished map; each stops earlier once an iteration lowers
  /// the energy by less than its tolerance (a fraction of the energy).
  int level_iterations = 8;
  double level_tolerance = 1e-3;
  int final_iterations = 100;
  double final_tolerance = 1e-4;
  SphereOptimizeOptions optimize;  // energy and rest clamps (iterations and tolerance are set above)
};

struct ProgressiveEmbeddingReport {
  int levels = 0;                      // levels of removals (each an independent set of vertices)
  std::int32_t base_vertices = 0;      // the mesh left when no vertex can be removed, embedded convexly
  std::int64_t insertions = 0;         // vertices put back, each inside the kernel of its link polygon
  std::int64_t failed_insertions = 0;  // kernels too thin for doubles (then the map is not valid)
  int optimizer_iterations = 0;        // Newton steps over all levels
  int final_iterations = 0;            // of them, on the finished map
  double energy_before = 0;            // of the finished map before its own optimization (per unit area)
  double energy_after = 0;
  OptimizeStop final_stop_reason = OptimizeStop::kNone;  // of the finished map's optimization
  bool valid = false;  // every triangle positively oriented (exact), north = +z, south = -z
};

/// A valid map of `mesh` with north at +z and south at -z. Vertices of degree at most 8 (never the
/// poles) are removed in rounds of independent sets, lowest degree first, each by a half-edge collapse
/// into a neighbour (its hole filled by the fan from that neighbour) that creates no duplicate edge and
/// no north-south edge, down to a base embedded by convex_embedding (5 vertices on every mesh tried).
/// The vertices are then put back level by level in reverse, each inside the spherical kernel of its
/// link polygon, which the fan makes non-empty on any valid map (points near the fan's apex see the
/// whole polygon); each level is optimized (optimize_on_sphere, towards equilateral triangles of the
/// surface's areas) so that the next level's kernels stay wide, and the finished map towards the
/// surface's own triangles. `sphere` receives one unit vector per vertex.
/// Preconditions: `mesh` closed, oriented outward, genus 0, 2-manifold, at least 5 vertices; north and
/// south not joined by an edge. Throws std::invalid_argument if the poles are out of range, equal or
/// adjacent. report.valid says whether every triangle ended positively oriented (certify the result).
ProgressiveEmbeddingReport progressive_embedding(const Mesh& mesh, std::int32_t north, std::int32_t south,
                                                 std::vector<Vec3>& sphere,
                                                 const ProgressiveEmbeddingOptions& options = {});

}  // namespace spheremap
