// Private to the handle repair: the values a closure gives the samples it moves.
#pragma once

#include <algorithm>
#include <cmath>
#include <limits>
#include <utility>

#include "spheremap/repair/closure.hpp"

namespace spheremap::detail {

// Half a grid step past the level, below it for a cut and above it for a fill, as if the surface ran
// along the faces of the moved samples' voxels. Just past the level (the smallest change of sign), the
// contour would run through the moved samples themselves, and a closure one sample thick would become
// two faces a hair apart: a needless sliver, and more area.
template <typename T>
struct MovedSampleValues {
  T below, above;
  MovedSampleValues(double level, double spacing)
      : below(std::min(std::nextafter(static_cast<T>(level), -std::numeric_limits<T>::max()),
                       static_cast<T>(level - 0.5 * spacing))),
        above(std::max(std::nextafter(static_cast<T>(level), std::numeric_limits<T>::max()),
                       static_cast<T>(level + 0.5 * spacing))) {}
  [[nodiscard]] T operator()(ClosureKind kind) const { return kind == ClosureKind::kFill ? above : below; }
};

}  // namespace spheremap::detail
