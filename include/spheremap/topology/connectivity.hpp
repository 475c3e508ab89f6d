// Adjacency of a closed oriented 2-manifold triangle mesh (stage: topology).
#pragma once

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

/// Breadth-first graph distances (in edges) from `source`; unreachable vertices get -1.
std::vector<std::int32_t> graph_distances(const VertexRings& rings, std::int32_t source);

}  // namespace spheremap
