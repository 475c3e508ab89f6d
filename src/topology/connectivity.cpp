#include "spheremap/topology/connectivity.hpp"

#include <algorithm>
#include <limits>
#include <numeric>
#include <stdexcept>
#include <string>

#include "../util/parallel.hpp"

namespace spheremap {

EdgeNumbering number_edges(std::size_t vertex_count, const std::vector<Triangle>& triangles) {
  // Bucket every half-edge under its lower endpoint (counting sort), then sort each small bucket by the
  // higher endpoint: linear overall, and far faster than a hash map of edges for millions of triangles.
  const std::size_t half_edge_count = 3 * triangles.size();
  std::vector<std::size_t> bucket_start(vertex_count + 1, 0);
  for (std::size_t h = 0; h < half_edge_count; ++h) {
    const auto lower = std::min(half_edge_origin(triangles, h), half_edge_target(triangles, h));
    ++bucket_start[static_cast<std::size_t>(lower) + 1];
  }
  for (std::size_t v = 0; v < vertex_count; ++v) bucket_start[v + 1] += bucket_start[v];

  struct Entry {
    std::int32_t higher_vertex;
    std::size_t half_edge;
  };
  std::vector<Entry> entries(half_edge_count);
  {
    std::vector<std::size_t> fill(bucket_start.begin(), bucket_start.end() - 1);
    for (std::size_t h = 0; h < half_edge_count; ++h) {
      const auto a = half_edge_origin(triangles, h), b = half_edge_target(triangles, h);
      entries[fill[static_cast<std::size_t>(std::min(a, b))]++] = {std::max(a, b), h};
    }
  }

  EdgeNumbering numbering;
  numbering.edge_of_half_edge.resize(half_edge_count);
  numbering.edge_endpoints.reserve(half_edge_count / 2 + 1);
  for (std::size_t v = 0; v < vertex_count; ++v) {
    const auto begin = entries.begin() + static_cast<std::ptrdiff_t>(bucket_start[v]);
    const auto end = entries.begin() + static_cast<std::ptrdiff_t>(bucket_start[v + 1]);
    // Ties broken by half-edge index so the numbering never depends on the sort's stability.
    std::sort(begin, end, [](const Entry& x, const Entry& y) {
      return x.higher_vertex != y.higher_vertex ? x.higher_vertex < y.higher_vertex : x.half_edge < y.half_edge;
    });
    for (auto it = begin; it != end; ++it) {
      if (it == begin || it->higher_vertex != (it - 1)->higher_vertex) {
        if (numbering.edge_endpoints.size() >= static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()))
          throw std::invalid_argument("number_edges: too many edges for 32-bit indices");
        numbering.edge_endpoints.push_back({static_cast<std::int32_t>(v), it->higher_vertex});
      }
      numbering.edge_of_half_edge[it->half_edge] = static_cast<std::int32_t>(numbering.edge_endpoints.size() - 1);
    }
  }
  return numbering;
}

std::vector<std::int32_t> opposite_half_edges(std::size_t vertex_count, const std::vector<Triangle>& triangles,
                                              int threads) {
  if (triangles.size() > static_cast<std::size_t>(std::numeric_limits<std::int32_t>::max()) / 3)
    throw std::invalid_argument("opposite_half_edges: too many triangles for 32-bit half-edge indices");
  // The triangles around each vertex (counting sort), then each half-edge a -> b looks among b's triangles
  // for b -> a and for other triangles that hold a -> b: one short list per half-edge, read in parallel.
  std::vector<std::int32_t> first(vertex_count + 1, 0);
  for (const Triangle& t : triangles)
    for (const std::int32_t v : t) ++first[static_cast<std::size_t>(v) + 1];
  std::partial_sum(first.begin(), first.end(), first.begin());
  std::vector<std::int32_t> around(static_cast<std::size_t>(first[vertex_count]));
  {
    std::vector<std::int32_t> next(first.begin(), first.end() - 1);
    for (std::size_t t = 0; t < triangles.size(); ++t)
      for (const std::int32_t v : triangles[t])
        around[static_cast<std::size_t>(next[v]++)] = static_cast<std::int32_t>(t);
  }
  std::vector<std::int32_t> opposite(3 * triangles.size(), -1);
  detail::parallel_ranges(static_cast<std::int64_t>(triangles.size()), 8192, threads,
                          [&](std::int64_t begin, std::int64_t end) {
                            for (auto t = static_cast<std::size_t>(begin); t < static_cast<std::size_t>(end); ++t)
                              for (std::size_t k = 0; k < 3; ++k) {
                                const std::int32_t a = triangles[t][k], b = triangles[t][(k + 1) % 3];
                                if (a == b) continue;  // a degenerate edge has no triangle across
                                std::int32_t match = -1, reversed = 0, same = 0;
                                for (std::int32_t i = first[b]; i < first[b + 1]; ++i) {
                                  const auto u = static_cast<std::size_t>(around[static_cast<std::size_t>(i)]);
                                  for (std::size_t j = 0; j < 3; ++j) {
                                    if (triangles[u][j] == b && triangles[u][(j + 1) % 3] == a)
                                      ++reversed, match = static_cast<std::int32_t>(3 * u + j);
                                    if (triangles[u][j] == a && triangles[u][(j + 1) % 3] == b) ++same;
                                  }
                                }
                                if (reversed == 1 && same == 1) opposite[3 * t + k] = match;
                              }
                          });
  return opposite;
}

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
    if (degree < 3)
      throw std::invalid_argument("build_vertex_rings: vertex " + std::to_string(v) + " has fewer than 3 triangles");
    // Degrees are small: a linear scan per step is faster than any map.
    std::int32_t current = from[begin];
    for (std::int64_t k = 0; k < degree; ++k) {
      rings.neighbors[begin + k] = current;
      std::int64_t slot = begin;
      while (slot < end && from[slot] != current) ++slot;
      if (slot == end)
        throw std::invalid_argument("build_vertex_rings: the triangles around vertex " + std::to_string(v) +
                                    " do not form a closed fan");
      current = to[slot];
      if (k + 1 < degree && current == from[begin])
        throw std::invalid_argument("build_vertex_rings: the triangles around vertex " + std::to_string(v) +
                                    " form more than one fan");
    }
    if (current != from[begin])
      throw std::invalid_argument("build_vertex_rings: the triangles around vertex " + std::to_string(v) +
                                  " do not form a single fan");
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
