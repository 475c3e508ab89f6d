// Private to src/render: a small software rasterizer for the hemisphere pictures. Triangles already in
// screen space (x right, y down, in samples; z larger = nearer) go into a depth buffer that keeps, per
// sample, the nearest triangle; shading happens afterwards, once per visible sample.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap::render_detail {

/// The nearest triangle at each sample (-1: background) and its depth.
struct IdBuffer {
  int width = 0, height = 0;
  std::vector<float> depth;
  std::vector<std::int32_t> triangle;
};

/// A buffer of width x height samples, all background.
IdBuffer make_id_buffer(int width, int height);

/// Draws every triangle of `triangles` (indices into `screen`) that faces the viewer (counter-clockwise on
/// screen as seen with y up, i.e. clockwise in y-down sample coordinates) into `buffer`, keeping the
/// nearest at each sample centre. Samples on an edge belong to both triangles, so no sample between two
/// triangles is missed; the nearer one, then the lower index, wins.
void rasterize(const std::vector<Vec3>& screen, const std::vector<Triangle>& triangles, IdBuffer& buffer);

/// Twice the signed area of (a, b, p) in y-down coordinates: positive when p is right of a -> b as seen on
/// screen with y up, i.e. for triangles that face the viewer, positive inside.
inline double edge(const Vec3& a, const Vec3& b, double px, double py) {
  return (b[0] - a[0]) * (py - a[1]) - (b[1] - a[1]) * (px - a[0]);
}

/// A screen triangle (a, b, c) with its area computed once, for the weights of its many samples.
struct ScreenTriangle {
  const Vec3* a;
  const Vec3* b;
  const Vec3* c;
  double area;  // edge(a, b, c)
  ScreenTriangle(const Vec3& a_, const Vec3& b_, const Vec3& c_)
      : a(&a_), b(&b_), c(&c_), area(edge(a_, b_, c_[0], c_[1])) {}
  /// The barycentric weights of the sample centre (x + 0.5, y + 0.5) (may be slightly outside [0, 1] on
  /// edges: clamp before use). Inline: the shading calls it for every sample.
  [[nodiscard]] std::array<double, 3> weights(double x, double y) const {
    const double px = x + 0.5, py = y + 0.5;
    if (area == 0) return {1.0 / 3, 1.0 / 3, 1.0 / 3};
    return {edge(*b, *c, px, py) / area, edge(*c, *a, px, py) / area, edge(*a, *b, px, py) / area};
  }
};

}  // namespace spheremap::render_detail
