#include "spheremap/topology/subdivide.hpp"

#include <cstdint>
#include <limits>
#include <stdexcept>
#include <string>
#include <utility>

#include "spheremap/geometry/vec.hpp"
#include "spheremap/topology/connectivity.hpp"

namespace spheremap {

void subdivide_midpoint_in_place(std::vector<Vec3>& positions, std::vector<Triangle>& triangles,
                                 bool project_to_unit_sphere) {
  const EdgeNumbering edges = number_edges(positions.size(), triangles);
  const auto old_vertex_count = static_cast<std::int64_t>(positions.size());
  const auto new_vertex_count = old_vertex_count + static_cast<std::int64_t>(edges.edge_endpoints.size());
  if (new_vertex_count > std::numeric_limits<std::int32_t>::max())
    throw std::invalid_argument("subdivision would exceed 2^31 - 1 vertices (32-bit triangle indices)");

  positions.reserve(positions.size() + edges.edge_endpoints.size());
  for (const auto& [a, b] : edges.edge_endpoints) {
    const Vec3 midpoint = 0.5 * (positions[a] + positions[b]);
    positions.push_back(project_to_unit_sphere ? normalized(midpoint) : midpoint);
  }

  std::vector<Triangle> refined;
  refined.reserve(4 * triangles.size());
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const auto [a, b, c] = triangles[t];
    const auto midpoint_vertex = [&](std::size_t corner) {
      return static_cast<std::int32_t>(old_vertex_count + edges.edge_of_half_edge[3 * t + corner]);
    };
    const std::int32_t ab = midpoint_vertex(0), bc = midpoint_vertex(1), ca = midpoint_vertex(2);
    // Same orientation as the parent: three corner triangles and the middle one.
    refined.push_back({a, ab, ca});
    refined.push_back({ab, b, bc});
    refined.push_back({ca, bc, c});
    refined.push_back({ab, bc, ca});
  }
  triangles = std::move(refined);
}

Mesh subdivide_midpoint(const Mesh& mesh, int levels) {
  if (levels < 0) throw std::invalid_argument("subdivide_midpoint: levels must be >= 0");
  const auto vertex_count = static_cast<std::int64_t>(mesh.positions.size());
  for (const auto& triangle : mesh.triangles)
    for (const auto v : triangle)
      if (v < 0 || v >= vertex_count)
        throw std::invalid_argument("subdivide_midpoint: triangle index " + std::to_string(v) + " out of range");
  Mesh result;
  result.positions = mesh.positions;
  result.triangles = mesh.triangles;
  for (int level = 0; level < levels; ++level) subdivide_midpoint_in_place(result.positions, result.triangles);
  return result;
}

}  // namespace spheremap
