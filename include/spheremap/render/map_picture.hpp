// 2D maps of the whole globe (stage: render): each pixel takes the value of the globe triangle under it,
// interpolated barycentrically (categorical values: the nearest vertex's), coloured by colour_scale, with a
// graticule every 30°, a colour bar or legend, a title and optional residue outlines; PNG, SVG or PDF. And
// the numeric grid beside each picture (TSV).
#pragma once

#include <array>
#include <cstdint>
#include <optional>
#include <string>
#include <vector>

#include "spheremap/render/globe.hpp"
#include "spheremap/render/image_format.hpp"
#include "spheremap/render/projection.hpp"
#include "spheremap/render/residue_selection.hpp"
#include "spheremap/render/sphere_locator.hpp"

namespace spheremap {

/// Where the pixel centres of a map image (width x height, the projection's bounding rectangle) fall on the
/// globe: per pixel, row by row from the top-left, the triangle under it (-1 off the map) and its weights.
struct MapSamples {
  Projection projection = Projection::mollweide;
  int width = 0, height = 0;
  std::vector<std::int32_t> triangle;
  std::vector<std::array<float, 3>> weights;
};

/// Samples the map of `locator` at the pixel centres of a width x height image of `projection` (run on
/// `threads` threads, 0: all; the result does not depend on it). A pixel's direction on the globe is its left
/// neighbour's turned by the row's constant step of longitude (fresh every 32 pixels): it agrees with
/// direction_of(unproject(...)) to rounding. Precondition: width, height > 0.
/// Throws std::invalid_argument if a side is not positive.
MapSamples sample_map(const SphereLocator& locator, Projection projection, int width, int height, int threads = 0);

/// The value of `property` at a point of triangle `triangle` with `weights`: interpolated from the corners
/// with a value (NaN if the nearest corner has none); categorical properties take the nearest corner's
/// value. NaN for triangle -1. Precondition: triangle < globe.triangles.size(). Never throws.
double value_at(const Globe& globe, const SurfaceProperty& property, std::int32_t triangle,
                const std::array<float, 3>& weights);

/// The colour range of a picture of `property`: `requested` if given, else the property's default range,
/// else the range of its values (colour_scale's data_range). Never throws.
ValueRange picture_range(const SurfaceProperty& property, const std::optional<ValueRange>& requested);

struct MapFigureOptions {
  int width = 2048, height = 1024;  // the whole figure, pixels (SVG/PDF: points)
  ImageFormat format = ImageFormat::png;
  std::optional<ValueRange> range;    // the colour range (default: picture_range)
  std::vector<std::int32_t> outline;  // residues (indices into globe.residues) outlined on the map
  std::string outline_label;          // the selection as given, for the caption (e.g. "A:45-60,B:12")
  int threads = 0;
};

/// The size in pixels of the map image inside a figure of options.width x options.height (twice as wide as
/// high). Throws InputError if the figure is smaller than 400 x 200 or larger than 16384 x 16384.
std::array<int, 2> map_image_size(const MapFigureOptions& options);

/// Where the map image lies in the figure: its top-left pixel {x, y} (its size is map_image_size). Throws as
/// map_image_size.
std::array<int, 2> map_image_origin(const MapFigureOptions& options);

/// The figure of `property` on `globe` in options.format: the map (samples from sample_map at
/// map_image_size(options)), title "<globe.name> · <property> · <projection>", graticule, key.
/// Preconditions: `property` belongs to `globe`; `samples` has map_image_size(options).
/// Throws std::invalid_argument if the samples' size differs, and as map_image_size.
std::string map_figure(const Globe& globe, const SurfaceProperty& property, const MapSamples& samples,
                       const MapFigureOptions& options);

/// The numeric grid of a map: the projection's bounding rectangle in `columns` x `rows` cells (cells whose
/// centre is off the map left out), one line per cell: row, column, latitude and longitude of its centre
/// (degrees, 3 decimals), value (mean of the property at 4 x 4 points of the cell; categorical: the most frequent
/// class, the smallest of equals; empty if none has a value) and the residues under those points (the nearest vertex's
/// residue, "A:45,A:46", in chain and number order). Tab-separated, a header line first. Preconditions: columns, rows >
/// 0. Throws std::invalid_argument otherwise.
std::string map_grid_tsv(const Globe& globe, const SurfaceProperty& property, const SphereLocator& locator,
                         Projection projection, int columns = 360, int rows = 180);

/// The same from samples taken once for every property: `grid` from sample_grid (4 x 4 samples a cell), on
/// `threads` threads (0: all; the text does not depend on it). Throws std::invalid_argument if `grid` is not
/// of that shape.
std::string map_grid_tsv(const Globe& globe, const SurfaceProperty& property, const MapSamples& grid, int threads = 0);

/// The grids of several properties from the same samples, in their order: the same text as map_grid_tsv of each,
/// at less cost (each cell's position and residues are found and formatted once). Throws as map_grid_tsv.
std::vector<std::string> map_grid_tsvs(const Globe& globe, const std::vector<const SurfaceProperty*>& properties,
                                       const MapSamples& grid, int threads = 0);

/// The samples of a columns x rows grid for map_grid_tsv (sample_map at 4 x 4 points a cell).
/// Throws std::invalid_argument if a side is not positive.
MapSamples sample_grid(const SphereLocator& locator, Projection projection, int columns, int rows, int threads = 0);

}  // namespace spheremap
