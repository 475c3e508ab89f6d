// Private to src/render: the value and colour of a property at a sample (a triangle and its barycentric weights),
// as value_at and colour_of(value_at(...)) give them, with a categorical property's colours looked up per vertex once.
#pragma once

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
  /// Preconditions: `property` belongs to `globe`; both outlive this.
  SampleColours(const Globe& globe, const SurfaceProperty& property, const ValueRange& range)
      : globe_(&globe), property_(&property), range_(range), table_(&colour_table(property.info.scale)) {
    // value_at gives a categorical property's nearest vertex value (also when it is NaN).
    if (property.info.scale != ScaleKind::categorical) return;
    vertex_.reserve(property.values.size());
    for (const double v : property.values) vertex_.push_back(colour_of(property.info.scale, range, v));
  }

  /// colour_of(scale, range, value_at(globe, property, triangle, weights)). Precondition: triangle >= 0.
  [[nodiscard]] Rgb8 operator()(std::int32_t triangle, const std::array<float, 3>& weights) const {
    if (!vertex_.empty()) return vertex_[globe_->triangles[triangle][nearest_corner(weights)]];
    // colour_of with its table looked up once.
    const int index = colour_index(property_->info.scale, range_, sample_value(*globe_, *property_, triangle, weights));
    return index < 0 ? kMissingValueColour : (*table_)[index];
  }

 private:
  const Globe* globe_;
  const SurfaceProperty* property_;
  ValueRange range_;
  const ColourTable* table_;
  std::vector<Rgb8> vertex_;  // categorical: the colour of each vertex's value; empty otherwise
};

}  // namespace spheremap::render_detail
