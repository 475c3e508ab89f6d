// The global fallback of the handle repair: every handle cut, or every tunnel filled.
#pragma once

#include "spheremap/repair/closure.hpp"
#include "spheremap/surface/contour.hpp"
#include "spheremap/surface/grid.hpp"

namespace spheremap {

/// Makes the solid {field > level} a topological ball, as seen by contour_isosurface (the Freudenthal
/// triangulation of the grid), by topology-preserving growth (Kriegeskorte & Goebel 2001; Han, Xu &
/// Prince 2002) in two ways, and applies the one that moves fewer samples as one closure:
/// - cut: grow a set from the deepest inside sample of the largest inside piece, adding inside samples by
///   decreasing value only when simple (their link meets the set in a non-empty connected part whose
///   complement in the link is non-empty and connected), so the set stays a ball; the inside samples
///   never added (where a loop would close; other pieces too) are cut;
/// - fill: the same growth of the outside from the whole grid border, by decreasing distance to the
///   solid; the outside samples never added (spanning tunnels, and cavities) are filled.
/// Modifies `field`; returns the closure (original_values empty, handles_removed 0; area_change as
/// contour_isosurface(field, level, threads, minimum_fraction) measures it).
/// Preconditions: some sample > level, every border sample <= level. Throws std::invalid_argument
/// otherwise.
/// Memory: one byte of state per sample, plus (while the growths run) two bytes of distance per sample
/// and the queues (4 bytes per queued sample). `threads` (0: one per hardware thread) is used for the
/// distance, and with two or more the two growths run at once; the result does not depend on it.
Closure close_all_handles(Grid3<double>& field, double level, double minimum_fraction = kContourMinimumFraction,
                          int threads = 0);
Closure close_all_handles(Grid3<float>& field, double level, double minimum_fraction = kContourMinimumFraction,
                          int threads = 0);

}  // namespace spheremap
