// Private to the handle repair: which handle clusters to close.
#pragma once

#include <vector>

#include "clusters.hpp"

namespace spheremap::detail {

struct Selection {
  std::vector<bool> chosen;  // per handle number (index into handle_of)
  int removes = 0;           // handles the chosen set removes, interactions counted
};

// The set of handle clusters that removes `handles_to_remove` handles (-1: as many as possible) at the
// least total cost. Each cluster is worth euler x price - cost, and a chosen interacting pair loses its
// penalty x price; for a given price the best set is a minimum cut (maximum_flow). The price is the
// smallest for which that set removes enough handles (binary search: the count grows with the price), so
// that no expensive closure is bought for a count beyond the genus, which only enclosed voids or
// split-off pieces can make up. If no price reaches it, the most handles. Sets the handle clusters' cost.
Selection select_clusters(std::vector<Cluster>& clusters, const std::vector<int>& handle_of,
                          const std::vector<Interaction>& interactions, int handles_to_remove);

}  // namespace spheremap::detail
