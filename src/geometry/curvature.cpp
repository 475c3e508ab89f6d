// Rusinkiewicz's curvature tensors: per triangle from normal differences, per vertex by weighted averaging.
#include "spheremap/geometry/curvature.hpp"

#include <array>
#include <cmath>
#include <limits>

#include "spheremap/geometry/vec.hpp"

namespace spheremap {
namespace {

// A second fundamental form in a tangent frame (u, v): [[uu, uv], [uv, vv]].
struct Form {
  double uu = 0, uv = 0, vv = 0;
};

// The mixed Voronoi areas of the three corners of triangle abc (Meyer, Desbrun, Schröder & Barr 2003):
// the Voronoi regions of a non-obtuse triangle; half the area for an obtuse corner, a quarter for the others.
std::array<double, 3> corner_areas(const std::array<Vec3, 3>& p) {
  const double area = triangle_area(p[0], p[1], p[2]);
  std::array<double, 3> corner{};
  if (!(area > 0)) return corner;
  std::array<double, 3> cosine_sign{}, cot{};
  for (int i = 0; i < 3; ++i) {
    const Vec3 a = p[(i + 1) % 3] - p[i], b = p[(i + 2) % 3] - p[i];
    cosine_sign[i] = dot(a, b);
    cot[i] = dot(a, b) / norm(cross(a, b));
  }
  for (int i = 0; i < 3; ++i) {
    if (cosine_sign[i] < 0) {  // obtuse at corner i
      for (int j = 0; j < 3; ++j) corner[j] = j == i ? area / 2 : area / 4;
      return corner;
    }
  }
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    corner[i] = (squared_distance(p[i], p[j]) * cot[k] + squared_distance(p[i], p[k]) * cot[j]) / 8;
  }
  return corner;
}

// Turns the frame (u, v), perpendicular to the unit vector `from`, about from x to so that it becomes
// perpendicular to `to`: the smallest rotation taking `from` to `to`.
void rotate_frame(Vec3& u, Vec3& v, const Vec3& from, const Vec3& to) {
  const double c = dot(from, to);
  if (c <= -1 + 1e-12) {
    u = -1.0 * u, v = -1.0 * v;
    return;
  }
  const Vec3 axis = (1.0 / (1 + c)) * (from + to);
  u = u - dot(to, u) * axis;
  v = v - dot(to, v) * axis;
}

// The least-squares form in the triangle's frame (t, b) fitted to the normal changes along its edges.
Form triangle_form(const std::array<Vec3, 3>& p, const std::array<Vec3, 3>& n, const Vec3& t, const Vec3& b) {
  double m00 = 0, m01 = 0, m11 = 0, m12 = 0, m22 = 0;  // normal equations of [u v 0; 0 u v] x = [du dv]
  double r0 = 0, r1 = 0, r2 = 0;
  for (int i = 0; i < 3; ++i) {
    const int from = (i + 1) % 3, to = (i + 2) % 3;  // edge opposite corner i
    const Vec3 e = p[to] - p[from], dn = n[to] - n[from];
    const double u = dot(e, t), v = dot(e, b), du = dot(dn, t), dv = dot(dn, b);
    m00 += u * u, m01 += u * v, m11 += u * u + v * v, m12 += u * v, m22 += v * v;
    r0 += u * du, r1 += v * du + u * dv, r2 += v * dv;
  }
  // Solve [[m00, m01, 0], [m01, m11, m12], [0, m12, m22]] x = r by Cramer's rule.
  const double det = m00 * (m11 * m22 - m12 * m12) - m01 * (m01 * m22);
  if (!(std::abs(det) > 0)) return {};
  const double x0 = (r0 * (m11 * m22 - m12 * m12) - m01 * (r1 * m22 - m12 * r2)) / det;
  const double x1 = (m00 * (r1 * m22 - m12 * r2) - r0 * (m01 * m22)) / det;
  const double x2 = (m00 * (m11 * r2 - r1 * m12) - m01 * (m01 * r2) + r0 * (m01 * m12)) / det;
  return {x0, x1, x2};
}

// A vertex's tangent frame: an incident edge made perpendicular to the normal, and normal x that.
void vertex_frames(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles,
                   const std::vector<Vec3>& normals, std::vector<Vec3>& u, std::vector<Vec3>& v) {
  u.assign(positions.size(), Vec3{0, 0, 0});
  v.assign(positions.size(), Vec3{0, 0, 0});
  for (const auto& t : triangles)
    for (int c = 0; c < 3; ++c) {
      const auto vertex = static_cast<std::size_t>(t[c]);
      if (dot(u[vertex], u[vertex]) > 0) continue;
      const Vec3& n = normals[vertex];
      const Vec3 edge = positions[static_cast<std::size_t>(t[(c + 1) % 3])] - positions[vertex];
      u[vertex] = normalized(edge - dot(edge, n) * n);
      v[vertex] = cross(n, u[vertex]);
    }
}

// Unit vertex normals by Max's weights ("Weights for computing vertex normals from facet normals", J. Graphics
// Tools 4, 1999): each corner adds (a x b) / (|a|² |b|²) of its two edges, exact for vertices on a sphere. The
// area-weighted normals (geometry/normals.hpp) are off by an angle proportional to the edge length on
// irregular meshes, which the normal differences below would turn into a curvature error of several percent
// that does not shrink with refinement.
std::vector<Vec3> max_weighted_normals(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles) {
  std::vector<Vec3> normals(positions.size(), Vec3{0, 0, 0});
  for (const auto& t : triangles)
    for (int c = 0; c < 3; ++c) {
      const Vec3& p = positions[static_cast<std::size_t>(t[c])];
      const Vec3 a = positions[static_cast<std::size_t>(t[(c + 1) % 3])] - p;
      const Vec3 b = positions[static_cast<std::size_t>(t[(c + 2) % 3])] - p;
      const double weight = dot(a, a) * dot(b, b);
      if (!(weight > 0)) continue;
      normals[static_cast<std::size_t>(t[c])] = normals[static_cast<std::size_t>(t[c])] + (1 / weight) * cross(a, b);
    }
  for (auto& n : normals)
    if (dot(n, n) > 0) n = normalized(n);
  return normals;
}

}  // namespace

PrincipalCurvatures principal_curvatures(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles) {
  const std::vector<Vec3> normals = max_weighted_normals(positions, triangles);
  std::vector<Vec3> frame_u, frame_v;
  vertex_frames(positions, triangles, normals, frame_u, frame_v);
  std::vector<Form> sum(positions.size());
  std::vector<double> weight(positions.size(), 0.0);
  for (const auto& tri : triangles) {
    const std::array<Vec3, 3> p{positions[tri[0]], positions[tri[1]], positions[tri[2]]};
    const std::array<Vec3, 3> n{normals[tri[0]], normals[tri[1]], normals[tri[2]]};
    const Vec3 face_normal = normalized(cross(p[1] - p[0], p[2] - p[0]));
    const Vec3 t = normalized(p[2] - p[1]);
    if (dot(face_normal, face_normal) == 0 || dot(t, t) == 0) continue;  // degenerate triangle
    const Vec3 b = cross(face_normal, t);
    const Form form = triangle_form(p, n, t, b);
    const std::array<double, 3> area = corner_areas(p);
    for (int c = 0; c < 3; ++c) {
      const auto vertex = static_cast<std::size_t>(tri[c]);
      if (dot(normals[vertex], normals[vertex]) == 0) continue;
      Vec3 u = frame_u[vertex], v = frame_v[vertex];
      rotate_frame(u, v, normals[vertex], face_normal);
      const double u1 = dot(u, t), v1 = dot(u, b), u2 = dot(v, t), v2 = dot(v, b);
      Form& s = sum[vertex];
      s.uu += area[c] * (form.uu * u1 * u1 + 2 * form.uv * u1 * v1 + form.vv * v1 * v1);
      s.uv += area[c] * (form.uu * u1 * u2 + form.uv * (u1 * v2 + u2 * v1) + form.vv * v1 * v2);
      s.vv += area[c] * (form.uu * u2 * u2 + 2 * form.uv * u2 * v2 + form.vv * v2 * v2);
      weight[vertex] += area[c];
    }
  }
  PrincipalCurvatures result;
  result.k1.assign(positions.size(), std::numeric_limits<double>::quiet_NaN());
  result.k2 = result.k1;
  for (std::size_t vertex = 0; vertex < positions.size(); ++vertex) {
    if (!(weight[vertex] > 0)) continue;
    const Form& s = sum[vertex];
    const double uu = s.uu / weight[vertex], uv = s.uv / weight[vertex], vv = s.vv / weight[vertex];
    const double mean = (uu + vv) / 2, half_gap = std::hypot((uu - vv) / 2, uv);
    result.k1[vertex] = mean + half_gap;
    result.k2[vertex] = mean - half_gap;
  }
  return result;
}

}  // namespace spheremap
