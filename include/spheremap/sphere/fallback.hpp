// The fallback map_to_sphere runs when the plain map and its repair end uncertified: a valid map built
// by progressive embedding and optimized on the sphere (embedding.hpp), certified like any other.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

#include "spheremap/mesh.hpp"
#include "spheremap/sphere/embedding.hpp"

namespace spheremap {

/// What the fallback did (MapDiagnostics::fallback; report.json's map.fallback when it ran).
struct FallbackReport {
  bool ran = false;
  /// The vertex put at -z: the south pole, or, when the poles are joined by an edge (default poles of a
  /// tiny mesh; an edge cannot join antipodal points), the vertex farthest from north in edges.
  std::int32_t south = -1;
  ProgressiveEmbeddingReport embedding;
};

/// A map of `mesh` with north at +z and south (or report.south, see above) at -z, every triangle
/// positively oriented unless report.embedding.valid is false (doubles could not hold a kernel or a
/// triangle: see docs/algorithm.md for the limits). The caller certifies it.
/// Preconditions: `mesh` closed, oriented outward, genus 0, 2-manifold, at least 5 vertices; north !=
/// south, both vertices of `mesh`. Returns an empty vector (report.ran false) when every vertex is a
/// neighbour of north (a tetrahedron: there is no pair of poles to put antipodal).
/// Throws std::invalid_argument if the poles are out of range or equal.
std::vector<Vec3> fallback_map(const Mesh& mesh, std::int32_t north, std::int32_t south, FallbackReport& report,
                               const ProgressiveEmbeddingOptions& options = {});

}  // namespace spheremap
