#include "spheremap/surface/contour.hpp"

#include <algorithm>
#include <stdexcept>
#include <unordered_map>

#include "spheremap/geometry/vec.hpp"

namespace spheremap {
namespace {

// Corners of a cell as offsets; the Freudenthal tetrahedra walk from corner 0 to corner 7 adding one
// axis at a time, in each of the six axis orders.
constexpr std::array<std::array<int, 3>, 8> kCorner = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0},
                                                         {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}}};
constexpr std::array<std::array<int, 4>, 6> kTetrahedra = {{{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                                                            {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}}};

// Where the surface passes within this fraction of a step of a sample, its vertex is kept at this fraction:
// vertices closer to a sample make sliver triangles of almost no area, whose area ratios dominate any
// distortion statistic of a map. The shift is at most a tenth of a step.
// Measured on 1crn at 0.5 Å: mean area distortion of its map 339,424% with 1e-6, 260% with 0.1; the SES
// area moved from -0.82% to -0.37% of MSMS's (0.2 overshoots to +1.5%).
constexpr double kMinimumFraction = 0.1;

}  // namespace

Mesh contour_isosurface(const Grid3<double>& field, double level) {
  const auto [nx, ny, nz] = field.size;
  if (nx < 2 || ny < 2 || nz < 2) throw std::invalid_argument("contour_isosurface: the grid needs at least 2 samples per axis");
  auto inside = [&](std::int64_t s) { return field.values[s] > level; };
  for (std::int64_t k = 0; k < nz; ++k)
    for (std::int64_t j = 0; j < ny; ++j)
      for (std::int64_t i = 0; i < nx; ++i) {
        const bool border = i == 0 || j == 0 || k == 0 || i == nx - 1 || j == ny - 1 || k == nz - 1;
        if (border && inside(field.index(i, j, k)))
          throw std::invalid_argument("contour_isosurface: the surface reaches the border of the grid; pad the grid");
      }
  Mesh mesh;
  std::unordered_map<std::uint64_t, std::int32_t> vertex_of_edge;
  auto edge_vertex = [&](std::int64_t a, std::int64_t b) {
    if (a > b) std::swap(a, b);
    const auto key = static_cast<std::uint64_t>(a) * 8 + static_cast<std::uint64_t>(b - a == 1 ? 0 : b - a == nx ? 1 : b - a == nx * ny ? 2
                                                                                   : b - a == nx + 1 ? 3 : b - a == nx * ny + 1 ? 4
                                                                                   : b - a == nx * ny + nx ? 5 : 6);
    auto [it, inserted] = vertex_of_edge.emplace(key, static_cast<std::int32_t>(mesh.positions.size()));
    if (inserted) {
      const double fa = field.values[a], fb = field.values[b];
      const double t = std::clamp((level - fa) / (fb - fa), kMinimumFraction, 1 - kMinimumFraction);
      auto position = [&](std::int64_t s) {
        const std::int64_t i = s % nx, j = (s / nx) % ny, k = s / (nx * ny);
        return field.point(i, j, k);
      };
      const Vec3 pa = position(a), pb = position(b);
      mesh.positions.push_back(pa + t * (pb - pa));
    }
    return it->second;
  };
  auto sample_point = [&](std::int64_t s) {
    const std::int64_t i = s % nx, j = (s / nx) % ny, k = s / (nx * ny);
    return field.point(i, j, k);
  };
  // Emits triangle (a, b, c) on the given edges, turned so that its normal points away from `from`
  // (an inside sample). Orientation is decided on edge midpoints, which are never degenerate.
  auto emit = [&](std::array<std::pair<std::int64_t, std::int64_t>, 3> edges, std::int64_t from) {
    Vec3 mid[3];
    for (int e = 0; e < 3; ++e) mid[e] = 0.5 * (sample_point(edges[e].first) + sample_point(edges[e].second));
    const Vec3 normal = cross(mid[1] - mid[0], mid[2] - mid[0]);
    if (dot(normal, mid[0] - sample_point(from)) < 0) std::swap(edges[1], edges[2]);
    mesh.triangles.push_back({edge_vertex(edges[0].first, edges[0].second), edge_vertex(edges[1].first, edges[1].second),
                              edge_vertex(edges[2].first, edges[2].second)});
  };
  for (std::int64_t k = 0; k + 1 < nz; ++k)
    for (std::int64_t j = 0; j + 1 < ny; ++j)
      for (std::int64_t i = 0; i + 1 < nx; ++i) {
        std::array<std::int64_t, 8> corner;
        int inside_count = 0;
        for (int c = 0; c < 8; ++c) {
          corner[c] = field.index(i + kCorner[c][0], j + kCorner[c][1], k + kCorner[c][2]);
          inside_count += inside(corner[c]);
        }
        if (inside_count == 0 || inside_count == 8) continue;
        for (const auto& tet : kTetrahedra) {
          std::array<std::int64_t, 4> in{}, out{};
          int n_in = 0, n_out = 0;
          for (int v : tet) (inside(corner[v]) ? in[n_in++] : out[n_out++]) = corner[v];
          if (n_in == 0 || n_out == 0) continue;
          if (n_in == 1) {
            emit({{{in[0], out[0]}, {in[0], out[1]}, {in[0], out[2]}}}, in[0]);
          } else if (n_in == 3) {
            emit({{{in[0], out[0]}, {in[1], out[0]}, {in[2], out[0]}}}, in[0]);
          } else {
            // A quad on edges (in0,out0) (in0,out1) (in1,out1) (in1,out0), split along one diagonal.
            emit({{{in[0], out[0]}, {in[0], out[1]}, {in[1], out[1]}}}, in[0]);
            emit({{{in[0], out[0]}, {in[1], out[1]}, {in[1], out[0]}}}, in[1]);
          }
        }
      }
  return mesh;
}

}  // namespace spheremap
