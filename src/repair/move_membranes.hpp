// Private to the handle repair: moving each handle cluster to a thinner section nearby.
#pragma once

#include <vector>

#include "clusters.hpp"
#include "repair_round.hpp"

namespace spheremap::detail {

// Counts the area change of each handle cluster (euler > 0), and moves it to the thinnest section of its
// handle or tunnel nearby (MembraneMover) when that changes less |area|, removes at least as many handles
// and stays apart from the other clusters of its side. The searches read only what stays fixed until
// closures are applied (the grown sets, the field), so they run in parallel, one mover per thread; the
// checks that follow depend on the clusters moved before (which samples are clustered) and run in order.
template <typename T>
void move_membranes(RepairRound<T>& round, std::vector<Cluster>& clusters);

}  // namespace spheremap::detail
