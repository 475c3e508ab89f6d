// Private to the handle repair: how a closure changes the Euler characteristic of the solid.
#pragma once

#include <cstdint>
#include <vector>

#include "spheremap/repair/closure.hpp"
#include "spheremap/surface/grid.hpp"

namespace spheremap::detail {

// The change of the Euler characteristic of the solid {field > level} (the full subcomplex of the
// Freudenthal triangulation on its samples) if `samples` (ascending, all on the side the closure leaves)
// moved across the level as `kind` says: positive when handles are removed. Each simplex touching them is
// counted once, from its smallest moved vertex. Uses the kToggled bit of `state` (one byte per sample),
// cleared again.
template <typename T>
int euler_change(const Grid3<T>& field, double level, const std::vector<std::int64_t>& samples, ClosureKind kind,
                 std::uint8_t* state);

}  // namespace spheremap::detail
