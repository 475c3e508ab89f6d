#include "cluster_selection.hpp"

#include <cmath>

#include "spheremap/graph/max_flow.hpp"

namespace spheremap::detail {
namespace {

// The best set of clusters when each has a value (weight, possibly negative) and some pairs of a cut and
// a fill lose value when both are chosen (penalty >= 0): maximise the chosen weights minus the penalties
// of chosen pairs. With the fills' choice flipped this is a submodular minimisation, i.e. a minimum cut
// (chosen cuts on the source side, chosen fills on the sink side; a pair's penalty is an arc from the cut
// to the fill). Of several best sets, the one of the smallest minimum cut.
std::vector<bool> best_selection(const std::vector<bool>& is_fill, const std::vector<std::int64_t>& weight,
                                 const std::vector<Interaction>& interactions) {
  const auto n = static_cast<std::int32_t>(weight.size());
  const std::int32_t source = n, sink = n + 1;
  FlowNetwork network{n + 2, {}};
  auto add = [&](std::int32_t a, std::int32_t b, std::int64_t capacity) {
    if (capacity > 0) network.arcs.push_back({a, b, capacity});
  };
  // Not choosing a cluster of positive weight loses it; choosing one of negative weight costs it.
  for (std::int32_t v = 0; v < n; ++v) {
    const auto w = weight[static_cast<std::size_t>(v)];
    if (is_fill[static_cast<std::size_t>(v)])
      w >= 0 ? add(v, sink, w) : add(source, v, -w);
    else
      w >= 0 ? add(source, v, w) : add(v, sink, -w);
  }
  for (const auto& i : interactions) add(i.cut, i.fill, i.penalty);
  const MaxFlow flow = maximum_flow(network, source, sink);
  // Chosen: the cuts on the source side, and the fills not.
  std::vector<bool> chosen(static_cast<std::size_t>(n));
  for (std::int32_t v = 0; v < n; ++v) {
    const bool reached = flow.source_side[static_cast<std::size_t>(v)] != 0;
    chosen[static_cast<std::size_t>(v)] = is_fill[static_cast<std::size_t>(v)] ? !reached : reached;
  }
  return chosen;
}

}  // namespace

Selection select_clusters(std::vector<Cluster>& clusters, const std::vector<int>& handle_of,
                          const std::vector<Interaction>& interactions, int handles_to_remove) {
  const int handles = static_cast<int>(handle_of.size());
  auto cluster = [&](int h) -> Cluster& {
    return clusters[static_cast<std::size_t>(handle_of[static_cast<std::size_t>(h)])];
  };
  std::vector<bool> is_fill(static_cast<std::size_t>(handles));
  std::int64_t most_cost = 1;
  for (int h = 0; h < handles; ++h) {
    auto& c = cluster(h);
    c.cost = std::llround(std::abs(c.area) * 1000);
    most_cost += c.cost;
    is_fill[static_cast<std::size_t>(h)] = c.closure.kind == ClosureKind::kFill;
  }
  auto select = [&](std::int64_t price) {
    std::vector<std::int64_t> weight(static_cast<std::size_t>(handles));
    for (int h = 0; h < handles; ++h) weight[static_cast<std::size_t>(h)] = cluster(h).euler * price - cluster(h).cost;
    auto priced = interactions;
    for (auto& i : priced) i.penalty *= price;
    Selection selection{best_selection(is_fill, weight, priced), 0};
    for (int h = 0; h < handles; ++h)
      if (selection.chosen[static_cast<std::size_t>(h)]) selection.removes += cluster(h).euler;
    for (const auto& i : interactions)
      if (selection.chosen[static_cast<std::size_t>(i.cut)] && selection.chosen[static_cast<std::size_t>(i.fill)])
        selection.removes -= static_cast<int>(i.penalty);
    return selection;
  };
  Selection selection = select(most_cost);
  if (handles_to_remove >= 0 && selection.removes > handles_to_remove) {
    std::int64_t low = 0, high = most_cost;  // select(high) removes enough; select(low) does not
    while (high - low > 1) {
      const std::int64_t middle = low + (high - low) / 2;
      (select(middle).removes >= handles_to_remove ? high : low) = middle;
    }
    selection = select(high);
  }
  return selection;
}

}  // namespace spheremap::detail
