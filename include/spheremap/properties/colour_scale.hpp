// Colour scales shared by every picture of spheremap (2D maps, hemisphere pictures, the viewer) and by the
// vertex colours of its PLY and glTF files: one 256-entry table per kind of scale and one rule from a value
// to a table entry, so that a value gets the same colour everywhere.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <span>
#include <string_view>

#include "spheremap/properties/property.hpp"

namespace spheremap {

/// An 8-bit sRGB colour.
struct Rgb8 {
  std::uint8_t r = 0, g = 0, b = 0;
  friend bool operator==(const Rgb8&, const Rgb8&) = default;
};

inline constexpr int kColourTableSize = 256;
using ColourTable = std::array<Rgb8, kColourTableSize>;

/// The colour of a missing value (NaN) on every scale: mid grey, in none of the tables' ramps.
inline constexpr Rgb8 kMissingValueColour{128, 128, 128};

/// matplotlib's viridis (van der Walt and Smith), its published 256 entries rounded to 8 bits. The tables below
/// are built once, on first use; none of these functions throws.
const ColourTable& viridis_table();

/// ColorBrewer's 9-class RdBu (Brewer), from red (entry 0) through near-white to blue (entry 255),
/// interpolated linearly in sRGB: negative potentials red, positive blue, as the paper draws them.
const ColourTable& red_white_blue_table();

/// Google's Turbo (Mikhailov 2019), matplotlib's published 256 entries rounded to 8 bits: the spectrum from
/// dark blue (entry 0) through green and yellow to dark red (entry 255), for the spectrum scale.
const ColourTable& spectrum_table();

/// Tableau 10 repeated: entry k is class k's colour (classes 10 apart share a colour).
const ColourTable& categorical_table();

/// The table of a scale kind (one of the four above).
const ColourTable& colour_table(ScaleKind kind);

/// The table entry of `value`, or -1 for a missing value. Continuous scales: t = (value - lo) / (hi - lo),
/// entry floor(256 t) clamped to [0, 255] (so lo..hi is cut into 256 equal bins; +-infinity saturate);
/// a range with hi <= lo gives entry 128 for every value. Categorical: the value rounded to the nearest
/// whole number, -1 if that is outside [0, 255]; `range` is not used. NaN gives -1 on every scale.
/// The viewer's script applies the same rule (viewer/src/colour.js); keep them equal. Never throws.
/// Inline: the pictures look up millions of samples.
inline int colour_index(ScaleKind kind, const ValueRange& range, double value) {
  if (std::isnan(value)) return -1;
  if (kind == ScaleKind::categorical) {
    const double k = std::round(value);
    return k >= 0 && k < kColourTableSize ? static_cast<int>(k) : -1;
  }
  if (!(range.hi > range.lo)) return kColourTableSize / 2;
  const double t = (value - range.lo) / (range.hi - range.lo);
  // Compare before converting: t may be infinite or far outside the int range.
  if (!(t > 0)) return 0;
  if (t >= 1) return kColourTableSize - 1;
  return std::min(static_cast<int>(t * kColourTableSize), kColourTableSize - 1);
}

/// colour_table(kind)[colour_index(...)], or kMissingValueColour for -1. Never throws.
Rgb8 colour_of(ScaleKind kind, const ValueRange& range, double value);

/// A default range for `values` (NaN ignored): sequential and spectrum [min, max]; diverging [-m, m] with m the largest
/// |value|; categorical [0, 255]. With no finite value, or all values equal (m = 0), the range is widened
/// to a width of 1 around them ([-1, 1] for diverging), so that hi > lo always. Never throws.
ValueRange data_range(ScaleKind kind, std::span<const float> values);

}  // namespace spheremap
