// The hemisphere pictures' rasterizer against the plain rule it implements: every sample centre of a triangle's box
// tested on its own.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <random>

#include "../../src/render/rasterizer.hpp"

namespace spheremap::render_detail {
namespace {

// rasterize without its shortcuts: each sample of the buffer tested against each facing triangle, its edge
// functions evaluated there (not stepped along the row).
IdBuffer rasterize_every_sample(const std::vector<Vec3>& screen, const std::vector<Triangle>& triangles, int width,
                                int height) {
  IdBuffer buffer = make_id_buffer(width, height);
  for (std::size_t t = 0; t < triangles.size(); ++t) {
    const FixedTriangle f(screen[triangles[t][0]], screen[triangles[t][1]], screen[triangles[t][2]]);
    const std::int64_t area = f.area();
    if (area >= 0) continue;
    for (int y = 0; y < height; ++y)
      for (int x = 0; x < width; ++x) {
        const std::int64_t px = FixedTriangle::centre(x), py = FixedTriangle::centre(y);
        const std::int64_t wa = f.edge(1, 2, px, py), wb = f.edge(2, 0, px, py), wc = f.edge(0, 1, px, py);
        if (wa > 0 || wb > 0 || wc > 0) continue;
        const float z = f.depth(wa, wb, wc, static_cast<double>(area));
        const std::size_t i = static_cast<std::size_t>(y) * width + x;
        if (z > buffer.depth[i]) {
          buffer.depth[i] = z;
          buffer.triangle[i] = static_cast<std::int32_t>(t);
        }
      }
  }
  return buffer;
}

TEST(Rasterizer, KeepsWhatTestingEverySampleKeeps) {
  // Small, large, thin and nearly horizontal or vertical triangles, corners on sample centres and edges, some
  // partly off the buffer: the rows' scans start left of each run and must miss none of it.
  std::mt19937 random(7);
  std::uniform_real_distribution<double> coordinate(-8, 72), offset(-3, 3), tiny(-1e-9, 1e-9), depth(-1, 1);
  std::vector<Vec3> screen;
  std::vector<Triangle> triangles;
  for (int k = 0; k < 3000; ++k) {
    const auto n = static_cast<std::int32_t>(screen.size());
    const double x = coordinate(random), y = coordinate(random);
    switch (k % 5) {
      case 0:  // anywhere, any size
        screen.push_back({x, y, depth(random)});
        screen.push_back({coordinate(random), coordinate(random), depth(random)});
        screen.push_back({coordinate(random), coordinate(random), depth(random)});
        break;
      case 1:  // small
        screen.push_back({x, y, depth(random)});
        screen.push_back({x + offset(random), y + offset(random), depth(random)});
        screen.push_back({x + offset(random), y + offset(random), depth(random)});
        break;
      case 2: {  // an edge nearly horizontal, long
        const double y2 = y + tiny(random);
        screen.push_back({x, y, depth(random)});
        screen.push_back({coordinate(random), y2, depth(random)});
        screen.push_back({coordinate(random), y + offset(random), depth(random)});
        break;
      }
      case 3: {  // corners on sample centres and boundaries
        const double cx = std::round(x) + 0.5, cy = std::round(y);
        screen.push_back({cx, cy, depth(random)});
        screen.push_back({cx + std::round(offset(random) * 4), cy + std::round(offset(random) * 4), depth(random)});
        screen.push_back(
            {cx + std::round(offset(random) * 4) + 0.5, cy + std::round(offset(random) * 4), depth(random)});
        break;
      }
      default: {  // thin sliver
        const double dx = offset(random) * 8, dy = offset(random) * 8;
        screen.push_back({x, y, depth(random)});
        screen.push_back({x + dx, y + dy, depth(random)});
        screen.push_back({x + dx / 2 + tiny(random) * 1e6, y + dy / 2 + tiny(random) * 1e6, depth(random)});
        break;
      }
    }
    // Either orientation: half face away and must be skipped by both.
    triangles.push_back(k % 2 == 0 ? Triangle{n, n + 1, n + 2} : Triangle{n, n + 2, n + 1});
  }
  constexpr int kWidth = 64, kHeight = 64;
  IdBuffer fast = make_id_buffer(kWidth, kHeight);
  rasterize(screen, triangles, fast);
  const IdBuffer plain = rasterize_every_sample(screen, triangles, kWidth, kHeight);
  EXPECT_EQ(fast.triangle, plain.triangle);
  EXPECT_EQ(fast.depth, plain.depth);
  // Not vacuous: most samples are covered, by many different triangles.
  const auto covered =
      std::count_if(plain.triangle.begin(), plain.triangle.end(), [](std::int32_t t) { return t >= 0; });
  EXPECT_GT(covered, kWidth * kHeight * 9 / 10);
}

TEST(Rasterizer, EachTriangleAloneKeepsItsSamples) {
  // One triangle at a time, so that no nearer triangle hides a sample a scan would have missed.
  std::mt19937 random(11);
  std::uniform_real_distribution<double> coordinate(-4, 36), offset(-6, 6), tiny(-1e-7, 1e-7);
  int compared = 0;
  for (int k = 0; k < 4000; ++k) {
    const double x = coordinate(random), y = coordinate(random);
    const double y1 = k % 3 == 0 ? y + tiny(random) : y + offset(random);
    const std::vector<Vec3> screen{{x, y, 0}, {x + offset(random), y1, 0}, {x + offset(random), y + offset(random), 0}};
    for (const Triangle& t : {Triangle{0, 1, 2}, Triangle{0, 2, 1}}) {
      IdBuffer fast = make_id_buffer(32, 32);
      rasterize(screen, {t}, fast);
      const IdBuffer plain = rasterize_every_sample(screen, {t}, 32, 32);
      ASSERT_EQ(fast.triangle, plain.triangle) << "triangle " << k;
      compared += std::count(plain.triangle.begin(), plain.triangle.end(), 0) > 0;
    }
  }
  EXPECT_GT(compared, 2000);
}

TEST(Rasterizer, TrianglesThatTileARegionLeaveNoSampleUncovered) {
  // A jittered grid over a rectangle whose sides are not on sample centres: every sample centre inside it lies in
  // some triangle, also those on (or within rounding of) a shared edge, because the snapped edges are exact.
  std::mt19937 random(5);
  std::uniform_real_distribution<double> jitter(-0.3, 0.3);
  constexpr int kCells = 23;
  constexpr double kLeft = 2.3, kTop = 1.7, kSide = 59.4;
  const double spacing = kSide / kCells;
  std::vector<Vec3> screen;
  for (int j = 0; j <= kCells; ++j)
    for (int i = 0; i <= kCells; ++i) {
      const bool border = i == 0 || j == 0 || i == kCells || j == kCells;
      Vec3 p{kLeft + (i + (border ? 0 : jitter(random))) * spacing,
             kTop + (j + (border ? 0 : jitter(random))) * spacing, 0};
      // Half the inner corners on sample centres or between two: many edges pass exactly through samples.
      if (!border && (i + j) % 2 == 0) p = {std::round(p[0] * 2) / 2, std::round(p[1] * 2) / 2, 0};
      screen.push_back(p);
    }
  std::vector<Triangle> triangles;
  const auto at = [](int i, int j) { return static_cast<std::int32_t>(j * (kCells + 1) + i); };
  for (int j = 0; j < kCells; ++j)
    for (int i = 0; i < kCells; ++i) {
      triangles.push_back({at(i, j), at(i + 1, j + 1), at(i + 1, j)});
      triangles.push_back({at(i, j), at(i, j + 1), at(i + 1, j + 1)});
    }
  for (const Triangle& t : triangles)
    ASSERT_LT(edge(screen[t[0]], screen[t[1]], screen[t[2]][0], screen[t[2]][1]), 0);  // all face the viewer
  IdBuffer buffer = make_id_buffer(64, 64);
  rasterize(screen, triangles, buffer);
  int inside = 0;
  for (int y = 0; y < 64; ++y)
    for (int x = 0; x < 64; ++x) {
      if (!(x + 0.5 > kLeft && x + 0.5 < kLeft + kSide && y + 0.5 > kTop && y + 0.5 < kTop + kSide)) continue;
      ++inside;
      EXPECT_GE(buffer.triangle[static_cast<std::size_t>(y) * 64 + x], 0) << x << ", " << y;
    }
  EXPECT_GT(inside, 3000);
}

}  // namespace
}  // namespace spheremap::render_detail
