// Small exact shapes and rotations shared by the geometry and metrics tests.
#pragma once

#include <array>
#include <cmath>
#include <map>
#include <utility>
#include <vector>

#include "spheremap/geometry/vec.hpp"
#include "spheremap/mesh.hpp"

namespace spheremap::testing_support {

// Octahedron split `levels` times into four by its edge midpoints, vertices on the unit sphere.
// Symmetric under the reflections x -> -x, y -> -y, z -> -z, and every face stays inside one octant.
inline Mesh subdivided_octahedron(int levels) {
  Mesh mesh;
  mesh.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  mesh.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoints;
    const auto midpoint = [&](int i, int j) {
      const auto key = std::minmax(i, j);
      const auto [it, inserted] = midpoints.try_emplace(key, static_cast<int>(mesh.positions.size()));
      if (inserted) mesh.positions.push_back(normalized(0.5 * (mesh.positions[i] + mesh.positions[j])));
      return it->second;
    };
    std::vector<Triangle> finer;
    for (const auto& [a, b, c] : mesh.triangles) {
      const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      finer.insert(finer.end(), {{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}});
    }
    mesh.triangles = std::move(finer);
  }
  return mesh;
}

/// The rotation by `angle` (radians) about `axis`, row-major (Rodrigues).
inline std::array<double, 9> rotation_about(const Vec3& axis, double angle) {
  const Vec3 k = normalized(axis);
  const double c = std::cos(angle), s = std::sin(angle), t = 1 - c;
  return {t * k[0] * k[0] + c,        t * k[0] * k[1] - s * k[2], t * k[0] * k[2] + s * k[1],
          t * k[0] * k[1] + s * k[2], t * k[1] * k[1] + c,        t * k[1] * k[2] - s * k[0],
          t * k[0] * k[2] - s * k[1], t * k[1] * k[2] + s * k[0], t * k[2] * k[2] + c};
}

}  // namespace spheremap::testing_support
