// Private to src/render: the value and colour of a property at a sample (a triangle and its barycentric weights),
// as value_at and colour_of(value_at(...)) give them, with a categorical property's colours looked up per vertex once.
#pragma once

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <vector>

#include "spheremap/render/colour_scale.hpp"
#include "spheremap/render/map_picture.hpp"

namespace spheremap::render_detail {

/// The corner (0, 1, 2) of largest weight, the first of equals (value_at's nearest vertex).
inline int nearest_corner(const std::array<float, 3>& w) {
  return w[1] > w[0] ? (w[2] > w[1] ? 2 : 1) : (w[2] > w[0] ? 2 : 0);
}

/// value_at for a sample on the globe (triangle >= 0), inline: the pictures call it for millions of samples.
inline double sample_value(const Globe& globe, const SurfaceProperty& property, std::int32_t triangle,
                           const std::array<float, 3>& weights) {
  const Triangle& t = globe.triangles[triangle];
  const double nearest_value = property.values[t[nearest_corner(weights)]];
  if (property.info.scale == ScaleKind::categorical || std::isnan(nearest_value)) return nearest_value;
  double sum = 0, weight = 0;
  for (int k = 0; k < 3; ++k) {
    const double v = property.values[t[k]];
    if (std::isnan(v)) continue;
    sum += weights[k] * v;
    weight += weights[k];
  }
  return sum / weight;  // weight > 0: the nearest corner has a value
}

class SampleColours {
 public:
  /// How much a channel (0-255) may vary between a triangle's corners for its colours to count as smooth.
  static constexpr int kSmoothSpread = 16;

  /// Preconditions: `property` belongs to `globe`; both outlive this.
  SampleColours(const Globe& globe, const SurfaceProperty& property, const ValueRange& range)
      : globe_(&globe),
        property_(&property),
        range_(range),
        table_(&colour_table(property.info.scale)),
        categorical_(property.info.scale == ScaleKind::categorical) {
    vertex_.reserve(property.values.size());
    for (const double v : property.values) vertex_.push_back(colour_of(property.info.scale, range, v));
    if (categorical_ || !(range.hi > range.lo)) return;
    // colour_index's position on the table, (value - lo) / (hi - lo) * 256, of every vertex: interpolated directly.
    scaled_.reserve(property.values.size());
    const double per_unit = kColourTableSize / (range.hi - range.lo);
    for (const double v : property.values) scaled_.push_back((v - range.lo) * per_unit);
  }

  /// colour_of(scale, range, value_at(globe, property, triangle, weights)), up to rounding where the value falls
  /// on the edge of one of the table's bins. Precondition: triangle >= 0.
  [[nodiscard]] Rgb8 operator()(std::int32_t triangle, const std::array<float, 3>& weights) const {
    // value_at gives a categorical property's nearest vertex value (also when it is NaN).
    const Triangle& t = globe_->triangles[triangle];
    if (categorical_) return vertex_[t[nearest_corner(weights)]];
    if (!scaled_.empty()) {
      // The table position interpolated like the value (colour_index's rule on it, the same up to rounding); a
      // missing or infinite corner value takes the general path below.
      const double position = (weights[0] * scaled_[t[0]] + weights[1] * scaled_[t[1]] + weights[2] * scaled_[t[2]]) /
                              (static_cast<double>(weights[0]) + weights[1] + weights[2]);
      if (std::isfinite(position)) {
        if (!(position > 0)) return (*table_)[0];
        return (*table_)[std::min(static_cast<int>(std::min(position, 1e9)), kColourTableSize - 1)];
      }
    }
    // colour_of with its table looked up once.
    const int index = colour_index(property_->info.scale, range_, sample_value(*globe_, *property_, triangle, weights));
    return index < 0 ? kMissingValueColour : (*table_)[index];
  }

  /// Whether the colour varies little and continuously across `triangle`, so that one sample stands for several:
  /// a categorical property whose corners have one colour; any other whose corners all have a value and colours
  /// within kSmoothSpread of each other in every channel (a steep or saturating stretch of the scale is not).
  /// Precondition: triangle >= 0.
  [[nodiscard]] bool smooth(std::int32_t triangle) const {
    const Triangle& t = globe_->triangles[triangle];
    if (categorical_) return vertex_[t[0]] == vertex_[t[1]] && vertex_[t[1]] == vertex_[t[2]];
    if (std::isnan(property_->values[t[0]]) || std::isnan(property_->values[t[1]]) ||
        std::isnan(property_->values[t[2]]))
      return false;
    const auto spread = [](int a, int b, int c) { return std::max({a, b, c}) - std::min({a, b, c}); };
    const Rgb8 &a = vertex_[t[0]], &b = vertex_[t[1]], &c = vertex_[t[2]];
    return spread(a.r, b.r, c.r) <= kSmoothSpread && spread(a.g, b.g, c.g) <= kSmoothSpread &&
           spread(a.b, b.b, c.b) <= kSmoothSpread;
  }

 private:
  const Globe* globe_;
  const SurfaceProperty* property_;
  ValueRange range_;
  const ColourTable* table_;
  bool categorical_;
  std::vector<Rgb8> vertex_;    // the colour of each vertex's value
  std::vector<double> scaled_;  // continuous scales with hi > lo: each vertex's table position; empty otherwise
};

}  // namespace spheremap::render_detail
