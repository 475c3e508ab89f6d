// Private to the handle repair: the topology-preserving growths of the solid and of the outside.
#pragma once

#include <cstdint>
#include <vector>

#include "spheremap/surface/grid.hpp"

namespace spheremap::detail {

// Both growths of the solid {field > level} (Kriegeskorte & Goebel 2001; Han, Xu & Prince 2002), as
// state bytes (sample_state.hpp), one per sample: kInside on inside samples; kInSolid on the samples the
// solid's growth reached (from the deepest sample of its largest piece, by decreasing value, simple
// samples only: a ball); kInOutside on those the outside's reached (from the grid border, by decreasing
// distance to the solid: a shell around a ball). The samples left out of both lie across the handles.
// `threads` (0: one per hardware thread) is used for the distance, and with two or more the two growths
// run at once; the result does not depend on it.
// Throws std::invalid_argument if nothing is inside or the solid reaches the grid's border.
template <typename T>
std::vector<std::uint8_t> grow_both(const Grid3<T>& field, double level, int threads);

}  // namespace spheremap::detail
