#include "spheremap/geometry/normals.hpp"

#include <stdexcept>

#include "spheremap/geometry/vec.hpp"

namespace spheremap {

std::vector<Vec3> vertex_normals(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles) {
  std::vector<Vec3> normals(positions.size(), Vec3{0, 0, 0});
  for (const auto& t : triangles) {
    // Twice the triangle's area along its normal: larger triangles weigh more, slivers hardly count.
    const Vec3 n = cross(positions[t[1]] - positions[t[0]], positions[t[2]] - positions[t[0]]);
    for (const auto v : t) normals[v] = normals[v] + n;
  }
  for (auto& n : normals) n = normalized(n);
  return normals;
}

std::vector<Vec3> offset_along_normals(const std::vector<Vec3>& positions, const std::vector<Vec3>& normals,
                                       double distance) {
  if (positions.size() != normals.size())
    throw std::invalid_argument("offset_along_normals: positions and normals differ in size");
  std::vector<Vec3> points(positions.size());
  for (std::size_t v = 0; v < positions.size(); ++v) points[v] = positions[v] + distance * normals[v];
  return points;
}

}  // namespace spheremap
