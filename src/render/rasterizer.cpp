// The depth-buffered triangle rasterizer of the hemisphere pictures (see rasterizer.hpp).
#include "rasterizer.hpp"

#include <algorithm>
#include <cmath>
#include <limits>

namespace spheremap::render_detail {

IdBuffer make_id_buffer(int width, int height) {
  IdBuffer buffer{width, height, {}, {}};
  const auto n = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  buffer.depth.assign(n, -std::numeric_limits<float>::infinity());
  buffer.triangle.assign(n, -1);
  return buffer;
}

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
      // inside are one run: the first outside sample after it ends the row.
      bool inside_before = false;
      for (int x = x0; x <= x1; ++x) {
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
