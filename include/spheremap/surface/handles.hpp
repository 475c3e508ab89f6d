// Removing handles from a sampled solid so that its contour has genus 0 (stage: surface).
#pragma once

#include <cstdint>
#include <vector>

#include "spheremap/surface/grid.hpp"

namespace spheremap {

struct HandleCut {
  bool filled = false;                        // true: tunnels were filled; false: handles were cut
  std::int64_t samples_removed = 0;           // samples whose side changed
  std::vector<std::int64_t> removed_samples;  // their grid indices, ascending
};

/// Makes the solid {field > level} a topological ball, as seen by contour_isosurface (the Freudenthal
/// triangulation of the grid), by topology-preserving growth (Kriegeskorte & Goebel 2001; Han, Xu &
/// Prince 2002) in two ways, keeping the one that changes fewer samples:
/// - cut: grow a set from the deepest inside sample, adding inside samples by decreasing value (ties by
///   index) only when simple — their link (14 lattice neighbours, a triangulated sphere) meets the set
///   in a non-empty connected part whose complement in the link is non-empty and connected (for a full
///   subcomplex of a 2-sphere this is contractibility, by Alexander duality), so the set stays a ball;
///   inside samples never added (where a loop would close) go just below `level`; other pieces too;
/// - fill: the same growth of the outside from the whole grid border, by increasing value; outside
///   samples never added (spanning tunnels, and cavities) go just above `level`.
/// Preconditions: some sample > level, every border sample <= level. Throws std::invalid_argument
/// otherwise. Returns what changed; modifies `field`.
HandleCut cut_handles(Grid3<double>& field, double level);

}  // namespace spheremap
