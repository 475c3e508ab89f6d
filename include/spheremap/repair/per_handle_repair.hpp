// One round of the per-handle repair: a small closure for each handle of the solid's main piece.
#pragma once

#include <cstdint>
#include <vector>

#include "spheremap/repair/closure.hpp"
#include "spheremap/surface/contour.hpp"
#include "spheremap/surface/grid.hpp"

namespace spheremap {

/// What one round of repair_handles applied.
struct PerHandleRepair {
  std::vector<Closure> closures;  // in the order applied
  std::int64_t samples_changed = 0;
  double area_change = 0;  // the sum of the closures' area_change
};

/// Removes the handles of the solid's main piece (the largest inside piece) by small closures, each a cut
/// of a handle or a fill of a tunnel, chosen for the least change of contour area:
/// - Both growths of close_all_handles run; the samples each leaves out are split into connected
///   clusters (membranes). Those that touch the main piece and raise the solid's Euler characteristic
///   (counted exactly on the lattice) remove handles; detached pieces and cavities are left alone.
/// - Each membrane moves to the section of its handle or tunnel with the fewest samples within 4 Å (a
///   minimum vertex cut, maximum_flow) when that changes less |area| and removes at least as many handles.
/// - The set of clusters removes `handles_to_remove` handles (-1: as many as possible) at the least total
///   |area change| (a minimum cut over the clusters, priced by binary search, so that nothing is bought
///   beyond the genus), and is applied cheapest first, each closure only if it still removes handles and
///   splits off no piece and closes no void (searched up to 500 Å³ around it).
/// A closure that splits off a larger piece also raises the Euler characteristic: the caller must check
/// the genus of the result (repair_outer_genus does) and may undo the round (undo_handle_repair).
/// Modifies `field`. Areas as contour_isosurface(field, level, threads, minimum_fraction) measures them.
/// Preconditions and throws: as close_all_handles. Memory: as close_all_handles, plus the clusters and,
/// per membrane moved, 9 bytes per sample of a box around it and its flow network (about 800 bytes per
/// sample within reach), for each of up to `threads` membranes searched at once. Deterministic;
/// independent of `threads`.
PerHandleRepair repair_handles(Grid3<double>& field, double level, double minimum_fraction = kContourMinimumFraction,
                               int threads = 0, int handles_to_remove = -1);
PerHandleRepair repair_handles(Grid3<float>& field, double level, double minimum_fraction = kContourMinimumFraction,
                               int threads = 0, int handles_to_remove = -1);

/// Restores the field values that `repair` (a result of repair_handles on this field) changed.
/// Precondition: the field is the one repaired, unchanged since but by later repairs already undone.
void undo_handle_repair(Grid3<double>& field, const PerHandleRepair& repair);
void undo_handle_repair(Grid3<float>& field, const PerHandleRepair& repair);

}  // namespace spheremap
