// Adjacency of a closed oriented 2-manifold triangle mesh (stage: topology).
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>
#include <span>
#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// For every vertex, its neighbours in counter-clockwise order seen from outside (the order of the
/// triangles' orientation), stored contiguously: neighbours of v are
/// neighbors[offsets[v] .. offsets[v+1]). The cyclic order starts at an arbitrary neighbour.
struct VertexRings {
  std::vector<std::int64_t> offsets;
  std::vector<std::int32_t> neighbors;

  [[nodiscard]] std::span<const std::int32_t> ring(std::int32_t v) const {
    return {neighbors.data() + offsets[v], static_cast<std::size_t>(offsets[v + 1] - offsets[v])};
  }
  [[nodiscard]] std::int32_t degree(std::int32_t v) const {
    return static_cast<std::int32_t>(offsets[v + 1] - offsets[v]);
  }
  [[nodiscard]] std::int32_t vertex_count() const { return static_cast<std::int32_t>(offsets.size()) - 1; }
};

/// Preconditions: `triangles` form a closed, consistently oriented 2-manifold on `vertex_count`
/// vertices (as produced by prepare_mesh). Throws std::invalid_argument if a vertex's triangles do not
/// form a single closed fan (the precondition is violated).
VertexRings build_vertex_rings(std::int32_t vertex_count, const std::vector<Triangle>& triangles);

/// Half-edge h = 3 * triangle + corner runs from triangles[h / 3][h % 3] to the next corner's vertex.
inline std::size_t next_half_edge(std::size_t h) { return h - h % 3 + (h + 1) % 3; }
inline std::size_t previous_half_edge(std::size_t h) { return h - h % 3 + (h + 2) % 3; }
inline std::int32_t half_edge_origin(const std::vector<Triangle>& triangles, std::size_t h) {
  return triangles[h / 3][h % 3];
}
inline std::int32_t half_edge_target(const std::vector<Triangle>& triangles, std::size_t h) {
  return triangles[h / 3][(h + 1) % 3];
}

/// Both half-edges of an edge share one edge id; ids are dense and numbered in (lower vertex,
/// higher vertex) order, so the numbering is deterministic.
struct EdgeNumbering {
  std::vector<std::int32_t> edge_of_half_edge;
  std::vector<std::array<std::int32_t, 2>> edge_endpoints;  // lower vertex first
};

/// Numbers the edges of any triangle soup (no manifold precondition: an edge is a pair of vertices,
/// however many triangles share it). Linear in the triangles.
/// Preconditions: every index in [0, vertex_count).
/// Throws std::invalid_argument if there are 2^31 - 1 edges or more.
EdgeNumbering number_edges(std::size_t vertex_count, const std::vector<Triangle>& triangles);

/// For every half-edge h (see next_half_edge), the half-edge of the triangle across its edge: the other
/// half-edge between the same two vertices, running the other way; -1 where the edge is not shared by
/// exactly two triangles in opposite directions (a hole, a non-manifold or a misoriented edge). Works on
/// any triangle soup, from `threads` threads (the result does not depend on them).
/// Preconditions: every index in [0, vertex_count). Throws std::invalid_argument if there are 2^31 or
/// more half-edges.
std::vector<std::int32_t> opposite_half_edges(std::size_t vertex_count, const std::vector<Triangle>& triangles,
                                              int threads = 1);

/// Breadth-first graph distances (in edges) from `source`; unreachable vertices get -1.
/// Precondition: source in [0, rings.vertex_count()). Throws nothing beyond std::bad_alloc.
std::vector<std::int32_t> graph_distances(const VertexRings& rings, std::int32_t source);

}  // namespace spheremap
