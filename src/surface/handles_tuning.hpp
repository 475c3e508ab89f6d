// Private to the surface stage: a setting of the handle repair (handles.cpp) that tests change to reach
// a code path the small grids of a unit test would not.
#pragma once

#include <cstdint>

namespace spheremap::detail {

/// Membranes of at least this many samples get a few of Dinic's shortest-path phases before the search
/// trees finish their maximum flow (MembraneMover::minimum_cut): the phases pay off on large membranes
/// only (BENCHMARKS.md). The cut found does not depend on it (the minimal minimum cut is unique).
inline std::int64_t& membrane_shortest_paths_from() {
  static std::int64_t samples = 1000;
  return samples;
}

}  // namespace spheremap::detail
