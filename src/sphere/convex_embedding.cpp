// Tutte embedding, Maxwell–Cremona lift and central projection (embedding.hpp: convex_embedding).
#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>
#include <algorithm>
#include <array>
#include <cmath>
#include <deque>
#include <numbers>
#include <stdexcept>
#include <string>
#include <vector>

#include "solver_section.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/sphere/embedding.hpp"
#include "spheremap/topology/connectivity.hpp"

namespace spheremap {
namespace {

using Point2 = std::array<double, 2>;

// Tutte's barycentric embedding: every vertex not on the outer triangle at the mean of its neighbours.
std::vector<Point2> tutte_embedding(const VertexRings& rings, const Triangle& outer) {
  const auto n = rings.vertex_count();
  std::vector<Point2> plane(n, Point2{0, 0});
  std::vector<Eigen::Index> unknown(n, -1);
  Eigen::Index unknowns = 0;
  for (std::int32_t v = 0; v < n; ++v)
    if (v != outer[0] && v != outer[1] && v != outer[2]) unknown[v] = unknowns++;
  // The outer face (a, b, c) is counter-clockwise seen from outside the surface, so with the unbounded
  // region on its left it runs clockwise in the plane; every inner face is then counter-clockwise.
  for (int k = 0; k < 3; ++k) {
    const double angle = std::numbers::pi / 2 - 2 * std::numbers::pi * k / 3;
    plane[outer[k]] = {std::cos(angle), std::sin(angle)};
  }
  std::vector<Eigen::Triplet<double>> entries;
  Eigen::MatrixXd rhs = Eigen::MatrixXd::Zero(unknowns, 2);
  for (std::int32_t v = 0; v < n; ++v) {
    if (unknown[v] < 0) continue;
    entries.emplace_back(unknown[v], unknown[v], rings.degree(v));
    for (const auto w : rings.ring(v)) {
      if (unknown[w] >= 0)
        entries.emplace_back(unknown[v], unknown[w], -1.0);
      else
        rhs(unknown[v], 0) += plane[w][0], rhs(unknown[v], 1) += plane[w][1];
    }
  }
  Eigen::SparseMatrix<double> matrix(unknowns, unknowns);
  matrix.setFromTriplets(entries.begin(), entries.end());
  const detail::SolverSection section;  // the factorization and every solve below
  Eigen::CholmodSupernodalLLT<Eigen::SparseMatrix<double>, Eigen::Lower> cholesky(matrix);
  if (cholesky.info() != Eigen::Success)
    throw std::runtime_error("convex_embedding: the Tutte system could not be factorized");
  Eigen::MatrixXd solution = cholesky.solve(rhs);
  // Iterative refinement: the residual in long double, the correction from the same factor.
  for (int step = 0; step < 2; ++step) {
    Eigen::MatrixXd residual(unknowns, 2);
    for (std::int32_t v = 0; v < n; ++v) {
      if (unknown[v] < 0) continue;
      for (int axis = 0; axis < 2; ++axis) {
        long double r = rhs(unknown[v], axis) - static_cast<long double>(rings.degree(v)) * solution(unknown[v], axis);
        for (const auto w : rings.ring(v))
          if (unknown[w] >= 0) r += solution(unknown[w], axis);
        residual(unknown[v], axis) = static_cast<double>(r);
      }
    }
    solution += cholesky.solve(residual);
  }
  for (std::int32_t v = 0; v < n; ++v)
    if (unknown[v] >= 0) plane[v] = {solution(unknown[v], 0), solution(unknown[v], 1)};
  return plane;
}

// Maxwell–Cremona: with positive stresses (the Tutte weights, 1) on the inner edges, each inner face
// gets a plane h_t(x) = g·x + c so that crossing edge i->j (face t on its left) from t adds
// ω·cross(p_j - p_i, x - p_i): a concave dome over the outer triangle whose faces, with the outer
// triangle below them, bound a convex polyhedron. Returns each vertex's height.
std::vector<double> lift(const std::vector<Point2>& plane, const std::vector<Triangle>& triangles,
                         std::size_t outer_face) {
  const auto n = plane.size();
  struct Plane {
    double gx, gy, c;
  };
  std::vector<Plane> planes(triangles.size(), Plane{0, 0, 0});
  std::vector<char> done(triangles.size(), 0);
  // Directed edge -> face on its left.
  std::vector<std::vector<std::pair<std::int32_t, std::size_t>>> left(n);
  for (std::size_t t = 0; t < triangles.size(); ++t)
    for (int k = 0; k < 3; ++k) left[triangles[t][k]].emplace_back(triangles[t][(k + 1) % 3], t);
  auto face_left_of = [&](std::int32_t i, std::int32_t j) {
    for (const auto& [to, face] : left[i])
      if (to == j) return face;
    throw std::logic_error("convex_embedding: an edge has no face on one side");
  };
  std::vector<double> height(n, 0);
  std::vector<char> has_height(n, 0);
  const std::size_t start = outer_face == 0 ? 1 : 0;
  std::deque<std::size_t> queue{start};
  done[start] = 1;
  while (!queue.empty()) {
    const auto t = queue.front();
    queue.pop_front();
    const auto& tri = triangles[t];
    for (int k = 0; k < 3; ++k) {
      const auto v = tri[k];
      if (!has_height[v])
        height[v] = planes[t].gx * plane[v][0] + planes[t].gy * plane[v][1] + planes[t].c, has_height[v] = 1;
    }
    for (int k = 0; k < 3; ++k) {
      const auto i = tri[k], j = tri[(k + 1) % 3];
      const auto other = face_left_of(j, i);
      if (other == outer_face || done[other]) continue;
      // h_other = h_t + cross(p_j - p_i, x - p_i) = h_t + dx (y - y_i) - dy (x - x_i).
      const double dx = plane[j][0] - plane[i][0], dy = plane[j][1] - plane[i][1];
      planes[other] = {planes[t].gx - dy, planes[t].gy + dx, planes[t].c - dx * plane[i][1] + dy * plane[i][0]};
      done[other] = 1;
      queue.push_back(other);
    }
  }
  return height;
}

}  // namespace

std::vector<Vec3> convex_embedding(std::int32_t vertex_count, const std::vector<Triangle>& triangles,
                                   std::int32_t north, std::int32_t south) {
  if (north < 0 || south < 0 || north >= vertex_count || south >= vertex_count || north == south)
    throw std::invalid_argument("convex_embedding: poles " + std::to_string(north) + ", " + std::to_string(south) +
                                " must be two different vertices in [0, " + std::to_string(vertex_count) + ")");
  const VertexRings rings = build_vertex_rings(vertex_count, triangles);
  for (const auto w : rings.ring(north))
    if (w == south) throw std::invalid_argument("convex_embedding: the poles are joined by an edge");
  std::size_t outer_face = triangles.size();
  for (std::size_t t = 0; t < triangles.size() && outer_face == triangles.size(); ++t)
    for (const auto v : triangles[t])
      if (v == north) outer_face = t;
  const auto plane = tutte_embedding(rings, triangles[outer_face]);
  const auto height = lift(plane, triangles, outer_face);

  // Scale the heights to the plane's extent (a round polyhedron projects with even triangle sizes),
  // then project from the midpoint of the poles: on the segment between two vertices that share no face,
  // so strictly inside the polyhedron, and every face is seen from it positively oriented.
  double low = height[0], high = height[0];
  for (const double h : height) low = std::min(low, h), high = std::max(high, h);
  const double scale = high > low ? 1.5 / (high - low) : 1.0;
  auto point = [&](std::int32_t v) { return Vec3{plane[v][0], plane[v][1], scale * height[v]}; };
  const Vec3 centre = 0.5 * (point(north) + point(south));
  std::vector<Vec3> sphere(vertex_count);
  for (std::int32_t v = 0; v < vertex_count; ++v) sphere[v] = normalized(point(v) - centre);
  // Rotate north to +z (the rotation about the axis north x z); south is then -z up to rounding.
  const Vec3 axis_n = sphere[north];
  const Vec3 z{0, 0, 1};
  const Vec3 k = cross(axis_n, z);
  const double s = norm(k), c = dot(axis_n, z);
  if (s > 0) {
    const Vec3 u = (1 / s) * k;
    for (auto& p : sphere) {
      // Rodrigues: p cos + (u x p) sin + u (u·p)(1 - cos).
      p = normalized(c * p + s * cross(u, p) + ((1 - c) * dot(u, p)) * u);
    }
  } else if (c < 0) {
    for (auto& p : sphere) p = {p[0], -p[1], -p[2]};
  }
  sphere[north] = z;
  sphere[south] = {0, 0, -1};
  return sphere;
}

}  // namespace spheremap
