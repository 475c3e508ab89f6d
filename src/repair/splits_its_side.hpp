// Private to the handle repair: whether a closure just applied split a side of the level instead of
// removing a handle. Tests call it alone.
#pragma once

#include <cstdint>
#include <vector>

#include "spheremap/repair/closure.hpp"
#include "spheremap/surface/grid.hpp"

namespace spheremap::detail {

// Whether a closure, just applied, split the side its samples left: a piece cut off the solid, or a pocket
// of the outside closed off into a void; or whether its samples stay apart from the side they joined (a
// floating piece, a void). Such a closure raises the Euler characteristic as a removed handle does, and
// removes none. `samples`: ascending grid indices, all on the side of `level` that `kind` leads to in
// `field` (above it for a fill, at or below it for a cut), and before the closure all on the other side.
// Everything beyond the grid counts as outside. The side left is searched breadth first from every
// sample next to the closure, one label per start, labels joined where their searches meet; a label all
// of whose samples are searched while other labels remain is a piece apart. The search stops after
// `budget` samples searched, or twice as many found, besides those next to the closure, and then answers
// false (a piece larger than about budget/2 samples is not found).
template <typename T>
bool closure_splits_its_side(const Grid3<T>& field, double level, const std::vector<std::int64_t>& samples,
                             ClosureKind kind, std::int64_t budget);

}  // namespace spheremap::detail
