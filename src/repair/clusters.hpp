// Private to the handle repair: the clusters of samples the growths left out, and what closing each
// would do.
#pragma once

#include <cstdint>
#include <vector>

#include "repair_round.hpp"
#include "spheremap/repair/closure.hpp"

namespace spheremap::detail {

// A connected cluster of samples left out by the growth of its side (a membrane, a detached piece, a
// cavity), and what closing it would do, alone, to the field of this round.
struct Cluster {
  Closure closure;        // kind and samples; handles_removed and area_change once applied
  int euler = 0;          // change of the solid's Euler characteristic (handles removed when positive)
  double area = 0;        // Å², change of the contour's area
  std::int64_t cost = 0;  // |area| in thousandths of Å²: what the selection minimises
};

// A cut and a fill that touch (the fill's membrane ends on the cut's): after one, the other may no longer
// raise the Euler characteristic as much, so choosing both loses `penalty` handles. cut and fill are
// handle numbers (indices into handle_clusters).
struct Interaction {
  int cut = 0, fill = 0;
  std::int64_t penalty = 0;
};

// The clusters of left-out samples (connected through samples on the same side that are also left out),
// by their smallest sample, each marked kClustered; euler, area and cost not yet counted.
template <typename T>
std::vector<Cluster> find_clusters(RepairRound<T>& round);

// Counts the Euler change of the clusters that touch the solid's main piece (the one grown, and the cut
// clusters on it); the others (whole detached pieces, membranes across tunnels through one) keep 0 and
// are left as they are: deleting a piece of genus 2 or more would also raise the Euler characteristic.
template <typename T>
void count_handles(RepairRound<T>& round, std::vector<Cluster>& clusters);

// The clusters that remove handles (euler > 0): their indices in `clusters`, ascending.
std::vector<int> handle_clusters(const std::vector<Cluster>& clusters);

// The pairs of handle clusters whose closures interact. Clusters of one side never touch, so every
// simplex of the lattice meets at most one cut and one fill, and the Euler change of any set of clusters
// is exactly the sum of their own plus these pairwise losses.
template <typename T>
std::vector<Interaction> cluster_interactions(RepairRound<T>& round, const std::vector<Cluster>& clusters,
                                              const std::vector<int>& handle_of);

}  // namespace spheremap::detail
