#include "move_membranes.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <utility>

#include "../util/parallel.hpp"
#include "membrane_mover.hpp"
#include "sample_state.hpp"
#include "tuning.hpp"

namespace spheremap::detail {
namespace {

// The new membrane of each handle cluster, where MembraneMover finds one (else empty).
template <typename T>
std::vector<std::vector<std::int64_t>> search_membranes(const RepairRound<T>& round,
                                                        const std::vector<Cluster>& clusters) {
  const int reach = std::max(2, static_cast<int>(std::lround(kMembraneReach / round.field.spacing)));
  std::vector<std::vector<std::int64_t>> moved_of(clusters.size());
  std::vector<std::unique_ptr<MembraneMover>> movers(static_cast<std::size_t>(round.threads));
  parallel_chunks(static_cast<std::int64_t>(clusters.size()), round.threads, [&](std::int64_t k, int worker) {
    const auto& c = clusters[static_cast<std::size_t>(k)];
    if (c.euler <= 0) return;
    auto& mover = movers[static_cast<std::size_t>(worker)];
    if (!mover) mover = std::make_unique<MembraneMover>(round.lattice, round.field.size, round.state.data(), reach);
    const bool cut = c.closure.kind == ClosureKind::kCut;
    auto moved = mover->move(c.closure.samples, cut ? kInSolid : kInOutside);
    if (moved.empty() || !mover->complete(moved, cut)) return;
    moved_of[static_cast<std::size_t>(k)] = std::move(moved);
  });
  return moved_of;
}

// Whether no sample of `moved` touches a clustered sample of its side other than those of `cluster`.
template <typename T>
bool apart_from_other_clusters(RepairRound<T>& round, const Cluster& cluster, const std::vector<std::int64_t>& moved) {
  auto& state = round.state;
  const bool inside = cluster.closure.kind == ClosureKind::kCut;
  for (const auto s : cluster.closure.samples) state[static_cast<std::size_t>(s)] |= kMark;
  bool apart = true;
  for (const auto s : moved) {
    round.lattice.neighbours(s, [&](int, std::int64_t t) {
      if (t >= 0 && (state[static_cast<std::size_t>(t)] & (kClustered | kMark)) == kClustered &&
          round.inside(t) == inside)
        apart = false;
    });
  }
  for (const auto s : cluster.closure.samples) state[static_cast<std::size_t>(s)] &= static_cast<std::uint8_t>(~kMark);
  return apart;
}

}  // namespace

template <typename T>
void move_membranes(RepairRound<T>& round, std::vector<Cluster>& clusters) {
  auto moved_of = search_membranes(round, clusters);
  for (std::size_t k = 0; k < clusters.size(); ++k) {
    auto& c = clusters[k];
    if (c.euler <= 0) continue;
    c.area = round.area_change(c.closure.samples, c.closure.kind);
    auto moved = std::move(moved_of[k]);
    if (moved.empty() || !apart_from_other_clusters(round, c, moved)) continue;
    // A section through a junction of tunnels (or handles) may remove more at once than the membrane it
    // replaces (it encloses no pocket and splits off no piece, so its Euler change counts handles only):
    // the selection weighs it as such; one that removes fewer is not taken.
    const int moved_euler = round.euler_change(moved, c.closure.kind);
    if (moved_euler < c.euler) continue;
    const double moved_area = round.area_change(moved, c.closure.kind);
    if (std::abs(moved_area) >= std::abs(c.area)) continue;
    for (const auto s : c.closure.samples)
      round.state[static_cast<std::size_t>(s)] &= static_cast<std::uint8_t>(~kClustered);
    for (const auto s : moved) round.state[static_cast<std::size_t>(s)] |= kClustered;
    c.closure.samples = std::move(moved);
    c.euler = moved_euler;
    c.area = moved_area;
  }
}

template void move_membranes(RepairRound<double>&, std::vector<Cluster>&);
template void move_membranes(RepairRound<float>&, std::vector<Cluster>&);

}  // namespace spheremap::detail
