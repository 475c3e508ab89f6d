// Private to the handle repair: how a closure changes the area of the contour.
#pragma once

#include <cstdint>
#include <vector>

#include "spheremap/surface/grid.hpp"

namespace spheremap::detail {

// The change of the area of contour_isosurface(field, level, ·, minimum_fraction) (all components) if
// `samples` took `value`, computed over the cells that have a corner in them exactly as
// contour_isosurface computes their triangles, so that it is exactly what the change does to the
// contour's area. The field is left as it was (it is changed and restored, hence not const).
template <typename T>
double area_change(Grid3<T>& field, double level, double minimum_fraction, const std::vector<std::int64_t>& samples,
                   T value);

}  // namespace spheremap::detail
