// Private to the handle repair: applying the chosen closures of a round.
#pragma once

#include <vector>

#include "cluster_selection.hpp"
#include "clusters.hpp"
#include "repair_round.hpp"
#include "spheremap/repair/per_handle_repair.hpp"

namespace spheremap::detail {

// Applies the handle clusters' closures, the chosen ones first, cheapest first within each group, each
// only if it still raises the Euler characteristic on the field as it then is and splits off no piece
// and closes no void (closure_splits_its_side): if a chosen one does not, the others complete the count.
// Stops at the count the selection removes, and at `handles_to_remove` (>= 0): a larger count can only
// come from closures that enclose voids or split off pieces (a connected solid without voids has an Euler
// characteristic of at most 1). Takes the clusters' closures.
template <typename T>
PerHandleRepair apply_closures(RepairRound<T>& round, std::vector<Cluster>& clusters, const std::vector<int>& handle_of,
                               const Selection& selection, int handles_to_remove);

}  // namespace spheremap::detail
