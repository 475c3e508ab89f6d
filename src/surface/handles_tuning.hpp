// Private to the surface stage: a setting of the handle repair (handles.cpp) that tests change to reach
// a code path the small grids of a unit test would not, and a check of the repair that tests call alone.
#pragma once

#include <cstdint>
#include <vector>

#include "spheremap/surface/grid.hpp"

namespace spheremap::detail {

/// Membranes of at least this many samples get a few of Dinic's shortest-path phases before the search
/// trees finish their maximum flow (MembraneMover::minimum_cut): the phases pay off on large membranes
/// only (BENCHMARKS.md). The cut found does not depend on it (the minimal minimum cut is unique).
inline std::int64_t& membrane_shortest_paths_from() {
  static std::int64_t samples = 1000;
  return samples;
}

/// Whether a change of the handle repair, just applied, split the side its samples left: a piece cut
/// off the solid, or a pocket of the outside closed off into a void; or whether its samples stay apart
/// from the side they joined (a floating piece, a void). Such a change raises the Euler characteristic as
/// a removed handle does, and removes none. `samples`: ascending grid indices, all on the side of `level`
/// that `filled` says (above it when filled, at or below it when cut) in `field`, and before the change
/// all on the other side. Everything beyond the grid counts as outside. The search stops after `budget`
/// samples searched, or twice as many found, besides those next to the change, and then answers false (a
/// piece larger than about budget/2 samples is not found).
bool change_splits_its_side(const Grid3<double>& field, double level, const std::vector<std::int64_t>& samples, bool filled,
                            std::int64_t budget);

}  // namespace spheremap::detail
