// The hemisphere pictures (see hemispheres.hpp): four panels drawn by the software rasterizer, supersampled,
// shaded with Lambert's law and a little ambient light, laid out with cairo.
#include "spheremap/render/hemispheres.hpp"

#include <Eigen/Dense>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include <fmt/format.h>

#include "../util/parallel.hpp"
#include "canvas.hpp"
#include "panel_shading.hpp"
#include "rasterizer.hpp"
#include "spheremap/error.hpp"
#include "spheremap/render/map_picture.hpp"

namespace spheremap {
namespace {

using render_detail::Align;

constexpr double kAmbient = 0.34;  // the light every visible point gets
constexpr double kDiffuse = 0.66;  // times cos(angle to the light)

Vec3 sub(const Vec3& a, const Vec3& b) { return {a[0] - b[0], a[1] - b[1], a[2] - b[2]}; }
Vec3 cross(const Vec3& a, const Vec3& b) {
  return {a[1] * b[2] - a[2] * b[1], a[2] * b[0] - a[0] * b[2], a[0] * b[1] - a[1] * b[0]};
}
double dot(const Vec3& a, const Vec3& b) { return a[0] * b[0] + a[1] * b[1] + a[2] * b[2]; }
Vec3 unit(const Vec3& v) {
  const double n = std::sqrt(dot(v, v));
  return n > 0 ? Vec3{v[0] / n, v[1] / n, v[2] / n} : Vec3{0, 0, 1};
}

// A camera: rows right, up, towards the viewer.
struct View {
  Vec3 right, up, towards;
  [[nodiscard]] Vec3 operator()(const Vec3& v) const { return {dot(right, v), dot(up, v), dot(towards, v)}; }
};

View front_view(const HemisphereViews& views) {
  const auto& f = views.front;
  return {{f[0], f[1], f[2]}, {f[3], f[4], f[5]}, {f[6], f[7], f[8]}};
}

View back_view(const HemisphereViews& views) {
  const View f = front_view(views);
  return {{-f.right[0], -f.right[1], -f.right[2]}, f.up, {-f.towards[0], -f.towards[1], -f.towards[2]}};
}

// Area-weighted vertex normals of a mesh (outward for counter-clockwise triangles).
std::vector<Vec3> vertex_normals(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles) {
  std::vector<Vec3> normals(positions.size(), Vec3{0, 0, 0});
  for (const Triangle& t : triangles) {
    const Vec3 n = cross(sub(positions[t[1]], positions[t[0]]), sub(positions[t[2]], positions[t[0]]));
    for (const std::int32_t v : t)
      for (int k = 0; k < 3; ++k) normals[v][k] += n[k];
  }
  for (Vec3& n : normals) n = unit(n);
  return normals;
}

struct PanelRect {
  double x, y, width, height;
  std::string label;
};

// What one figure colours its panels by.
struct Colouring {
  const SurfaceProperty* property;
  ValueRange range;
};

// Colourings shaded together (at most render_detail::kMaxShadedFigures) and which triangles are smooth in each.
struct ShadingBatch {
  std::vector<render_detail::SampleColours> colours;
  std::vector<std::uint64_t> smooth;
};

// One panel of each figure: the mesh (positions around `centre`, scaled by `scale` pixels per unit) seen through
// `view`, rasterized once and shaded once per colouring (the geometry of a sample does not depend on the
// property), as ARGB pixels (transparent background), one image per colouring.
std::vector<std::vector<std::uint32_t>> render_panel(const Globe& globe, const std::vector<ShadingBatch>& batches,
                                                     const std::vector<Vec3>& positions,
                                                     const std::vector<Vec3>& normals, const Vec3& centre,
                                                     const View& view, double scale, int width, int height,
                                                     int supersampling, int threads) {
  const int ss = supersampling;
  const int sw = width * ss, sh = height * ss;
  std::vector<Vec3> screen;
  screen.reserve(positions.size());
  for (const Vec3& p : positions) {
    const Vec3 c = view(sub(p, centre));
    screen.push_back({sw / 2.0 + c[0] * scale * ss, sh / 2.0 - c[1] * scale * ss, c[2]});
  }
  render_detail::IdBuffer buffer = render_detail::make_id_buffer(sw, sh);
  render_detail::rasterize(screen, globe.triangles, buffer);
  // The light comes from the viewer's upper left; Lambert's law at each vertex, interpolated over the
  // triangles (Gouraud): the vertex normals of a smooth surface vary little across a triangle.
  const Vec3 light_direction = unit({-0.45, 0.55, 1.0});
  std::vector<double> light(positions.size());
  for (std::size_t v = 0; v < positions.size(); ++v)
    light[v] = kAmbient + kDiffuse * std::max(0.0, dot(view(normals[v]), light_direction));
  std::vector<std::vector<std::uint32_t>> pixels;
  for (const ShadingBatch& batch : batches)
    for (auto& figure : render_detail::shade_panel(buffer, width, height, supersampling, screen, globe.triangles, light,
                                                   batch.colours, batch.smooth, threads))
      pixels.push_back(std::move(figure));
  return pixels;
}

// Where the top of the trace seen through `view` lies in the figure (y, pixels), tubes included.
double trace_top(const std::vector<TracePath>& trace, const Vec3& centre, const View& view, double scale,
                 const PanelRect& panel) {
  double top = panel.y + panel.height / 2;
  for (const TracePath& path : trace)
    for (const Vec3& p : path.points) top = std::min(top, panel.y + panel.height / 2 - view(sub(p, centre))[1] * scale);
  return top - std::max(2.0, panel.width / 75) * 1.45 / 2;
}

// The trace seen through `view`, as tubes: segments far to near, each a dark line under a coloured one.
void draw_trace(cairo_t* cr, const std::vector<TracePath>& trace, const SurfaceProperty& property,
                const ValueRange& range, const Vec3& centre, const View& view, double scale, const PanelRect& panel) {
  struct Segment {
    double depth;
    std::array<double, 4> ends;
    Rgb8 colour;
  };
  std::vector<Segment> segments;
  const double cx = panel.x + panel.width / 2, cy = panel.y + panel.height / 2;
  for (const TracePath& path : trace)
    for (std::size_t k = 0; k + 1 < path.points.size() && k + 1 < path.values.size(); ++k) {
      const Vec3 a = view(sub(path.points[k], centre)), b = view(sub(path.points[k + 1], centre));
      const double mid = (path.values[k] + path.values[k + 1]) / 2;
      segments.push_back({(a[2] + b[2]) / 2,
                          {cx + a[0] * scale, cy - a[1] * scale, cx + b[0] * scale, cy - b[1] * scale},
                          colour_of(property.info.scale, range, mid)});
    }
  std::stable_sort(segments.begin(), segments.end(),
                   [](const Segment& a, const Segment& b) { return a.depth < b.depth; });
  const double width = std::max(2.0, panel.width / 75);
  cairo_set_line_cap(cr, CAIRO_LINE_CAP_ROUND);
  for (const Segment& s : segments) {
    cairo_new_path(cr);
    cairo_move_to(cr, s.ends[0], s.ends[1]);
    cairo_line_to(cr, s.ends[2], s.ends[3]);
    cairo_set_source_rgb(cr, 0.15, 0.15, 0.15);
    cairo_set_line_width(cr, width * 1.45);
    cairo_stroke_preserve(cr);
    cairo_set_source_rgb(cr, s.colour.r / 255.0, s.colour.g / 255.0, s.colour.b / 255.0);
    cairo_set_line_width(cr, width);
    cairo_stroke(cr);
  }
}

}  // namespace

HemisphereViews hemisphere_views(const std::vector<Vec3>& surface) {
  HemisphereViews views;
  Eigen::Vector3d mean = Eigen::Vector3d::Zero();
  for (const Vec3& p : surface) mean += Eigen::Vector3d(p[0], p[1], p[2]);
  mean /= static_cast<double>(std::max<std::size_t>(surface.size(), 1));
  Eigen::Matrix3d covariance = Eigen::Matrix3d::Zero();
  for (const Vec3& p : surface) {
    const Eigen::Vector3d d = Eigen::Vector3d(p[0], p[1], p[2]) - mean;
    covariance += d * d.transpose();
  }
  views.centre = {mean[0], mean[1], mean[2]};
  // Eigenvalues ascending: column 2 is the axis of most spread (right), 1 the next (up), 0 the least.
  const Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> solver(covariance);
  Eigen::Matrix3d axes = solver.eigenvectors();
  // Fixed signs: each of right and up points to the positive side of its largest component.
  for (const int k : {2, 1}) {
    Eigen::Index largest = 0;
    axes.col(k).cwiseAbs().maxCoeff(&largest);
    if (axes(largest, k) < 0) axes.col(k) *= -1;
  }
  const Eigen::Vector3d right = axes.col(2), up = axes.col(1), towards = right.cross(up);
  views.front = {right[0], right[1], right[2], up[0], up[1], up[2], towards[0], towards[1], towards[2]};
  return views;
}

std::vector<std::string> hemisphere_figures(const Globe& globe, const std::vector<const SurfaceProperty*>& properties,
                                            const HemisphereOptions& options) {
  if (options.width < 400 || options.height < 400 || options.width > 16384 || options.height > 16384)
    throw InputError(fmt::format("--size {}x{}: a hemisphere figure must be between 400x400 and 16384x16384 pixels",
                                 options.width, options.height));
  if (options.supersampling < 1 || options.supersampling > 8)
    throw InputError(fmt::format("supersampling {}: it must be 1 to 8", options.supersampling));
  if (!options.trace.empty() && properties.size() > 1)
    throw std::invalid_argument("hemisphere_figures: a trace's values belong to one property");
  if (properties.empty()) return {};
  std::vector<Colouring> colourings;
  for (const SurfaceProperty* property : properties)
    colourings.push_back({property, picture_range(*property, options.range)});
  const HemisphereViews views = hemisphere_views(globe.surface);
  const View front = front_view(views), back = back_view(views);

  const double w = options.width, h = options.height;
  const double margin = 0.02 * h, title_size = std::max(12.0, 0.03 * h), font_size = std::max(9.0, 0.018 * h);
  const double key_height = 5.2 * font_size;
  const double top = margin + 2.0 * title_size + 0.6 * font_size;
  const double grid_height = h - top - key_height - margin;
  const bool with_trace = !options.trace.empty();
  const int columns = with_trace ? 3 : 2;
  const double cell_w = (w - 2 * margin) / columns, cell_h = grid_height / 2;
  const double label_space = 1.6 * font_size;
  const int side = std::max(1, static_cast<int>(std::floor(std::min(cell_w, cell_h - label_space) * 0.96)));
  const auto panel_at = [&](double column, double row, std::string label) {
    const double x = margin + column * cell_w + (cell_w - side) / 2;
    const double y = top + row * cell_h + label_space;
    return PanelRect{std::round(x), std::round(y), static_cast<double>(side), static_cast<double>(side),
                     std::move(label)};
  };
  const double first = with_trace ? 1 : 0;
  const std::vector<PanelRect> panels{panel_at(first, 0, "surface, front"), panel_at(first + 1, 0, "surface, back"),
                                      panel_at(first, 1, "globe, front"), panel_at(first + 1, 1, "globe, back")};

  // The surface fills its panel at the same scale in both views; the globe (radius 1) likewise.
  double radius = 0;
  // The largest distance from the centre across the line of sight: the same for both views.
  for (const Vec3& p : globe.surface) {
    const Vec3 c = front(sub(p, views.centre));
    radius = std::max(radius, std::hypot(c[0], c[1]));
  }
  const double surface_scale = side / 2.0 * 0.94 / std::max(radius, 1e-9);
  const double globe_scale = side / 2.0 * 0.94;
  const std::vector<Vec3> surface_normals = vertex_normals(globe.surface, globe.triangles);
  const Vec3 origin{0, 0, 0};

  struct Job {
    const std::vector<Vec3>* positions;
    const std::vector<Vec3>* normals;
    const Vec3* centre;
    const View* view;
    double scale;
  };
  const std::array<Job, 4> jobs{{{&globe.surface, &surface_normals, &views.centre, &front, surface_scale},
                                 {&globe.surface, &surface_normals, &views.centre, &back, surface_scale},
                                 {&globe.sphere, &globe.sphere, &origin, &front, globe_scale},
                                 {&globe.sphere, &globe.sphere, &origin, &back, globe_scale}}};
  const int threads = detail::surface_threads(options.threads);
  // The colours of every panel's samples (a sample's colour does not depend on the panel), in batches shade_panel
  // takes at once.
  std::vector<ShadingBatch> batches;
  for (std::size_t f = 0; f < colourings.size(); ++f) {
    if (f % render_detail::kMaxShadedFigures == 0) batches.emplace_back();
    batches.back().colours.emplace_back(globe, *colourings[f].property, colourings[f].range);
  }
  for (ShadingBatch& batch : batches)
    batch.smooth = render_detail::smooth_triangles(batch.colours, globe.triangles.size());
  // The four panels side by side (each on one thread: its rasterization is serial), each shaded for every figure.
  std::array<std::vector<std::vector<std::uint32_t>>, 4> panel_pixels;  // [panel][figure]
  detail::parallel_chunks(4, threads, [&](std::int64_t k, int) {
    const Job& job = jobs[static_cast<std::size_t>(k)];
    panel_pixels[static_cast<std::size_t>(k)] =
        render_panel(globe, batches, *job.positions, *job.normals, *job.centre, *job.view, job.scale, side, side,
                     options.supersampling, 1);
  });
  // Then the figures side by side, each laid out (and encoded) on one thread.
  const std::string letters = with_trace ? "bcde" : "abcd";
  std::vector<std::string> figures(colourings.size());
  detail::parallel_chunks(static_cast<std::int64_t>(colourings.size()), threads, [&](std::int64_t f, int) {
    const SurfaceProperty& property = *colourings[static_cast<std::size_t>(f)].property;
    const ValueRange& range = colourings[static_cast<std::size_t>(f)].range;
    render_detail::Canvas canvas(options.format, options.width, options.height);
    cairo_t* cr = canvas.cr();
    for (std::size_t k = 0; k < jobs.size(); ++k) {
      std::vector<std::uint32_t>& pixels = panel_pixels[k][static_cast<std::size_t>(f)];
      cairo_surface_t* image = render_detail::image_surface(pixels, side, side);
      cairo_set_source_surface(cr, image, panels[k].x, panels[k].y);
      cairo_paint(cr);
      cairo_surface_destroy(image);
      render_detail::set_font(cr, font_size, true);
      render_detail::draw_text(cr, panels[k].x, panels[k].y - 0.45 * font_size, std::string(1, letters[k]),
                               Align::left);
      render_detail::set_font(cr, font_size);
      render_detail::draw_text(cr, panels[k].x + 1.3 * font_size, panels[k].y - 0.45 * font_size, panels[k].label,
                               Align::left, {60, 60, 60});
    }
    if (with_trace) {
      const PanelRect trace_panel = panel_at(0, 0.5, "backbone, front");  // between the two rows
      draw_trace(cr, options.trace, property, range, views.centre, front, surface_scale, trace_panel);
      // The label just above the trace (which is smaller than its panel: the surface's scale), clear of its tubes.
      const double label_y =
          std::max(trace_panel.y, trace_top(options.trace, views.centre, front, surface_scale, trace_panel)) -
          0.9 * font_size;
      render_detail::set_font(cr, font_size, true);
      render_detail::draw_text(cr, trace_panel.x, label_y, "a", Align::left);
      render_detail::set_font(cr, font_size);
      render_detail::draw_text(cr, trace_panel.x + 1.3 * font_size, label_y, trace_panel.label, Align::left,
                               {60, 60, 60});
    }
    render_detail::set_font(cr, title_size, true);
    render_detail::draw_text(cr, w / 2, margin + title_size,
                             fmt::format("{} · {} · surface and globe", globe.name, property.info.name), Align::centre);
    render_detail::set_font(cr, font_size * 0.9);
    render_detail::draw_text(cr, w / 2, margin + 1.5 * title_size + 0.45 * font_size,
                             "front: along the surface's axis of least spread; back: turned 180° about the vertical",
                             Align::centre, {90, 90, 90});
    render_detail::draw_colour_key(cr, render_detail::colour_key(property, range), margin, h - margin - key_height,
                                   w - 2 * margin, key_height, font_size);
    figures[static_cast<std::size_t>(f)] = canvas.finish();
  });
  return figures;
}

std::string hemisphere_figure(const Globe& globe, const SurfaceProperty& property, const HemisphereOptions& options) {
  return hemisphere_figures(globe, {&property}, options).front();
}

}  // namespace spheremap
