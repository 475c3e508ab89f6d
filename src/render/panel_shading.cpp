// The shading of a hemisphere panel (see panel_shading.hpp).
#include "panel_shading.hpp"

#include <algorithm>
#include <array>
#include <limits>
#include <stdexcept>
#include <type_traits>

#include "../util/parallel.hpp"

namespace spheremap::render_detail {
namespace {

// std::lround of a finite v >= 0 that fits (v minus its integer part is exact), without lround's call.
std::uint32_t round_half_up(double v) {
  const auto whole = static_cast<std::uint32_t>(v);
  return v - whole >= 0.5 ? whole + 1 : whole;
}

// The triangles of a pixel's samples, when they are few and meet: every sample covered, at most four triangles, each
// sharing a corner with the first (pieces of one smooth surface, not an occluding fold).
struct PixelTriangles {
  std::array<std::int32_t, 4> triangle{};
  int count = 0;  // 0: the samples are not of one piece of surface
};

bool share_a_corner(const Triangle& a, const Triangle& b) {
  for (const std::int32_t u : a)
    if (u == b[0] || u == b[1] || u == b[2]) return true;
  return false;
}

// `Ss` is int, or std::integral_constant for the usual supersampling (its loops then unrolled).
template <typename Ss>
PixelTriangles pixel_triangles(const IdBuffer& buffer, const std::vector<Triangle>& triangles, int x, int y, Ss ss) {
  PixelTriangles p;
  const std::int32_t* first = buffer.triangle.data() + static_cast<std::size_t>(y) * ss * buffer.width + x * ss;
  for (int sy = 0; sy < ss; ++sy) {
    const std::int32_t* row = first + static_cast<std::size_t>(sy) * buffer.width;
    for (int sx = 0; sx < ss; ++sx) {
      const std::int32_t t = row[sx];
      if (t < 0) return {};
      bool seen = false;
      for (int k = 0; k < p.count; ++k) seen = seen || p.triangle[k] == t;
      if (seen) continue;
      if (p.count == 4 || (p.count > 0 && !share_a_corner(triangles[p.triangle[0]], triangles[t]))) return {};
      p.triangle[p.count++] = t;
    }
  }
  return p;
}

}  // namespace

std::vector<std::uint64_t> smooth_triangles(const std::vector<SampleColours>& colours, std::size_t triangles) {
  if (colours.size() > kMaxShadedFigures) throw std::invalid_argument("smooth_triangles: more than 64 colourings");
  std::vector<std::uint64_t> smooth(triangles, 0);
  for (std::size_t t = 0; t < triangles; ++t)
    for (std::size_t f = 0; f < colours.size(); ++f)
      if (colours[f].smooth(static_cast<std::int32_t>(t))) smooth[t] |= std::uint64_t{1} << f;
  return smooth;
}

std::vector<std::vector<std::uint32_t>> shade_panel(const IdBuffer& buffer, int width, int height, int supersampling,
                                                    const std::vector<Vec3>& screen,
                                                    const std::vector<Triangle>& triangles,
                                                    const std::vector<double>& light,
                                                    const std::vector<SampleColours>& colours,
                                                    const std::vector<std::uint64_t>& smooth, int threads) {
  if (colours.size() > kMaxShadedFigures) throw std::invalid_argument("shade_panel: more than 64 colourings");
  const int sw = buffer.width;
  const std::size_t figures = colours.size();
  const std::uint64_t every_figure = figures == 64 ? ~std::uint64_t{0} : (std::uint64_t{1} << figures) - 1;
  std::vector<std::vector<std::uint32_t>> pixels(figures,
                                                 std::vector<std::uint32_t>(static_cast<std::size_t>(width) * height));
  if (screen.empty() || figures == 0) return pixels;
  // The rows first..last; `ss_value` is the supersampling, as a compile-time constant for the usual one.
  const auto shade_rows = [&](auto ss_value, std::int64_t first, std::int64_t last) {
    const int ss = ss_value;
    std::vector<std::array<double, 3>> sums(figures);  // r, g, b of each figure's pixel
    // The triangle of the previous sample and what its samples share (most samples lie in their neighbour's).
    std::int32_t current = -1;
    ScreenTriangle corners(screen[0], screen[0], screen[0]);
    std::array<double, 3> corner_light{};
    const auto select = [&](std::int32_t t) {
      if (t == current) return;
      const Triangle& tri = triangles[t];
      corners = ScreenTriangle(screen[tri[0]], screen[tri[1]], screen[tri[2]]);
      corner_light = {light[tri[0]], light[tri[1]], light[tri[2]]};
      current = t;
    };
    // The weights of sample point (sx, sy) of the current triangle, clamped to it, and the light there.
    const auto weights_at = [&](double sx, double sy, std::array<float, 3>& weights) {
      std::array<double, 3> w = corners.weights(sx, sy);
      for (double& wk : w) wk = std::max(wk, 0.0);
      const double total = w[0] + w[1] + w[2];
      for (double& wk : w) wk = total > 0 ? wk / total : 1.0 / 3;
      weights = {static_cast<float>(w[0]), static_cast<float>(w[1]), static_cast<float>(w[2])};
      return w[0] * corner_light[0] + w[1] * corner_light[1] + w[2] * corner_light[2];
    };
    const double samples = static_cast<double>(ss) * ss;
    // The pixel centre in the sample coordinates of ScreenTriangle::weights (which adds half a sample).
    const double centre = (ss - 1) / 2.0;
    std::array<float, 3> weights{};
    for (auto y = static_cast<int>(first); y < last; ++y)
      for (int x = 0; x < width; ++x) {
        const std::size_t at = static_cast<std::size_t>(y) * width + x;
        // One piece of smooth surface under the pixel: shaded once, at the centre, in the triangle that holds it
        // (the first of the pixel's that does, else the one it is least outside), in each figure whose colours are
        // smooth on all of the pixel's triangles; per sample in the others.
        const PixelTriangles under = pixel_triangles(buffer, triangles, x, y, ss_value);
        std::uint64_t once = under.count > 0 ? every_figure : 0;
        for (int k = 0; k < under.count; ++k) once &= smooth[static_cast<std::size_t>(under.triangle[k])];
        if (once != 0) {
          const double cx = x * ss + centre, cy = y * ss + centre;
          std::int32_t holder = under.triangle[0];
          if (under.count > 1) {
            // Inside a facing triangle every edge function is <= 0 (its area is negative): no division needed.
            const double px = cx + 0.5, py = cy + 0.5;
            int k = 0;
            for (; k < under.count; ++k) {
              const Triangle& tri = triangles[under.triangle[k]];
              const Vec3 &a = screen[tri[0]], &b = screen[tri[1]], &c = screen[tri[2]];
              if (edge(b, c, px, py) <= 0 && edge(c, a, px, py) <= 0 && edge(a, b, px, py) <= 0) break;
            }
            if (k < under.count) {
              holder = under.triangle[k];
            } else {  // in none of them (in a sliver between the samples): the one it is least outside
              double best = -std::numeric_limits<double>::infinity();
              for (k = 0; k < under.count; ++k) {
                select(under.triangle[k]);
                const std::array<double, 3> w = corners.weights(cx, cy);
                if (const double least = std::min({w[0], w[1], w[2]}); least > best) best = least, holder = current;
              }
            }
          }
          select(holder);
          const double shade = weights_at(cx, cy, weights);
          for (std::size_t f = 0; f < figures; ++f) {
            if ((once >> f & 1) == 0) continue;
            const Rgb8 c = colours[f](holder, weights);
            const auto byte = [&](std::uint8_t v) { return round_half_up(std::min(v * shade, 255.0)); };
            pixels[f][at] = (0xffu << 24) | (byte(c.r) << 16) | (byte(c.g) << 8) | byte(c.b);
          }
          if (once == every_figure) continue;
        }
        std::fill(sums.begin(), sums.end(), std::array<double, 3>{0, 0, 0});
        double covered = 0;
        for (int sy = y * ss; sy < (y + 1) * ss; ++sy)
          for (int sx = x * ss; sx < (x + 1) * ss; ++sx) {
            const std::int32_t t = buffer.triangle[static_cast<std::size_t>(sy) * sw + sx];
            if (t < 0) continue;
            select(t);
            const double shade = weights_at(sx, sy, weights);
            for (std::size_t f = 0; f < figures; ++f) {
              if ((once >> f & 1) != 0) continue;
              const Rgb8 colour = colours[f](t, weights);
              sums[f][0] += colour.r * shade, sums[f][1] += colour.g * shade, sums[f][2] += colour.b * shade;
            }
            covered += 1;
          }
        if (covered == 0) continue;
        // Premultiplied ARGB: coverage is the alpha, so edges blend with the white page.
        const auto byte = [&](double v) { return round_half_up(std::clamp(v / samples, 0.0, 255.0)); };
        const auto alpha = round_half_up(covered / samples * 255);
        for (std::size_t f = 0; f < figures; ++f)
          if ((once >> f & 1) == 0)
            pixels[f][at] = (alpha << 24) | (byte(sums[f][0]) << 16) | (byte(sums[f][1]) << 8) | byte(sums[f][2]);
      }
  };
  detail::parallel_ranges(height, 8, detail::surface_threads(threads), [&](std::int64_t first, std::int64_t last) {
    if (supersampling == 2)
      shade_rows(std::integral_constant<int, 2>{}, first, last);
    else
      shade_rows(supersampling, first, last);
  });
  return pixels;
}

}  // namespace spheremap::render_detail
