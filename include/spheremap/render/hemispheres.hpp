// The paper's hemisphere pictures (Figures 5-8) (stage: render): the original surface and its globe, each
// seen from two opposite directions, coloured alike by one property, shaded, with a key. Drawn by a software
// rasterizer with a depth buffer, supersampled: headless, no GPU, the same bytes for the same input.
#pragma once

#include <optional>
#include <string>
#include <vector>

#include "spheremap/render/globe.hpp"
#include "spheremap/render/image_format.hpp"

namespace spheremap {

/// The two opposite views: camera space is (right, up, towards the viewer). The front view looks along the
/// surface's axis of least spread with its axis of most spread across (as PyMOL's `orient` and the viewer
/// open); the back view is the front one turned 180° about the vertical axis.
struct HemisphereViews {
  Vec3 centre{0, 0, 0};                                    // of the surface (the globe is centred at the origin)
  std::array<double, 9> front{1, 0, 0, 0, 1, 0, 0, 0, 1};  // rows: right, up, towards the viewer
};

/// The views of `surface` (principal axes of its vertices; fixed signs, so the same surface always gives the
/// same views). Precondition: at least one vertex. Never throws (but std::bad_alloc).
HemisphereViews hemisphere_views(const std::vector<Vec3>& surface);

/// A chain of points drawn as a tube beside the surface (the backbone of the paper's Figure 8), coloured
/// by `values` on the picture's scale.
struct TracePath {
  std::vector<Vec3> points;    // e.g. the CA atoms of one chain, in order
  std::vector<double> values;  // one per point
};

struct HemisphereOptions {
  int width = 1600, height = 1600;  // the whole figure, pixels (SVG/PDF: points)
  ImageFormat format = ImageFormat::png;
  std::optional<ValueRange> range;  // the colour range (default: picture_range)
  int supersampling = 2;            // samples per pixel along each axis (antialiasing)
  /// When not empty: a fifth panel, the trace seen from the front view (the paper's Figure 8a).
  std::vector<TracePath> trace;
  int threads = 0;
};

/// The figure: panels a, b (surface from the front and the back), c, d (globe from the same directions),
/// Lambert shading with ambient light from the viewer's upper left, and the property's colour key.
/// Preconditions: `property` belongs to `globe`; globe has triangles.
/// Throws InputError if the size is outside 400x400..16384x16384 or supersampling outside 1..8.
std::string hemisphere_figure(const Globe& globe, const SurfaceProperty& property, const HemisphereOptions& options);

/// The figures of several properties of `globe` with the same options, in their order: the same bytes as
/// hemisphere_figure of each, at a fraction of the cost (the four views are rasterized once and shaded for every
/// property). Preconditions as hemisphere_figure, for each property. Throws as hemisphere_figure, and
/// std::invalid_argument if `options.trace` is not empty with more than one property (its values are one
/// property's).
std::vector<std::string> hemisphere_figures(const Globe& globe, const std::vector<const SurfaceProperty*>& properties,
                                            const HemisphereOptions& options);

}  // namespace spheremap
