#include "clusters.hpp"

#include <algorithm>
#include <utility>

#include "sample_state.hpp"

namespace spheremap::detail {

template <typename T>
std::vector<Cluster> find_clusters(RepairRound<T>& round) {
  auto& state = round.state;
  auto left_out = [&](std::int64_t s) {
    return round.inside(s) ? !(state[static_cast<std::size_t>(s)] & kInSolid)
                           : !(state[static_cast<std::size_t>(s)] & kInOutside);
  };
  std::vector<Cluster> clusters;
  std::vector<std::int64_t> stack;
  for (std::int64_t s = 0; s < round.lattice.count(); ++s) {
    if ((state[static_cast<std::size_t>(s)] & kClustered) || !left_out(s)) continue;
    const bool inside = round.inside(s);
    Cluster cluster;
    cluster.closure.kind = inside ? ClosureKind::kCut : ClosureKind::kFill;
    stack.push_back(s);
    state[static_cast<std::size_t>(s)] |= kClustered;
    while (!stack.empty()) {
      const auto v = stack.back();
      stack.pop_back();
      cluster.closure.samples.push_back(v);
      round.lattice.neighbours(v, [&](int, std::int64_t t) {
        if (t < 0 || (state[static_cast<std::size_t>(t)] & kClustered) || round.inside(t) != inside || !left_out(t))
          return;
        state[static_cast<std::size_t>(t)] |= kClustered;
        stack.push_back(t);
      });
    }
    std::sort(cluster.closure.samples.begin(), cluster.closure.samples.end());
    clusters.push_back(std::move(cluster));
  }
  return clusters;
}

template <typename T>
void count_handles(RepairRound<T>& round, std::vector<Cluster>& clusters) {
  auto& state = round.state;
  auto is_fill = [&](std::size_t c) { return clusters[c].closure.kind == ClosureKind::kFill; };
  // The cut clusters on the main piece are marked, so that fills touching them count as on it too.
  std::vector<bool> on_main(clusters.size(), false);
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    if (is_fill(c) || !round.touches(clusters[c].closure.samples, kInSolid)) continue;
    on_main[c] = true;
    for (const auto s : clusters[c].closure.samples) state[static_cast<std::size_t>(s)] |= kMark;
  }
  for (std::size_t c = 0; c < clusters.size(); ++c)
    if (is_fill(c)) on_main[c] = round.touches(clusters[c].closure.samples, kInSolid | kMark);
  for (std::size_t c = 0; c < clusters.size(); ++c) {
    auto& closure = clusters[c].closure;
    if (!is_fill(c))
      for (const auto s : closure.samples) state[static_cast<std::size_t>(s)] &= static_cast<std::uint8_t>(~kMark);
    clusters[c].euler = on_main[c] ? round.euler_change(closure.samples, closure.kind) : 0;
  }
}

std::vector<int> handle_clusters(const std::vector<Cluster>& clusters) {
  std::vector<int> handle_of;
  for (int c = 0; c < static_cast<int>(clusters.size()); ++c)
    if (clusters[static_cast<std::size_t>(c)].euler > 0) handle_of.push_back(c);
  return handle_of;
}

namespace {

// For each handle h, the handles numbered above h whose clusters touch its cluster, ascending.
template <typename T>
std::vector<std::vector<int>> touching_handles(const RepairRound<T>& round, const std::vector<Cluster>& clusters,
                                               const std::vector<int>& handle_of) {
  const int handles = static_cast<int>(handle_of.size());
  std::vector<std::pair<std::int64_t, int>> owner;  // (sample, handle number), sorted
  for (int h = 0; h < handles; ++h)
    for (const auto s : clusters[static_cast<std::size_t>(handle_of[static_cast<std::size_t>(h)])].closure.samples)
      owner.emplace_back(s, h);
  std::sort(owner.begin(), owner.end());
  std::vector<std::vector<int>> touching(static_cast<std::size_t>(handles));
  for (int h = 0; h < handles; ++h) {
    auto& found_here = touching[static_cast<std::size_t>(h)];
    for (const auto s : clusters[static_cast<std::size_t>(handle_of[static_cast<std::size_t>(h)])].closure.samples)
      round.lattice.neighbours(s, [&](int, std::int64_t t) {
        if (t < 0 || !(round.state[static_cast<std::size_t>(t)] & kClustered)) return;
        const auto found = std::lower_bound(owner.begin(), owner.end(), std::make_pair(t, -1));
        if (found != owner.end() && found->first == t && found->second > h) found_here.push_back(found->second);
      });
    std::sort(found_here.begin(), found_here.end());
    found_here.erase(std::unique(found_here.begin(), found_here.end()), found_here.end());
  }
  return touching;
}

}  // namespace

template <typename T>
std::vector<Interaction> cluster_interactions(RepairRound<T>& round, const std::vector<Cluster>& clusters,
                                              const std::vector<int>& handle_of) {
  const auto touching = touching_handles(round, clusters, handle_of);
  T* values = round.field.values.data();
  std::vector<Interaction> interactions;
  for (int h = 0; h < static_cast<int>(handle_of.size()); ++h) {
    for (const int other : touching[static_cast<std::size_t>(h)]) {
      const auto& first = clusters[static_cast<std::size_t>(handle_of[static_cast<std::size_t>(h)])];
      const auto& second = clusters[static_cast<std::size_t>(handle_of[static_cast<std::size_t>(other)])];
      // The second's Euler change with the first closed.
      std::vector<T> original;
      original.reserve(first.closure.samples.size());
      for (const auto s : first.closure.samples)
        original.push_back(values[s]), values[s] = round.moved_value(first.closure.kind);
      const int together = round.euler_change(second.closure.samples, second.closure.kind);
      for (std::size_t k = 0; k < original.size(); ++k) values[first.closure.samples[k]] = original[k];
      // A gain when both are chosen (not seen in practice) is ignored: the penalties must not be negative.
      if (together < second.euler) {
        const bool first_fills = first.closure.kind == ClosureKind::kFill;
        interactions.push_back({first_fills ? other : h, first_fills ? h : other, second.euler - together});
      }
    }
  }
  return interactions;
}

template std::vector<Cluster> find_clusters(RepairRound<double>&);
template std::vector<Cluster> find_clusters(RepairRound<float>&);
template void count_handles(RepairRound<double>&, std::vector<Cluster>&);
template void count_handles(RepairRound<float>&, std::vector<Cluster>&);
template std::vector<Interaction> cluster_interactions(RepairRound<double>&, const std::vector<Cluster>&,
                                                       const std::vector<int>&);
template std::vector<Interaction> cluster_interactions(RepairRound<float>&, const std::vector<Cluster>&,
                                                       const std::vector<int>&);

}  // namespace spheremap::detail
