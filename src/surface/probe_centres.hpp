// Private to the surface stage: probe centres on the SAS surface itself (the solvent-accessible surface,
// every atom's sphere enlarged by the probe), which keep re-entrant regions of the SES accurate below the
// grid spacing, and the decision which pockets of the lattice a probe reaches from outside.
#pragma once

#include <vector>

#include "../util/stage_timer.hpp"
#include "pockets.hpp"
#include "spheremap/molecule/structure.hpp"
#include "spheremap/surface/grid.hpp"

namespace spheremap::detail {

/// Probe centres on the SAS surface (see solvent_excluded_field), in grid coordinates, sorted so that
/// consecutive centres touch the same part of the grid; decides on the way which pockets of `field`
/// (labelled by flood_and_label_pockets) a probe reaches from outside, and resolves them: 0 (probe
/// centres) or +infinity.
///
/// A probe rolling on the SAS from outside (as MSMS does) goes along its edges, the exposed arcs of the
/// circles where two enlarged spheres meet, from arc to arc through the vertices where three meet. The
/// lattice misses passages narrower than a step, but exposed arcs thread them (an open window between
/// three enlarged spheres is crossed by the whole arcs of their three circles, none of which the third
/// sphere covers). So the exposed arcs are computed exactly (angular intervals of each circle left
/// uncovered by the other spheres), joined at their shared vertices, and joined to the outside or a
/// pocket when one of their samples sees an outside sample of it among the 27 around its nearest sample
/// along a segment outside every enlarged sphere. Pockets and arcs joined to the outside carve; the
/// others do not (with carve_cavities, everything joined to an outside sample carves).
///
/// Laps "neighbours", "arcs", "pockets" and "projections" on `clock`.
/// Preconditions: `atoms` not empty, radii positive; `field` as flood_and_label_pockets left it, with
/// `pockets` its result; threads >= 1. Multithreaded; the result does not depend on the thread count.
template <typename T>
std::vector<Vec3> surface_probe_centres(Grid3<T>& field, const std::vector<Atom>& atoms, double probe,
                                        const Pockets& pockets, bool carve_cavities, int threads, StageTimer& clock);

}  // namespace spheremap::detail
