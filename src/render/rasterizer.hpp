// Private to src/render: a small software rasterizer for the hemisphere pictures. Triangles already in
// screen space (x right, y down, in samples; z larger = nearer) go into a depth buffer that keeps, per
// sample, the nearest triangle; shading happens afterwards, once per visible sample.
#pragma once

#include <array>
#include <cmath>
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
/// nearest at each sample centre. The corners are snapped to 1/256 of a sample (FixedTriangle) and the samples
/// tested exactly, in integers: a sample on an edge belongs to both triangles, so no sample between two
/// triangles is missed; the nearer one, then the lower index, wins. Triangles with a corner farther than 2^20
/// samples from the origin are skipped (the pictures' are inside their panel).
void rasterize(const std::vector<Vec3>& screen, const std::vector<Triangle>& triangles, IdBuffer& buffer);

/// A screen triangle snapped to fixed point (1/256 sample), its edge functions exact in 64-bit integers.
struct FixedTriangle {
  static constexpr int kBits = 8;  // fractional bits of a coordinate
  static constexpr std::int64_t kOne = std::int64_t{1} << kBits;
  std::array<std::int64_t, 3> x, y;  // corners a, b, c
  std::array<double, 3> z;
  /// Preconditions: every coordinate is finite and within 2^20 samples of the origin.
  FixedTriangle(const Vec3& a, const Vec3& b, const Vec3& c)
      : x{snap(a[0]), snap(b[0]), snap(c[0])}, y{snap(a[1]), snap(b[1]), snap(c[1])}, z{a[2], b[2], c[2]} {}
  /// Corners snapped already (x, y of snap()) with their depths.
  FixedTriangle(const std::array<std::int64_t, 2>& a, const std::array<std::int64_t, 2>& b,
                const std::array<std::int64_t, 2>& c, const std::array<double, 3>& depths)
      : x{a[0], b[0], c[0]}, y{a[1], b[1], c[1]}, z(depths) {}
  /// The nearest fixed-point value (ties to even); llrint, which compilers inline.
  static std::int64_t snap(double v) { return static_cast<std::int64_t>(std::llrint(v * kOne)); }
  /// The fixed-point coordinate of sample centre i + 0.5.
  static std::int64_t centre(std::int64_t i) { return i * kOne + kOne / 2; }
  /// Twice the signed area of (corner i, corner j, p) as edge() computes it; exact.
  [[nodiscard]] std::int64_t edge(int i, int j, std::int64_t px, std::int64_t py) const {
    return (x[j] - x[i]) * (py - y[i]) - (y[j] - y[i]) * (px - x[i]);
  }
  /// edge(a, b, c): negative for a triangle that faces the viewer.
  [[nodiscard]] std::int64_t area() const { return edge(0, 1, x[2], y[2]); }
  /// The depth at fixed-point p from the edge functions of a, b, c there (wa = edge(1, 2, p), ...).
  [[nodiscard]] float depth(std::int64_t wa, std::int64_t wb, std::int64_t wc, double area) const {
    return static_cast<float>(
        (static_cast<double>(wa) * z[0] + static_cast<double>(wb) * z[1] + static_cast<double>(wc) * z[2]) / area);
  }
};

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
