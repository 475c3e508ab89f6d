// The depth-buffered triangle rasterizer of the hemisphere pictures (see rasterizer.hpp).
#include "rasterizer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

namespace spheremap::render_detail {

IdBuffer make_id_buffer(int width, int height) {
  IdBuffer buffer{width, height, {}, {}};
  const auto n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  buffer.depth.assign(n, -std::numeric_limits<float>::infinity());
  buffer.triangle.assign(n, -1);
  return buffer;
}

namespace {

// A sample column one left of the first sample centre (x + 0.5) of row py inside the edges of (a, b, c) that bound
// the row's run on the left (those whose edge() decreases along the row); at most x1 + 1.
int row_start(const Vec3& a, const Vec3& b, const Vec3& c, double py, int x1) {
  double left = -std::numeric_limits<double>::infinity();  // the largest crossing so far
  for (const auto& [p, q] : {std::pair{&a, &b}, {&b, &c}, {&c, &a}}) {
    // edge(p, q, px, py) = along - slope * (px - p.x), computed so: where slope > 0 it bounds the run on the left,
    // <= 0 (inside) from px = p.x + along / slope on (to within rounding, far less than a sample).
    const double slope = (*q)[1] - (*p)[1];
    if (!(slope > 0)) continue;
    const double along = ((*q)[0] - (*p)[0]) * (py - (*p)[1]);
    left = std::max(left, (*p)[0] + along / slope);
  }
  // Clamped to the box first: beyond it nothing is scanned, and the int conversion cannot overflow.
  left = std::clamp(left, -2.0, static_cast<double>(x1) + 2);
  return static_cast<int>(std::ceil(left - 0.5)) - 1;
}

}  // namespace

void rasterize(const std::vector<Vec3>& screen, const std::vector<Triangle>& triangles, IdBuffer& buffer) {
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Vec3& a = screen[triangles[t][0]];
    const Vec3& b = screen[triangles[t][1]];
    const Vec3& c = screen[triangles[t][2]];
    // In y-down coordinates a triangle facing the viewer turns clockwise: its edge() area is negative.
    const double area = edge(a, b, c[0], c[1]);
    if (!(area < 0)) continue;
    const int x0 = std::max(0, static_cast<int>(std::floor(std::min({a[0], b[0], c[0]}) - 0.5)));
    const int x1 = std::min(buffer.width - 1, static_cast<int>(std::ceil(std::max({a[0], b[0], c[0]}) - 0.5)));
    const int y0 = std::max(0, static_cast<int>(std::floor(std::min({a[1], b[1], c[1]}) - 0.5)));
    const int y1 = std::min(buffer.height - 1, static_cast<int>(std::ceil(std::max({a[1], b[1], c[1]}) - 0.5)));
    for (int y = y0; y <= y1; ++y) {
      const double py = y + 0.5;
      // Along a row each edge() is monotonic in px as computed (each rounded step is), so the samples found
      // inside are one run: the first outside sample after it ends the row, and the scan may start anywhere
      // left of the run. It starts one sample left of where the edges that bound the run on the left cross the row
      // (the crossing is off by far less than a sample), so that the samples before are not tested one by one.
      bool inside_before = false;
      const int start = std::max(x0, row_start(a, b, c, py, x1));
      for (int x = start; x <= x1; ++x) {
        const double px = x + 0.5;
        const double wa = edge(b, c, px, py), wb = edge(c, a, px, py), wc = edge(a, b, px, py);
        if (wa > 0 || wb > 0 || wc > 0) {  // outside (the area is negative: inside is <= 0)
          if (inside_before) break;
          continue;
        }
        inside_before = true;
        const auto z = static_cast<float>((wa * a[2] + wb * b[2] + wc * c[2]) / area);
        const std::size_t i = static_cast<std::size_t>(y) * buffer.width + x;
        if (z > buffer.depth[i]) {
          buffer.depth[i] = z;
          buffer.triangle[i] = static_cast<std::int32_t>(t);
        }
      }
    }
  }
}

}  // namespace spheremap::render_detail
