#include "spheremap/topology/connectivity.hpp"

#include <numeric>
#include <stdexcept>
#include <string>

namespace spheremap {

VertexRings build_vertex_rings(std::int32_t vertex_count, const std::vector<Triangle>& triangles) {
  // At vertex a, triangle (a, b, c) says: counter-clockwise after b comes c.
  std::vector<std::int64_t> start(static_cast<std::size_t>(vertex_count) + 1, 0);
  for (const auto& t : triangles)
    for (auto v : t) ++start[v + 1];
  std::partial_sum(start.begin(), start.end(), start.begin());
  std::vector<std::int32_t> from(start.back()), to(start.back());
  {
    std::vector<std::int64_t> fill(start.begin(), start.end() - 1);
    for (const auto& t : triangles) {
      for (int k = 0; k < 3; ++k) {
        const auto slot = fill[t[k]]++;
        from[slot] = t[(k + 1) % 3];
        to[slot] = t[(k + 2) % 3];
      }
    }
  }
  VertexRings rings;
  rings.offsets = start;
  rings.neighbors.resize(start.back());
  for (std::int32_t v = 0; v < vertex_count; ++v) {
    const auto begin = start[v], end = start[v + 1];
    const auto degree = end - begin;
    if (degree < 3) throw std::invalid_argument("build_vertex_rings: vertex " + std::to_string(v) + " has fewer than 3 triangles");
    // Degrees are small: a linear scan per step is faster than any map.
    std::int32_t current = from[begin];
    for (std::int64_t k = 0; k < degree; ++k) {
      rings.neighbors[begin + k] = current;
      std::int64_t slot = begin;
      while (slot < end && from[slot] != current) ++slot;
      if (slot == end) throw std::invalid_argument("build_vertex_rings: the triangles around vertex " + std::to_string(v) + " do not form a closed fan");
      current = to[slot];
      if (k + 1 < degree && current == from[begin])
        throw std::invalid_argument("build_vertex_rings: the triangles around vertex " + std::to_string(v) + " form more than one fan");
    }
    if (current != from[begin]) throw std::invalid_argument("build_vertex_rings: the triangles around vertex " + std::to_string(v) + " do not form a single fan");
  }
  return rings;
}

std::vector<std::int32_t> graph_distances(const VertexRings& rings, std::int32_t source) {
  std::vector<std::int32_t> distance(rings.vertex_count(), -1);
  std::vector<std::int32_t> queue{source};
  distance[source] = 0;
  for (std::size_t head = 0; head < queue.size(); ++head) {
    const auto v = queue[head];
    for (auto w : rings.ring(v)) {
      if (distance[w] < 0) {
        distance[w] = distance[v] + 1;
        queue.push_back(w);
      }
    }
  }
  return distance;
}

}  // namespace spheremap
