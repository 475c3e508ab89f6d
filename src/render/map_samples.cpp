// Sampling a globe through a projection: the pixels of a map and the cells of its numeric grid (see
// map_picture.hpp).
#include <algorithm>
#include <array>
#include <charconv>
#include <cmath>
#include <iterator>
#include <limits>
#include <numbers>
#include <stdexcept>
#include <system_error>

#include <fmt/format.h>

#include "../util/parallel.hpp"
#include "sample_colours.hpp"
#include "spheremap/render/colour_scale.hpp"
#include "spheremap/render/map_picture.hpp"

namespace spheremap {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kPi = std::numbers::pi;
constexpr int kFreshEvery = 32;  // pixels of a row between directions computed afresh (sample_map)

// The plane point at (column + fx, row + fy) of a width x height image of the projection's rectangle.
PlanePoint plane_point(const PlanePoint& half, int width, int height, double column, double row) {
  return {(column / width * 2 - 1) * half.x, (1 - row / height * 2) * half.y};
}

}  // namespace

MapSamples sample_map(const SphereLocator& locator, Projection projection, int width, int height, int threads) {
  if (width <= 0 || height <= 0) throw std::invalid_argument("sample_map: the image must have a positive size");
  MapSamples samples{projection, width, height, {}, {}};
  const auto pixels = static_cast<std::size_t>(width) * static_cast<std::size_t>(height);
  samples.triangle.assign(pixels, -1);
  samples.weights.assign(pixels, {0, 0, 0});
  const PlanePoint half = projection_half_extent(projection);
  detail::parallel_ranges(height, 16, detail::surface_threads(threads), [&](std::int64_t first, std::int64_t last) {
    for (auto row = static_cast<int>(first); row < last; ++row) {
      const RowUnprojection unproject_row(projection, plane_point(half, width, height, 0.5, row + 0.5).y);
      std::int32_t previous = -1;  // the triangle of the pixel to the left, which most pixels share (per row: the
                                   // result does not depend on how rows are split between threads)
      // Along a row the longitude grows by a constant step (the longitude one pixel right of the centre line):
      // each pixel's direction is its left neighbour's turned by that step about the axis, instead of a cosine and
      // a sine of its own; evaluated afresh every kFreshEvery pixels and where the longitude is clamped, so that
      // rounding never accumulates over more than that.
      const auto step = unproject_row(2 * half.x / width);
      const bool stepping = step && std::abs(step->longitude) < kPi;  // else a row of a pixel or two: all fresh
      const double cos_step = stepping ? std::cos(step->longitude) : 1;
      const double sin_step = stepping ? std::sin(step->longitude) : 0;
      Vec3 direction{};
      int turned = kFreshEvery;  // since the last fresh direction
      for (int column = 0; column < width; ++column) {
        const auto at = unproject_row(plane_point(half, width, height, column + 0.5, row + 0.5).x);
        if (!at) {
          turned = kFreshEvery;
          continue;
        }
        if (stepping && turned < kFreshEvery && std::abs(at->longitude) < kPi) {
          direction = {direction[0] * cos_step - direction[1] * sin_step,
                       direction[0] * sin_step + direction[1] * cos_step, direction[2]};
          ++turned;
        } else {
          direction = unproject_row.direction(at->longitude);
          turned = 1;
        }
        const SphereHit hit = locate_on_sphere(locator, direction, kPi / 2 - at->latitude, at->longitude, previous);
        previous = hit.triangle;
        const std::size_t i = static_cast<std::size_t>(row) * width + column;
        samples.triangle[i] = hit.triangle;
        samples.weights[i] = {static_cast<float>(hit.weights[0]), static_cast<float>(hit.weights[1]),
                              static_cast<float>(hit.weights[2])};
      }
    }
  });
  return samples;
}

double value_at(const Globe& globe, const SurfaceProperty& property, std::int32_t triangle,
                const std::array<float, 3>& weights) {
  return triangle < 0 ? kNaN : render_detail::sample_value(globe, property, triangle, weights);
}

ValueRange picture_range(const SurfaceProperty& property, const std::optional<ValueRange>& requested) {
  if (requested) return *requested;
  if (property.info.default_range) return *property.info.default_range;
  const std::vector<float> values(property.values.begin(), property.values.end());
  return data_range(property.info.scale, values);
}

namespace {

constexpr int kGridSubsamples = 4;  // per cell side

using CellResidues = std::array<std::int32_t, kGridSubsamples * kGridSubsamples>;

// Appends `value` as printf's %.<precision>f (fixed) or %.<precision>g (general) would write it: std::to_chars, which
// is specified so, takes a fraction of fmt's instructions for a precision (fmt falls back to Dragon4 for many).
// Precondition: the text fits in 64 characters (|value| < 1e50 for fixed).
void append_number(fmt::memory_buffer& out, double value, std::chars_format format, int precision) {
  char text[64];
  const auto written = std::to_chars(text, text + sizeof text, value, format, precision);
  if (written.ec != std::errc()) throw std::invalid_argument("append_number: the number does not fit");
  out.append(text, written.ptr);
}

void append_number(fmt::memory_buffer& out, int value) {
  char text[16];
  out.append(text, std::to_chars(text, text + sizeof text, value).ptr);
}

// Calls visit(triangle, weights) for each of the cell's points on the globe (the pixels of the fine samples it
// covers), row by row.
template <typename Visit>
void for_each_cell_point(const MapSamples& fine, int row, int column, Visit&& visit) {
  for (int sy = 0; sy < kGridSubsamples; ++sy)
    for (int sx = 0; sx < kGridSubsamples; ++sx) {
      const std::size_t i = static_cast<std::size_t>(row * kGridSubsamples + sy) * fine.width +
                            static_cast<std::size_t>(column * kGridSubsamples + sx);
      if (fine.triangle[i] >= 0) visit(fine.triangle[i], fine.weights[i]);
    }
}

// The residues under the cell's points (the pixels of the fine samples it covers; indices into globe.residues),
// ascending, each once: how many.
int cell_residues(const Globe& globe, const MapSamples& fine, int row, int column, CellResidues& residues) {
  int count = 0;
  if (globe.vertex_residue.empty()) return 0;
  for_each_cell_point(fine, row, column, [&](std::int32_t triangle, const std::array<float, 3>& w) {
    const std::int32_t vertex = globe.triangles[triangle][render_detail::nearest_corner(w)];
    if (globe.vertex_residue[vertex] >= 0) residues[count++] = globe.vertex_residue[vertex];
  });
  std::sort(residues.begin(), residues.begin() + count);
  return static_cast<int>(std::unique(residues.begin(), residues.begin() + count) - residues.begin());
}

// The cell's value: the mean of the property at its points (categorical: the most frequent class, the smallest of
// equals); NaN if none has a value.
double cell_value(const Globe& globe, const SurfaceProperty& property, const MapSamples& fine, int row, int column) {
  double sum = 0;
  int count = 0;
  const bool categorical = property.info.scale == ScaleKind::categorical;
  std::array<double, kGridSubsamples * kGridSubsamples> classes{};
  int class_count = 0;
  for_each_cell_point(fine, row, column, [&](std::int32_t triangle, const std::array<float, 3>& w) {
    const double v = render_detail::sample_value(globe, property, triangle, w);
    if (std::isnan(v)) return;
    if (categorical) classes[class_count++] = v;
    sum += v, ++count;
  });
  double value = kNaN;
  if (categorical) {
    std::sort(classes.begin(), classes.begin() + class_count);
    int best = 0;
    for (int k = 0; k < class_count;) {
      int n = 1;
      while (k + n < class_count && classes[k + n] == classes[k]) ++n;
      if (n > best) best = n, value = classes[k];
      k += n;
    }
  } else if (count > 0) {
    value = sum / count;
  }
  return value;
}

}  // namespace

MapSamples sample_grid(const SphereLocator& locator, Projection projection, int columns, int rows, int threads) {
  if (columns <= 0 || rows <= 0) throw std::invalid_argument("sample_grid: the grid must have cells");
  return sample_map(locator, projection, columns * kGridSubsamples, rows * kGridSubsamples, threads);
}

std::vector<std::string> map_grid_tsvs(const Globe& globe, const std::vector<const SurfaceProperty*>& properties,
                                       const MapSamples& grid, int threads) {
  if (grid.width % kGridSubsamples != 0 || grid.height % kGridSubsamples != 0 || grid.width == 0)
    throw std::invalid_argument("map_grid_tsv: the samples are not those of sample_grid");
  const int columns = grid.width / kGridSubsamples, rows = grid.height / kGridSubsamples;
  const PlanePoint half = projection_half_extent(grid.projection);
  std::vector<std::string> ids;  // residue_id of each residue, once
  ids.reserve(globe.residues.size());
  for (const ResidueLabel& residue : globe.residues) ids.push_back(residue_id(residue));
  const std::size_t tables = properties.size();
  std::vector<std::vector<std::string>> lines(tables, std::vector<std::string>(static_cast<std::size_t>(rows)));
  // A cell's position and residues are the same in every table: formatted once, the values once per table.
  detail::parallel_ranges(rows, 4, detail::surface_threads(threads), [&](std::int64_t first, std::int64_t last) {
    std::vector<fmt::memory_buffer> out(tables);
    fmt::memory_buffer position, residues;
    fmt::memory_buffer latitude;  // the row's, formatted once: it depends on the row alone
    for (auto row = static_cast<int>(first); row < last; ++row) {
      // RowUnprojection gives unproject's points bit for bit.
      const RowUnprojection unproject_row(grid.projection, plane_point(half, columns, rows, 0.5, row + 0.5).y);
      latitude.clear();
      for (int column = 0; column < columns; ++column) {
        const auto centre = unproject_row(plane_point(half, columns, rows, column + 0.5, row + 0.5).x);
        if (!centre) continue;
        if (latitude.size() == 0) append_number(latitude, centre->latitude / kDegree, std::chars_format::fixed, 3);
        position.clear();  // row, column, latitude, longitude (degrees, 3 decimals)
        append_number(position, row);
        position.push_back('\t');
        append_number(position, column);
        position.push_back('\t');
        position.append(latitude.data(), latitude.data() + latitude.size());
        position.push_back('\t');
        append_number(position, centre->longitude / kDegree, std::chars_format::fixed, 3);
        position.push_back('\t');
        CellResidues under{};
        const int count = cell_residues(globe, grid, row, column, under);
        residues.clear();
        residues.push_back('\t');
        for (int k = 0; k < count; ++k) {
          if (k > 0) residues.push_back(',');
          const std::string& id = ids[static_cast<std::size_t>(under[k])];
          residues.append(id.data(), id.data() + id.size());
        }
        residues.push_back('\n');
        for (std::size_t t = 0; t < tables; ++t) {
          out[t].append(position.data(), position.data() + position.size());
          const double value = cell_value(globe, *properties[t], grid, row, column);
          if (!std::isnan(value)) append_number(out[t], value, std::chars_format::general, 6);  // as {:.6g}
          out[t].append(residues.data(), residues.data() + residues.size());
        }
      }
      for (std::size_t t = 0; t < tables; ++t) {
        lines[t][static_cast<std::size_t>(row)] = fmt::to_string(out[t]);
        out[t].clear();
      }
    }
  });
  std::vector<std::string> tsvs(tables);
  for (std::size_t t = 0; t < tables; ++t) {
    std::size_t size = 0;
    for (const auto& line : lines[t]) size += line.size();
    std::string& tsv = tsvs[t];
    tsv = "row\tcolumn\tlatitude\tlongitude\tvalue\tresidues\n";
    tsv.reserve(tsv.size() + size);
    for (auto& line : lines[t]) tsv += line, line = std::string();
  }
  return tsvs;
}

std::string map_grid_tsv(const Globe& globe, const SurfaceProperty& property, const MapSamples& grid, int threads) {
  return map_grid_tsvs(globe, {&property}, grid, threads).front();
}

std::string map_grid_tsv(const Globe& globe, const SurfaceProperty& property, const SphereLocator& locator,
                         Projection projection, int columns, int rows) {
  return map_grid_tsv(globe, property, sample_grid(locator, projection, columns, rows));
}

}  // namespace spheremap
