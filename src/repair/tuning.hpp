// Private to the handle repair: its settings, one of which tests change to reach a code path that the
// small grids of a unit test would not.
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

// How far (Å) from where the growths put a membrane its handle or tunnel is searched for a thinner
// section (MembraneMover): most of what a far longer reach gains, for a fraction of the time
// (BENCHMARKS.md).
constexpr double kMembraneReach = 4.0;

// How far (Å³ of samples) the check for a closure that splits off a piece (closure_splits_its_side)
// searches before it gives up: larger than the pieces seen split off, small enough to cost little
// (BENCHMARKS.md). A larger piece is left to the next round of repair_outer_genus.
constexpr double kSplitSearchVolume = 500.0;
// ... and at most this many samples (500 Å³ at grids of 0.08 Å and coarser): the search's table and queue,
// about 80 bytes per sample of the budget, stay near 80 MB at the finest grids the command line accepts.
constexpr std::int64_t kSplitSearchMostSamples = std::int64_t{1} << 20;

}  // namespace spheremap::detail
