#include "spheremap/shapes/shapes.hpp"

#include <algorithm>
#include <cmath>
#include <cstddef>
#include <limits>
#include <random>
#include <stdexcept>
#include <string>
#include <utility>
#include <vector>

#include "spheremap/geometry/vec.hpp"
#include "spheremap/topology/connectivity.hpp"
#include "spheremap/topology/subdivide.hpp"

namespace spheremap {
namespace {

constexpr std::int64_t kMaxVertexCount = std::numeric_limits<std::int32_t>::max();

/// Uniform double in [0, 1) from 53 raw bits of the generator. std::mt19937's raw output is fixed by
/// the standard, unlike std::uniform_real_distribution, so meshes are identical across standard libraries.
double uniform_unit(std::mt19937& generator) {
  const std::uint64_t high_27_bits = generator() >> 5;
  const std::uint64_t low_26_bits = generator() >> 6;
  return (static_cast<double>(high_27_bits) * 67108864.0 + static_cast<double>(low_26_bits)) / 9007199254740992.0;
}

Vec3 random_point_in_unit_ball(std::mt19937& generator) {
  // Rejection from the cube: uniform in the ball, and deterministic because the draw sequence is
  // (braced initializers evaluate left to right, unlike function arguments).
  while (true) {
    const Vec3 candidate{2 * uniform_unit(generator) - 1, 2 * uniform_unit(generator) - 1,
                         2 * uniform_unit(generator) - 1};
    if (dot(candidate, candidate) <= 1) return candidate;
  }
}

void require_valid_indices(const Mesh& mesh, const char* function) {
  const auto vertex_count = static_cast<std::int64_t>(mesh.positions.size());
  for (const auto& triangle : mesh.triangles)
    for (const auto v : triangle)
      if (v < 0 || v >= vertex_count)
        throw std::invalid_argument(std::string(function) + ": triangle index " + std::to_string(v) + " out of range");
}

}  // namespace

Mesh make_icosphere(int levels) {
  if (levels < 0 || levels > 10)
    throw std::invalid_argument("make_icosphere: levels must be in [0, 10], got " + std::to_string(levels));
  const double phi = (1 + std::sqrt(5.0)) / 2;
  Mesh mesh;
  mesh.positions = {{-1, phi, 0},  {1, phi, 0},  {-1, -phi, 0}, {1, -phi, 0}, {0, -1, phi},  {0, 1, phi},
                    {0, -1, -phi}, {0, 1, -phi}, {phi, 0, -1},  {phi, 0, 1},  {-phi, 0, -1}, {-phi, 0, 1}};
  for (auto& p : mesh.positions) p = normalized(p);
  mesh.triangles = {{0, 11, 5},  {0, 5, 1},  {0, 1, 7},  {0, 7, 10}, {0, 10, 11}, {1, 5, 9}, {5, 11, 4},
                    {11, 10, 2}, {10, 7, 6}, {7, 1, 8},  {3, 9, 4},  {3, 4, 2},   {3, 2, 6}, {3, 6, 8},
                    {3, 8, 9},   {4, 9, 5},  {2, 4, 11}, {6, 2, 10}, {8, 6, 7},   {9, 8, 1}};
  const std::size_t final_vertex_count = 10 * (std::size_t{1} << (2 * levels)) + 2;
  mesh.positions.reserve(final_vertex_count);
  // Projecting after every level (not only at the end) keeps the triangles close to equilateral.
  for (int level = 0; level < levels; ++level) subdivide_midpoint_in_place(mesh.positions, mesh.triangles, true);
  return mesh;
}

Mesh make_ellipsoid(int levels, double ax, double ay, double az) {
  for (const double axis : {ax, ay, az})
    if (!(std::isfinite(axis) && axis > 0))
      throw std::invalid_argument(
          "make_ellipsoid: semi-axes must be finite and positive (a negative one would turn the mesh inside out)");
  Mesh mesh = make_icosphere(levels);
  for (auto& p : mesh.positions) p = {ax * p[0], ay * p[1], az * p[2]};
  return mesh;
}

// `rings` is the number of vertex rings strictly between the two poles, at evenly spaced x stations:
// vertex count rings * segments + 2, (rings - 1) * segments quads plus a triangle fan at each pole.
Mesh make_dumbbell(double separation, double neck_radius, int rings, int segments) {
  if (!(std::isfinite(separation) && separation >= 0))
    throw std::invalid_argument("make_dumbbell: separation must be finite and >= 0");
  if (!(neck_radius > 0 && neck_radius < 1))
    throw std::invalid_argument("make_dumbbell: neck_radius must be in (0, 1)");
  if (rings < 1 || segments < 3) throw std::invalid_argument("make_dumbbell: need rings >= 1 and segments >= 3");
  if (static_cast<std::int64_t>(rings) * segments + 2 > kMaxVertexCount)
    throw std::invalid_argument("make_dumbbell: rings * segments exceeds 32-bit triangle indices");

  const double half_separation = separation / 2;
  const double half_length = half_separation + 1;
  // Max of the two spheres' circles and the neck: single-valued in x, continuous, and > 0 strictly
  // inside (-half_length, half_length), so every ring is a proper polygon.
  const auto profile_radius = [&](double x) {
    const double left = 1 - (x + half_separation) * (x + half_separation);
    const double right = 1 - (x - half_separation) * (x - half_separation);
    double radius = std::sqrt(std::max({0.0, left, right}));
    if (std::abs(x) <= half_separation) radius = std::max(radius, neck_radius);
    return radius;
  };

  Mesh mesh;
  mesh.positions.reserve(static_cast<std::size_t>(rings) * segments + 2);
  const auto pi = std::acos(-1.0);
  for (int ring = 0; ring < rings; ++ring) {
    const double x = -half_length + 2 * half_length * (ring + 1) / (rings + 1);
    const double radius = profile_radius(x);
    for (int segment = 0; segment < segments; ++segment) {
      const double angle = 2 * pi * segment / segments;
      mesh.positions.push_back({x, radius * std::cos(angle), radius * std::sin(angle)});
    }
  }
  const auto left_pole = static_cast<std::int32_t>(mesh.positions.size());
  mesh.positions.push_back({-half_length, 0, 0});
  const auto right_pole = static_cast<std::int32_t>(mesh.positions.size());
  mesh.positions.push_back({half_length, 0, 0});

  const auto ring_vertex = [&](int ring, int segment) {
    return static_cast<std::int32_t>(ring * segments + segment % segments);
  };
  // Going around the angle, then along +x, is counter-clockwise seen from outside.
  mesh.triangles.reserve(2 * static_cast<std::size_t>(rings) * segments);
  for (int segment = 0; segment < segments; ++segment)
    mesh.triangles.push_back({left_pole, ring_vertex(0, segment + 1), ring_vertex(0, segment)});
  for (int ring = 0; ring + 1 < rings; ++ring) {
    for (int segment = 0; segment < segments; ++segment) {
      mesh.triangles.push_back(
          {ring_vertex(ring, segment), ring_vertex(ring, segment + 1), ring_vertex(ring + 1, segment + 1)});
      mesh.triangles.push_back(
          {ring_vertex(ring, segment), ring_vertex(ring + 1, segment + 1), ring_vertex(ring + 1, segment)});
    }
  }
  for (int segment = 0; segment < segments; ++segment)
    mesh.triangles.push_back({right_pole, ring_vertex(rings - 1, segment), ring_vertex(rings - 1, segment + 1)});
  return mesh;
}

Mesh perturb_vertices(const Mesh& mesh, double amplitude, std::uint32_t seed) {
  if (!(std::isfinite(amplitude) && amplitude >= 0))
    throw std::invalid_argument("perturb_vertices: amplitude must be finite and >= 0");
  require_valid_indices(mesh, "perturb_vertices");

  // Each edge of a closed mesh is seen from two triangles, so both sums count it twice: the ratio is
  // the mean length of the vertex's edges.
  std::vector<double> incident_length_sum(mesh.positions.size(), 0.0);
  std::vector<int> incident_count(mesh.positions.size(), 0);
  for (const auto& triangle : mesh.triangles) {
    for (int corner = 0; corner < 3; ++corner) {
      const auto a = triangle[corner], b = triangle[(corner + 1) % 3];
      const double length = norm(mesh.positions[b] - mesh.positions[a]);
      incident_length_sum[a] += length;
      incident_length_sum[b] += length;
      ++incident_count[a];
      ++incident_count[b];
    }
  }

  // Topology is unchanged, so the per-vertex attributes stay valid and are kept.
  Mesh perturbed = mesh;
  std::mt19937 generator(seed);
  for (std::size_t v = 0; v < perturbed.positions.size(); ++v) {
    const Vec3 direction = random_point_in_unit_ball(generator);  // drawn even for isolated vertices
    if (incident_count[v] == 0) continue;
    const double mean_edge_length = incident_length_sum[v] / incident_count[v];
    perturbed.positions[v] = perturbed.positions[v] + (amplitude * mean_edge_length) * direction;
  }
  return perturbed;
}

namespace {

// The half-edge connectivity random_edge_flips keeps up to date while it flips: opposite half-edges, one
// half-edge per edge id, and vertex degrees.
class FlipMesh {
 public:
  // Throws std::invalid_argument unless `mesh` is a closed, consistently oriented 2-manifold with one fan
  // per vertex.
  explicit FlipMesh(Mesh& mesh)
      : mesh_(mesh),
        triangles_(mesh.triangles),
        half_edge_count_(3 * triangles_.size()),
        edges_(number_edges(mesh.positions.size(), triangles_)),
        first_half_edge_(edges_.edge_endpoints.size(), half_edge_count_),
        opposite_(half_edge_count_, half_edge_count_),
        degree_(mesh.positions.size(), 0) {
    for (std::size_t h = 0; h < half_edge_count_; ++h) {
      const auto edge = static_cast<std::size_t>(edges_.edge_of_half_edge[h]);
      const std::size_t partner = first_half_edge_[edge];
      if (partner == half_edge_count_) {
        first_half_edge_[edge] = h;
        continue;
      }
      if (opposite_[partner] != half_edge_count_ ||
          half_edge_origin(triangles_, partner) != half_edge_target(triangles_, h))
        throw std::invalid_argument("random_edge_flips: mesh is not a consistently oriented 2-manifold");
      opposite_[partner] = h;
      opposite_[h] = partner;
    }
    for (std::size_t h = 0; h < half_edge_count_; ++h)
      if (opposite_[h] == half_edge_count_)
        throw std::invalid_argument("random_edge_flips: mesh is not closed (edge with a single triangle)");
    for (const auto& triangle : triangles_)
      for (const auto v : triangle) ++degree_[v];
    require_single_fans();
  }

  [[nodiscard]] std::size_t edge_count() const { return edges_.edge_endpoints.size(); }

  // Flips edge `edge` (ab, between (a, b, c) and (b, a, d)) to cd when that keeps the mesh simplicial
  // (no degree below 3, no duplicate edge) and both new triangles face the way both old ones did.
  void flip_if_allowed(std::size_t edge) {
    // The flipped edge keeps its id (it is never revisited), so first_half_edge stays a valid index.
    const std::size_t h_ab = first_half_edge_[edge];
    const std::size_t h_ba = opposite_[h_ab];
    const std::size_t h_bc = next_half_edge(h_ab), h_ca = previous_half_edge(h_ab);
    const std::size_t h_ad = next_half_edge(h_ba), h_db = previous_half_edge(h_ba);
    const auto a = half_edge_origin(triangles_, h_ab), b = half_edge_target(triangles_, h_ab);
    const auto c = half_edge_origin(triangles_, h_ca), d = half_edge_origin(triangles_, h_db);
    if (c == d || degree_[a] <= 3 || degree_[b] <= 3 || are_neighbors(h_ca, d)) return;

    // Before: (a, b, c) and (b, a, d). After: (c, a, d) and (d, b, c), the same quad split along cd.
    const Vec3 old_normal_1 = normal(a, b, c), old_normal_2 = normal(b, a, d);
    const Vec3 new_normal_1 = normal(c, a, d), new_normal_2 = normal(d, b, c);
    if (!(dot(new_normal_1, old_normal_1) > 0 && dot(new_normal_1, old_normal_2) > 0 &&
          dot(new_normal_2, old_normal_1) > 0 && dot(new_normal_2, old_normal_2) > 0))
      return;

    const std::size_t outer_ca = opposite_[h_ca], outer_ad = opposite_[h_ad];
    const std::size_t outer_db = opposite_[h_db], outer_bc = opposite_[h_bc];
    const auto edge_ca = edges_.edge_of_half_edge[h_ca], edge_ad = edges_.edge_of_half_edge[h_ad];
    const auto edge_db = edges_.edge_of_half_edge[h_db], edge_bc = edges_.edge_of_half_edge[h_bc];

    const std::size_t first = h_ab / 3, second = h_ba / 3;
    triangles_[first] = {c, a, d};   // half-edges: c->a, a->d, d->c
    triangles_[second] = {d, b, c};  // half-edges: d->b, b->c, c->d
    const std::size_t new_ca = 3 * first, new_ad = 3 * first + 1, new_dc = 3 * first + 2;
    const std::size_t new_db = 3 * second, new_bc = 3 * second + 1, new_cd = 3 * second + 2;
    link(new_ca, outer_ca);
    link(new_ad, outer_ad);
    link(new_db, outer_db);
    link(new_bc, outer_bc);
    link(new_dc, new_cd);
    edges_.edge_of_half_edge[new_ca] = edge_ca;
    edges_.edge_of_half_edge[new_ad] = edge_ad;
    edges_.edge_of_half_edge[new_db] = edge_db;
    edges_.edge_of_half_edge[new_bc] = edge_bc;
    edges_.edge_of_half_edge[new_dc] = edges_.edge_of_half_edge[new_cd] = static_cast<std::int32_t>(edge);
    first_half_edge_[static_cast<std::size_t>(edge_ca)] = new_ca;
    first_half_edge_[static_cast<std::size_t>(edge_ad)] = new_ad;
    first_half_edge_[static_cast<std::size_t>(edge_db)] = new_db;
    first_half_edge_[static_cast<std::size_t>(edge_bc)] = new_bc;
    first_half_edge_[edge] = new_dc;
    --degree_[a];
    --degree_[b];
    ++degree_[c];
    ++degree_[d];
  }

 private:
  // The fan walk of are_neighbors is the edge-existence test, so each vertex must have one closed fan.
  void require_single_fans() const {
    std::vector<char> walked(mesh_.positions.size(), 0);
    for (std::size_t h = 0; h < half_edge_count_; ++h) {
      const auto v = half_edge_origin(triangles_, h);
      if (walked[v]) continue;
      walked[v] = 1;
      std::int32_t fan_size = 0;
      std::size_t around = h;
      do {
        ++fan_size;
        around = opposite_[previous_half_edge(around)];
      } while (around != h && fan_size <= degree_[v]);
      if (fan_size != degree_[v])
        throw std::invalid_argument("random_edge_flips: vertex " + std::to_string(v) +
                                    " is not manifold (several fans)");
    }
  }
  [[nodiscard]] bool are_neighbors(std::size_t half_edge_from_vertex, std::int32_t other) const {
    std::size_t around = half_edge_from_vertex;
    do {
      if (half_edge_target(triangles_, around) == other) return true;
      around = opposite_[previous_half_edge(around)];
    } while (around != half_edge_from_vertex);
    return false;
  }
  [[nodiscard]] Vec3 normal(std::int32_t a, std::int32_t b, std::int32_t c) const {
    const auto& p = mesh_.positions;
    return cross(p[b] - p[a], p[c] - p[a]);
  }
  void link(std::size_t h, std::size_t g) {
    opposite_[h] = g;
    opposite_[g] = h;
  }

  Mesh& mesh_;
  std::vector<Triangle>& triangles_;
  std::size_t half_edge_count_;
  EdgeNumbering edges_;
  std::vector<std::size_t> first_half_edge_, opposite_;
  std::vector<std::int32_t> degree_;
};

}  // namespace

Mesh random_edge_flips(const Mesh& mesh, double probability, std::uint32_t seed) {
  if (!(probability >= 0 && probability <= 1))
    throw std::invalid_argument("random_edge_flips: probability must be in [0, 1]");
  require_valid_indices(mesh, "random_edge_flips");
  Mesh flipped = mesh;  // vertices do not move, so attributes stay valid
  FlipMesh flips(flipped);
  // One random draw per original edge in edge-id order, whether or not it flips: the sequence of
  // draws, hence the result, depends only on the seed and the input mesh.
  std::mt19937 generator(seed);
  for (std::size_t edge = 0; edge < flips.edge_count(); ++edge)
    if (uniform_unit(generator) < probability) flips.flip_if_allowed(edge);
  return flipped;
}

Mesh make_subdivided_cube(int n) {
  // 6 n^2 + 2 vertices must fit 32-bit indices; 10000 (600M vertices) is far beyond any practical use.
  if (n < 1 || n > 10000) throw std::invalid_argument("make_subdivided_cube: n must be in [1, 10000]");
  const auto grid_size = static_cast<std::int64_t>(n) + 1;
  // Dense lookup from grid coordinates (i, j, k) in [0, n]^3 would be (n+1)^3 entries; the surface has
  // only ~6 n^2 points, so key them by a face-independent code in a sorted table instead.
  const auto point_code = [&](std::int64_t i, std::int64_t j, std::int64_t k) {
    return (i * grid_size + j) * grid_size + k;
  };

  std::vector<std::int64_t> surface_codes;
  surface_codes.reserve(6 * static_cast<std::size_t>(n) * static_cast<std::size_t>(n) + 2);
  for (std::int64_t i = 0; i <= n; ++i)
    for (std::int64_t j = 0; j <= n; ++j)
      for (std::int64_t k = 0; k <= n; ++k) {
        const bool on_surface = i == 0 || i == n || j == 0 || j == n || k == 0 || k == n;
        if (on_surface) surface_codes.push_back(point_code(i, j, k));
        // Skip the cube's interior of this (i, j) column in one step.
        if (!on_surface && k == 1 && n > 1) k = n - 1;
      }
  // Codes were generated in increasing order, so the table is already sorted.
  Mesh mesh;
  mesh.positions.reserve(surface_codes.size());
  for (const auto code : surface_codes) {
    const std::int64_t k = code % grid_size, j = (code / grid_size) % grid_size, i = code / (grid_size * grid_size);
    const auto coordinate = [&](std::int64_t index) { return -1.0 + 2.0 * static_cast<double>(index) / n; };
    mesh.positions.push_back({coordinate(i), coordinate(j), coordinate(k)});
  }
  const auto vertex_at = [&](const std::array<std::int64_t, 3>& grid_point) {
    const auto code = point_code(grid_point[0], grid_point[1], grid_point[2]);
    return static_cast<std::int32_t>(std::lower_bound(surface_codes.begin(), surface_codes.end(), code) -
                                     surface_codes.begin());
  };

  mesh.triangles.reserve(12 * static_cast<std::size_t>(n) * static_cast<std::size_t>(n));
  for (int normal_axis = 0; normal_axis < 3; ++normal_axis) {
    for (const int side : {-1, 1}) {
      // (u, v, normal) right-handed on the + side and swapped on the - side, so (u, v) order is
      // counter-clockwise seen from outside on every face.
      const int u_axis = side > 0 ? (normal_axis + 1) % 3 : (normal_axis + 2) % 3;
      const int v_axis = side > 0 ? (normal_axis + 2) % 3 : (normal_axis + 1) % 3;
      const auto face_vertex = [&](std::int64_t u, std::int64_t v) {
        std::array<std::int64_t, 3> grid_point{};
        grid_point[normal_axis] = side > 0 ? n : 0;
        grid_point[u_axis] = u;
        grid_point[v_axis] = v;
        return vertex_at(grid_point);
      };
      for (std::int64_t u = 0; u < n; ++u)
        for (std::int64_t v = 0; v < n; ++v) {
          const auto p00 = face_vertex(u, v), p10 = face_vertex(u + 1, v);
          const auto p11 = face_vertex(u + 1, v + 1), p01 = face_vertex(u, v + 1);
          mesh.triangles.push_back({p00, p10, p11});
          mesh.triangles.push_back({p00, p11, p01});
        }
    }
  }
  return mesh;
}

}  // namespace spheremap
