#include "spheremap/sphere/fallback.hpp"

#include <stdexcept>
#include <string>

#include "spheremap/geometry/vec.hpp"
#include "spheremap/topology/connectivity.hpp"

namespace spheremap {
namespace {

// The vertex farthest from north in edges (ties: farthest in space, then the lowest index); -1 if every
// vertex is north or its neighbour.
std::int32_t farthest_in_edges(const Mesh& mesh, std::int32_t north) {
  const auto n = static_cast<std::int32_t>(mesh.positions.size());
  const auto distance = graph_distances(build_vertex_rings(n, mesh.triangles), north);
  std::int32_t best = -1;
  for (std::int32_t v = 0; v < n; ++v) {
    if (distance[v] < 2) continue;
    if (best < 0 || distance[v] > distance[best] ||
        (distance[v] == distance[best] && squared_distance(mesh.positions[v], mesh.positions[north]) >
                                              squared_distance(mesh.positions[best], mesh.positions[north])))
      best = v;
  }
  return best;
}

}  // namespace

std::vector<Vec3> fallback_map(const Mesh& mesh, std::int32_t north, std::int32_t south, FallbackReport& report,
                               const ProgressiveEmbeddingOptions& options) {
  const auto n = static_cast<std::int32_t>(mesh.positions.size());
  if (north < 0 || south < 0 || north >= n || south >= n || north == south)
    throw std::invalid_argument("fallback_map: poles " + std::to_string(north) + ", " + std::to_string(south) +
                                " must be two different vertices in [0, " + std::to_string(n) + ")");
  report = FallbackReport{};
  bool adjacent = false;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k)
      adjacent = adjacent || (t[k] == north && (t[(k + 1) % 3] == south || t[(k + 2) % 3] == south));
  report.south = adjacent ? farthest_in_edges(mesh, north) : south;
  if (report.south < 0) return {};
  report.ran = true;
  std::vector<Vec3> sphere;
  report.embedding = progressive_embedding(mesh, north, report.south, sphere, options);
  return sphere;
}

}  // namespace spheremap
