// Private to src/render: the shading of a hemisphere panel from its rasterized samples (hemispheres.cpp draws the
// panels; a test checks the shading on its own).
#pragma once

#include <cstdint>
#include <vector>

#include "rasterizer.hpp"
#include "sample_colours.hpp"

namespace spheremap::render_detail {

/// The most colourings shade_panel shades at once (a bit each in smooth_triangles' masks).
inline constexpr std::size_t kMaxShadedFigures = 64;

/// For each triangle, whether its colours are smooth (SampleColours::smooth) in each colouring: bit f for colours[f].
/// Throws std::invalid_argument for more than kMaxShadedFigures colourings.
std::vector<std::uint64_t> smooth_triangles(const std::vector<SampleColours>& colours, std::size_t triangles);

/// The pixels (premultiplied ARGB, transparent background) of a width x height panel whose samples, supersampling
/// along each axis, are in `buffer` (triangles indexing `triangles` over the screen points `screen`), one image per
/// colouring in `colours`. A sample is coloured by its barycentric weights and darkened by `light` (per vertex)
/// interpolated alike (Gouraud); a pixel is the mean of its samples, coverage its alpha.
/// A pixel whose samples all lie on one piece of surface (all covered, by at most four triangles that each share a
/// corner with the first) is shaded once instead, at its centre, in the first of those triangles that holds it (else
/// the one it is least outside), in each figure whose colours are smooth on all of them (SampleColours::smooth):
/// shading and colours are continuous there, so it differs from the mean of its samples only by the colour scale's
/// curvature within the pixel. Silhouettes, folds and category boundaries keep every sample.
/// `smooth` is smooth_triangles(colours, triangles.size()): each figure decides alone, so that a figure does not
/// depend on which are drawn with it. Rows run on `threads` threads (0: all); the result does not depend on their
/// number.
/// Preconditions: the sizes agree; `light` has a value per screen point; every colouring is of the same globe.
/// Throws std::invalid_argument for more than kMaxShadedFigures colourings.
std::vector<std::vector<std::uint32_t>> shade_panel(const IdBuffer& buffer, int width, int height, int supersampling,
                                                    const std::vector<Vec3>& screen,
                                                    const std::vector<Triangle>& triangles,
                                                    const std::vector<double>& light,
                                                    const std::vector<SampleColours>& colours,
                                                    const std::vector<std::uint64_t>& smooth, int threads);

}  // namespace spheremap::render_detail
