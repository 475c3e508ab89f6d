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

namespace {

// floor(a / 2^kBits) and ceil(a / 2^kBits) of a fixed-point value (arithmetic shifts round down).
std::int64_t floor_samples(std::int64_t a) { return a >> FixedTriangle::kBits; }
std::int64_t ceil_samples(std::int64_t a) { return -((-a) >> FixedTriangle::kBits); }

}  // namespace

void rasterize(const std::vector<Vec3>& screen, const std::vector<Triangle>& triangles, IdBuffer& buffer) {
  constexpr double kFar = 1 << 20;  // samples: products of fixed-point differences stay far inside 64 bits
  constexpr std::int64_t kStep = FixedTriangle::kOne;
  // Each corner snapped once (about six triangles share it); those too far off are left out with their triangles.
  std::vector<std::array<std::int64_t, 2>> fixed(screen.size());
  std::vector<std::uint8_t> near(screen.size());
  for (std::size_t v = 0; v < screen.size(); ++v) {
    near[v] = std::abs(screen[v][0]) < kFar && std::abs(screen[v][1]) < kFar;  // false for NaN
    if (near[v] != 0) fixed[v] = {FixedTriangle::snap(screen[v][0]), FixedTriangle::snap(screen[v][1])};
  }
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const Triangle& tri = triangles[t];
    if (near[tri[0]] == 0 || near[tri[1]] == 0 || near[tri[2]] == 0) continue;
    const FixedTriangle f(fixed[tri[0]], fixed[tri[1]], fixed[tri[2]],
                          {screen[tri[0]][2], screen[tri[1]][2], screen[tri[2]][2]});
    // In y-down coordinates a triangle facing the viewer turns clockwise: its edge() area is negative.
    const std::int64_t area = f.area();
    if (area >= 0) continue;
    // The samples whose centres (i * kStep + kStep / 2) lie within the corners' extent.
    const std::int64_t x0 = std::max<std::int64_t>(0, ceil_samples(std::min({f.x[0], f.x[1], f.x[2]}) - kStep / 2));
    const std::int64_t x1 =
        std::min<std::int64_t>(buffer.width - 1, floor_samples(std::max({f.x[0], f.x[1], f.x[2]}) - kStep / 2));
    const std::int64_t y0 = std::max<std::int64_t>(0, ceil_samples(std::min({f.y[0], f.y[1], f.y[2]}) - kStep / 2));
    const std::int64_t y1 =
        std::min<std::int64_t>(buffer.height - 1, floor_samples(std::max({f.y[0], f.y[1], f.y[2]}) - kStep / 2));
    if (x0 > x1 || y0 > y1) continue;
    // Each edge function changes by a constant per sample along a row and per row down a column: exact in
    // integers, so adding it gives what evaluating it at each sample gives.
    const std::int64_t right_a = -(f.y[2] - f.y[1]) * kStep, right_b = -(f.y[0] - f.y[2]) * kStep,
                       right_c = -(f.y[1] - f.y[0]) * kStep;
    const std::int64_t down_a = (f.x[2] - f.x[1]) * kStep, down_b = (f.x[0] - f.x[2]) * kStep,
                       down_c = (f.x[1] - f.x[0]) * kStep;
    const std::int64_t px0 = FixedTriangle::centre(x0), py0 = FixedTriangle::centre(y0);
    std::int64_t row_a = f.edge(1, 2, px0, py0), row_b = f.edge(2, 0, px0, py0), row_c = f.edge(0, 1, px0, py0);
    const auto area_d = static_cast<double>(area);
    for (std::int64_t y = y0; y <= y1; ++y, row_a += down_a, row_b += down_b, row_c += down_c) {
      std::int64_t wa = row_a, wb = row_b, wc = row_c;
      // Along a row each edge function is linear, so the samples found inside are one run: the first
      // outside sample after it ends the row.
      bool inside_before = false;
      const std::size_t row = static_cast<std::size_t>(y) * buffer.width;
      for (std::int64_t x = x0; x <= x1; ++x, wa += right_a, wb += right_b, wc += right_c) {
        if (wa > 0 || wb > 0 || wc > 0) {  // outside (the area is negative: inside is <= 0)
          if (inside_before) break;
          continue;
        }
        inside_before = true;
        const float z = f.depth(wa, wb, wc, area_d);
        const std::size_t i = row + static_cast<std::size_t>(x);
        if (z > buffer.depth[i]) {
          buffer.depth[i] = z;
          buffer.triangle[i] = static_cast<std::int32_t>(t);
        }
      }
    }
  }
}

}  // namespace spheremap::render_detail
