// The figure of a map: the coloured map, clipped to the projection's outline, under a graticule, with
// title, labels, residue outlines and the colour key (see map_picture.hpp).
#include <algorithm>
#include <cmath>
#include <stdexcept>

#include <fmt/format.h>

#include "canvas.hpp"
#include "sample_colours.hpp"
#include "spheremap/error.hpp"
#include "spheremap/render/map_picture.hpp"

namespace spheremap {
namespace {

using render_detail::Align;

// Where the pieces of a map figure go, in pixels from the top-left corner.
struct MapLayout {
  double margin, title_size, font_size;
  double map_x, map_y;  // the map image's top-left corner
  int map_width, map_height;
  double key_y, key_height;
};

MapLayout lay_out(int width, int height) {
  MapLayout l{};
  l.margin = 0.02 * height;
  l.title_size = std::max(12.0, 0.034 * height);
  l.font_size = std::max(9.0, 0.021 * height);
  l.key_height = 5.2 * l.font_size;
  const double top = l.margin + 2.0 * l.title_size + 0.6 * l.font_size;
  const double label_space = 4.5 * l.font_size;  // latitude labels left and right
  const double available_height = height - top - l.key_height - l.margin - 2.2 * l.font_size;
  const double available_width = width - 2 * (l.margin + label_space);
  l.map_height = std::max(1, static_cast<int>(std::floor(std::min(available_height, available_width / 2))));
  l.map_width = 2 * l.map_height;
  l.map_x = std::round((width - l.map_width) / 2.0);
  l.map_y = std::round(top);
  l.key_y = l.map_y + l.map_height + 2.0 * l.font_size;
  return l;
}

// The figure point of a globe point.
struct ToFigure {
  MapLayout layout;
  PlanePoint half;
  Projection projection;
  [[nodiscard]] std::array<double, 2> operator()(double latitude_degrees, double longitude_degrees) const {
    const PlanePoint p = project(projection, {latitude_degrees * kDegree, longitude_degrees * kDegree});
    return {layout.map_x + (p.x / half.x + 1) / 2 * layout.map_width,
            layout.map_y + (1 - p.y / half.y) / 2 * layout.map_height};
  }
};

// The map's outline: the meridian at +180° from south to north, then the one at -180° back.
void outline_path(cairo_t* cr, const ToFigure& to) {
  cairo_new_path(cr);
  for (int k = 0; k <= 720; ++k) {
    const auto [x, y] = to(-90 + k * 0.25, 180);
    k == 0 ? cairo_move_to(cr, x, y) : cairo_line_to(cr, x, y);
  }
  for (int k = 0; k <= 720; ++k) {
    const auto [x, y] = to(90 - k * 0.25, -180);
    cairo_line_to(cr, x, y);
  }
  cairo_close_path(cr);
}

// Pixel colours of the map, transparent off the map; pixels just off it take a neighbour's colour so that
// the antialiased outline blends map colour, not background.
std::vector<std::uint32_t> map_pixels(const Globe& globe, const SurfaceProperty& property, const MapSamples& s,
                                      const ValueRange& range) {
  std::vector<std::uint32_t> pixels(s.triangle.size(), 0);
  const render_detail::SampleColours colour(globe, property, range);
  for (std::size_t i = 0; i < pixels.size(); ++i)
    if (s.triangle[i] >= 0) pixels[i] = render_detail::opaque(colour(s.triangle[i], s.weights[i]));
  std::vector<std::uint32_t> grown = pixels;
  for (int y = 0; y < s.height; ++y)
    for (int x = 0; x < s.width; ++x) {
      const std::size_t i = static_cast<std::size_t>(y) * s.width + x;
      if (pixels[i] != 0) continue;
      for (const auto& [dx, dy] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}}) {
        const int nx = x + dx, ny = y + dy;
        if (nx < 0 || ny < 0 || nx >= s.width || ny >= s.height) continue;
        const std::uint32_t c = pixels[static_cast<std::size_t>(ny) * s.width + nx];
        if (c != 0) {
          grown[i] = c;
          break;
        }
      }
    }
  return grown;
}

void draw_graticule(cairo_t* cr, const ToFigure& to, double line_width) {
  cairo_set_line_width(cr, line_width);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_BUTT);
  for (int latitude = -60; latitude <= 60; latitude += 30) {
    cairo_new_path(cr);
    for (int k = 0; k <= 360; ++k) {
      const auto [x, y] = to(latitude, -180 + k);
      k == 0 ? cairo_move_to(cr, x, y) : cairo_line_to(cr, x, y);
    }
    cairo_set_source_rgba(cr, 0, 0, 0, latitude == 0 ? 0.55 : 0.35);
    cairo_stroke(cr);
  }
  for (int longitude = -150; longitude <= 150; longitude += 30) {
    cairo_new_path(cr);
    for (int k = 0; k <= 360; ++k) {
      const auto [x, y] = to(-90 + k * 0.5, longitude);
      k == 0 ? cairo_move_to(cr, x, y) : cairo_line_to(cr, x, y);
    }
    cairo_set_source_rgba(cr, 0, 0, 0, longitude == 0 ? 0.55 : 0.35);
    cairo_stroke(cr);
  }
}

std::string latitude_label(int degrees) {
  return degrees == 0 ? "0°" : fmt::format("{}°{}", std::abs(degrees), degrees > 0 ? "N" : "S");
}

std::string longitude_label(int degrees) {
  return degrees == 0 || std::abs(degrees) == 180 ? fmt::format("{}°", std::abs(degrees))
                                                  : fmt::format("{}°{}", std::abs(degrees), degrees > 0 ? "E" : "W");
}

void draw_graticule_labels(cairo_t* cr, const ToFigure& to, const MapLayout& l) {
  render_detail::set_font(cr, l.font_size * 0.9);
  const Rgb8 ink{70, 70, 70};
  for (int latitude = -60; latitude <= 60; latitude += 30) {
    const auto [x, y] = to(latitude, -180);
    const auto [x_right, y_right] = to(latitude, 180);
    render_detail::draw_text(cr, x - 0.5 * l.font_size, y + 0.35 * l.font_size, latitude_label(latitude), Align::right,
                             ink);
    render_detail::draw_text(cr, x_right + 0.5 * l.font_size, y_right + 0.35 * l.font_size, latitude_label(latitude),
                             Align::left, ink);
  }
  // Longitudes under the map, where each meridian crosses the equator.
  for (int longitude = -180; longitude <= 180; longitude += 30) {
    const auto [x, y] = to(0, longitude);
    render_detail::draw_text(cr, x, l.map_y + l.map_height + 1.25 * l.font_size, longitude_label(longitude),
                             Align::centre, ink);
  }
}

// The boundary of the outlined residues: the 0.5 contour (marching squares over pixel centres) of the
// field that is 1 on their vertices and 0 elsewhere, interpolated as the values are.
void draw_outline(cairo_t* cr, const Globe& globe, const MapSamples& s, const std::vector<std::int32_t>& residues,
                  const MapLayout& l) {
  std::vector<char> selected_residue(globe.residues.size(), 0);
  for (const std::int32_t r : residues) selected_residue[r] = 1;
  std::vector<float> field(s.triangle.size(), -1);
  for (std::size_t i = 0; i < field.size(); ++i) {
    if (s.triangle[i] < 0) continue;
    const Triangle& t = globe.triangles[s.triangle[i]];
    float f = 0;
    for (int k = 0; k < 3; ++k) {
      const std::int32_t r = globe.vertex_residue[t[k]];
      if (r >= 0 && selected_residue[r]) f += s.weights[i][k];
    }
    field[i] = f;
  }
  cairo_new_path(cr);
  const auto at = [&](int x, int y) { return field[static_cast<std::size_t>(y) * s.width + x]; };
  const auto point = [&](double x, double y) { return std::array<double, 2>{l.map_x + x + 0.5, l.map_y + y + 0.5}; };
  for (int y = 0; y + 1 < s.height; ++y)
    for (int x = 0; x + 1 < s.width; ++x) {
      const std::array<float, 4> c{at(x, y), at(x + 1, y), at(x + 1, y + 1), at(x, y + 1)};
      if (std::min({c[0], c[1], c[2], c[3]}) < 0) continue;  // off the map
      // Crossings of the four cell edges, in order top, right, bottom, left.
      std::vector<std::array<double, 2>> crossings;
      const std::array<std::array<int, 2>, 4> corner{{{0, 0}, {1, 0}, {1, 1}, {0, 1}}};
      for (int e = 0; e < 4; ++e) {
        const float a = c[e], b = c[(e + 1) % 4];
        if ((a >= 0.5f) == (b >= 0.5f)) continue;
        const double t = (0.5 - a) / (b - a);
        const auto& p = corner[e];
        const auto& q = corner[(e + 1) % 4];
        crossings.push_back(point(x + p[0] + t * (q[0] - p[0]), y + p[1] + t * (q[1] - p[1])));
      }
      for (std::size_t k = 0; k + 1 < crossings.size(); k += 2) {
        cairo_move_to(cr, crossings[k][0], crossings[k][1]);
        cairo_line_to(cr, crossings[k + 1][0], crossings[k + 1][1]);
      }
    }
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
  const double width = std::max(1.5, l.font_size * 0.12);
  cairo_set_source_rgba(cr, 1, 1, 1, 0.9);
  cairo_set_line_width(cr, 2.2 * width);
  cairo_stroke_preserve(cr);
  cairo_set_source_rgb(cr, 0, 0, 0);
  cairo_set_line_width(cr, width);
  cairo_stroke(cr);
}

std::string projection_title(Projection projection) {
  switch (projection) {
    case Projection::mollweide: return "Mollweide projection";
    case Projection::equirectangular: return "equirectangular projection";
    case Projection::sinusoidal: return "sinusoidal projection";
  }
  return "";
}

void draw_titles(cairo_t* cr, const Globe& globe, const SurfaceProperty& property, Projection projection,
                 const MapFigureOptions& options, const MapLayout& l) {
  render_detail::set_font(cr, l.title_size, true);
  const std::string title = fmt::format("{} · {} · {}", globe.name, property.info.name, projection_title(projection));
  render_detail::draw_text(cr, options.width / 2.0, l.margin + l.title_size, title, Align::centre);
  render_detail::set_font(cr, l.font_size * 0.85);
  std::string caption = "latitude and longitude of the globe superposed on the structure (north = +z)";
  if (!options.outline.empty()) caption += " · outlined: " + options.outline_label;
  render_detail::draw_text(cr, options.width / 2.0, l.margin + 1.5 * l.title_size + 0.45 * l.font_size, caption,
                           Align::centre, {90, 90, 90});
}

}  // namespace

std::array<int, 2> map_image_size(const MapFigureOptions& options) {
  if (options.width < 400 || options.height < 200 || options.width > 16384 || options.height > 16384)
    throw InputError(fmt::format("--size {}x{}: a map figure must be between 400x200 and 16384x16384 pixels",
                                 options.width, options.height));
  const MapLayout l = lay_out(options.width, options.height);
  return {l.map_width, l.map_height};
}

std::array<int, 2> map_image_origin(const MapFigureOptions& options) {
  map_image_size(options);
  const MapLayout l = lay_out(options.width, options.height);
  return {static_cast<int>(l.map_x), static_cast<int>(l.map_y)};
}

std::string map_figure(const Globe& globe, const SurfaceProperty& property, const MapSamples& samples,
                       const MapFigureOptions& options) {
  const auto size = map_image_size(options);
  if (samples.width != size[0] || samples.height != size[1])
    throw std::invalid_argument("map_figure: the samples are not of the map's size");
  const MapLayout l = lay_out(options.width, options.height);
  const ValueRange range = picture_range(property, options.range);
  const ToFigure to{l, projection_half_extent(samples.projection), samples.projection};
  render_detail::Canvas canvas(options.format, options.width, options.height);
  cairo_t* cr = canvas.cr();
  std::vector<std::uint32_t> pixels = map_pixels(globe, property, samples, range);
  cairo_surface_t* image = render_detail::image_surface(pixels, samples.width, samples.height);
  cairo_save(cr);
  outline_path(cr, to);
  cairo_clip(cr);
  cairo_set_source_surface(cr, image, l.map_x, l.map_y);
  cairo_pattern_set_filter(cairo_get_source(cr), CAIRO_FILTER_NEAREST);
  cairo_paint(cr);
  cairo_restore(cr);
  cairo_surface_destroy(image);
  draw_graticule(cr, to, std::max(0.8, l.font_size * 0.05));
  if (!options.outline.empty()) draw_outline(cr, globe, samples, options.outline, l);
  outline_path(cr, to);
  cairo_set_source_rgb(cr, 0.25, 0.25, 0.25);
  cairo_set_line_width(cr, std::max(1.0, l.font_size * 0.08));
  cairo_stroke(cr);
  draw_graticule_labels(cr, to, l);
  draw_titles(cr, globe, property, samples.projection, options, l);
  render_detail::draw_colour_key(cr, render_detail::colour_key(property, range), l.margin, l.key_y,
                                 options.width - 2 * l.margin, l.key_height, l.font_size);
  return canvas.finish();
}

}  // namespace spheremap
