// The hemisphere panels' shading: a pixel whose samples all lie on one piece of surface is shaded once, at its centre
// (where the colours are smooth); every other pixel is the mean of its samples, coverage its alpha.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>

#include "../../src/render/panel_shading.hpp"
#include "spheremap/render/map_picture.hpp"
#include "spheremap/shapes/shapes.hpp"

namespace spheremap::render_detail {
namespace {

std::uint32_t round_half_up(double v) { return static_cast<std::uint32_t>(std::floor(v + 0.5)); }

struct Scene {
  Globe globe;
  std::vector<Vec3> screen;
  std::vector<double> light;
  IdBuffer buffer;
};

// An icosphere seen from +z, `side` pixels across at `ss` x `ss` samples, a property equal to z and the octants.
Scene sphere_scene(int side, int ss) {
  const Mesh sphere = make_icosphere(4);
  std::vector<Vec3> unit_sphere;
  for (const Vec3& p : sphere.positions) {
    const double n = std::sqrt(p[0] * p[0] + p[1] * p[1] + p[2] * p[2]);
    unit_sphere.push_back({p[0] / n, p[1] / n, p[2] / n});
  }
  SurfaceProperty x{{"x", "", ScaleKind::sequential, ValueRange{-1, 1}, {}}, "test", {}};
  for (const Vec3& p : unit_sphere) x.values.push_back(p[0]);
  std::vector<SurfaceProperty> properties = properties_from_attributes(sphere, unit_sphere);
  properties.push_back(x);
  Scene scene{make_globe(sphere, unit_sphere, properties, "icosphere"), {}, {}, {}};
  const double half = side * ss / 2.0;
  for (const Vec3& p : unit_sphere) {
    scene.screen.push_back({half + p[0] * half * 0.9, half - p[1] * half * 0.9, p[2]});
    scene.light.push_back(0.3 + 0.7 * std::max(0.0, p[2]));
  }
  scene.buffer = make_id_buffer(side * ss, side * ss);
  rasterize(scene.screen, scene.globe.triangles, scene.buffer);
  return scene;
}

// The samples' triangles of pixel (x, y), in sample order.
std::vector<std::int32_t> samples_of(const Scene& s, int x, int y, int ss) {
  std::vector<std::int32_t> hit;
  for (int sy = y * ss; sy < (y + 1) * ss; ++sy)
    for (int sx = x * ss; sx < (x + 1) * ss; ++sx)
      hit.push_back(s.buffer.triangle[static_cast<std::size_t>(sy) * s.buffer.width + sx]);
  return hit;
}

// The pixel's distinct triangles if it is shaded once: every sample covered, at most four triangles, each sharing a
// corner with the first and with smooth colours; else none.
std::vector<std::int32_t> shaded_once(const Scene& s, const SampleColours& colours, int x, int y, int ss) {
  const std::vector<std::int32_t> hit = samples_of(s, x, y, ss);
  std::vector<std::int32_t> distinct;
  for (const std::int32_t t : hit)
    if (std::find(distinct.begin(), distinct.end(), t) == distinct.end()) distinct.push_back(t);
  const auto meets_first = [&](std::int32_t t) {
    const Triangle &a = s.globe.triangles[distinct.front()], &b = s.globe.triangles[t];
    return std::find_first_of(a.begin(), a.end(), b.begin(), b.end()) != a.end();
  };
  const bool once = std::find(hit.begin(), hit.end(), -1) == hit.end() && distinct.size() <= 4 &&
                    std::all_of(distinct.begin(), distinct.end(), meets_first) &&
                    std::all_of(distinct.begin(), distinct.end(), [&](std::int32_t t) { return colours.smooth(t); });
  return once ? distinct : std::vector<std::int32_t>{};
}

// What shade_panel gives, written plainly: one shade at the centre, or every sample shaded.
std::uint32_t expected_pixel(const Scene& s, const SampleColours& colours, int x, int y, int ss) {
  const auto shaded = [&](std::int32_t t, double sx, double sy, std::array<double, 3>& rgb) {
    const Triangle& tri = s.globe.triangles[t];
    std::array<double, 3> w = ScreenTriangle(s.screen[tri[0]], s.screen[tri[1]], s.screen[tri[2]]).weights(sx, sy);
    for (double& wk : w) wk = std::max(wk, 0.0);
    const double total = w[0] + w[1] + w[2];
    for (double& wk : w) wk /= total;
    const double shade = w[0] * s.light[tri[0]] + w[1] * s.light[tri[1]] + w[2] * s.light[tri[2]];
    const Rgb8 c = colours(t, {static_cast<float>(w[0]), static_cast<float>(w[1]), static_cast<float>(w[2])});
    rgb = {c.r * shade, c.g * shade, c.b * shade};
  };
  std::array<double, 3> rgb{};
  if (const std::vector<std::int32_t> once = shaded_once(s, colours, x, y, ss); !once.empty()) {
    // In the triangle that holds the centre: the first of the pixel's that does (its weights there are >= 0), else
    // the one it is least outside.
    const double cx = x * ss + (ss - 1) / 2.0, cy = y * ss + (ss - 1) / 2.0;
    const auto least_weight = [&](std::int32_t t) {
      const Triangle& tri = s.globe.triangles[t];
      const auto w = ScreenTriangle(s.screen[tri[0]], s.screen[tri[1]], s.screen[tri[2]]).weights(cx, cy);
      return std::min({w[0], w[1], w[2]});
    };
    auto holder = std::find_if(once.begin(), once.end(), [&](std::int32_t t) { return least_weight(t) >= 0; });
    if (holder == once.end())
      holder = std::max_element(once.begin(), once.end(),
                                [&](std::int32_t a, std::int32_t b) { return least_weight(a) < least_weight(b); });
    shaded(*holder, cx, cy, rgb);
    return 0xff000000u | (round_half_up(rgb[0]) << 16) | (round_half_up(rgb[1]) << 8) | round_half_up(rgb[2]);
  }
  const std::vector<std::int32_t> hit = samples_of(s, x, y, ss);
  std::array<double, 3> sum{};
  int covered = 0;
  for (std::size_t k = 0; k < hit.size(); ++k) {
    if (hit[k] < 0) continue;
    shaded(hit[k], x * ss + static_cast<int>(k) % ss, y * ss + static_cast<int>(k) / ss, rgb);
    for (int c = 0; c < 3; ++c) sum[c] += rgb[c];
    ++covered;
  }
  if (covered == 0) return 0;
  const double n = ss * ss;
  return (round_half_up(covered / n * 255) << 24) | (round_half_up(sum[0] / n) << 16) |
         (round_half_up(sum[1] / n) << 8) | round_half_up(sum[2] / n);
}

// Supersampling 2 (the default, which shade_panel compiles apart) and 3.
class PanelShading : public testing::TestWithParam<int> {};

TEST_P(PanelShading, APixelOnOnePieceOfSurfaceIsShadedAtItsCentreAndAnEdgePixelPerSample) {
  constexpr int kSide = 90;
  const int ss = GetParam();
  const Scene s = sphere_scene(kSide, ss);
  const SurfaceProperty& x = *find_globe_property(s.globe, "x");
  const SurfaceProperty& octant = *find_globe_property(s.globe, "octant");
  const std::vector<SampleColours> colours{SampleColours(s.globe, x, *x.info.default_range),
                                           SampleColours(s.globe, octant, picture_range(octant, std::nullopt))};
  const std::vector<std::uint64_t> smooth = smooth_triangles(colours, s.globe.triangles.size());
  const auto pixels = shade_panel(s.buffer, kSide, kSide, ss, s.screen, s.globe.triangles, s.light, colours, smooth, 1);
  ASSERT_EQ(pixels.size(), 2u);
  EXPECT_EQ(pixels, shade_panel(s.buffer, kSide, kSide, ss, s.screen, s.globe.triangles, s.light, colours, smooth, 2));
  // Each figure alone gives what it gives beside the other.
  EXPECT_EQ(pixels[0], shade_panel(s.buffer, kSide, kSide, ss, s.screen, s.globe.triangles, s.light, {colours[0]},
                                   smooth_triangles({colours[0]}, s.globe.triangles.size()), 1)
                           .front());
  int once = 0, in_several = 0, per_sample = 0, octant_boundary = 0;
  for (int y = 0; y < kSide; ++y)
    for (int px = 0; px < kSide; ++px) {
      const std::size_t i = static_cast<std::size_t>(y) * kSide + px;
      for (std::size_t f = 0; f < 2; ++f)
        ASSERT_EQ(pixels[f][i], expected_pixel(s, colours[f], px, y, ss))
            << "figure " << f << " at " << px << ", " << y;
      const auto x_once = shaded_once(s, colours[0], px, y, ss), octant_once = shaded_once(s, colours[1], px, y, ss);
      once += !x_once.empty();
      in_several += x_once.size() > 1;
      per_sample += x_once.empty() && (pixels[0][i] >> 24) != 0;
      octant_boundary += !x_once.empty() && octant_once.empty();
    }
  // Not vacuous: both kinds of pixel, pixels over several triangles shaded once, and inner pixels on octant boundaries
  // (shaded per sample there).
  EXPECT_GT(once, 3000) << in_several << " " << per_sample << " " << octant_boundary;
  EXPECT_GT(in_several, 1500);
  EXPECT_GT(per_sample, 150);
  EXPECT_GT(octant_boundary, 20);
}

INSTANTIATE_TEST_SUITE_P(Supersampling, PanelShading, testing::Values(2, 3));

}  // namespace
}  // namespace spheremap::render_detail
