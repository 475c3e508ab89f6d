#include "apply_closures.hpp"

#include <algorithm>
#include <cmath>
#include <utility>

#include "splits_its_side.hpp"
#include "tuning.hpp"

namespace spheremap::detail {
namespace {

// Handle numbers, the chosen first, then by cost, then by first sample.
std::vector<int> closing_order(const std::vector<Cluster>& clusters, const std::vector<int>& handle_of,
                               const Selection& selection) {
  std::vector<int> order(handle_of.size());
  for (std::size_t h = 0; h < order.size(); ++h) order[h] = static_cast<int>(h);
  auto cheaper = [&](int a, int b) {
    const auto& ca = clusters[static_cast<std::size_t>(handle_of[static_cast<std::size_t>(a)])];
    const auto& cb = clusters[static_cast<std::size_t>(handle_of[static_cast<std::size_t>(b)])];
    if (ca.cost != cb.cost) return ca.cost < cb.cost;
    return ca.closure.samples.front() < cb.closure.samples.front();
  };
  const auto& chosen = selection.chosen;
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    if (chosen[static_cast<std::size_t>(a)] != chosen[static_cast<std::size_t>(b)])
      return static_cast<bool>(chosen[static_cast<std::size_t>(a)]);
    return cheaper(a, b);
  });
  return order;
}

template <typename T>
void restore(T* values, const Closure& closure) {
  for (std::size_t k = 0; k < closure.samples.size(); ++k)
    values[closure.samples[k]] = static_cast<T>(closure.original_values[k]);
}

}  // namespace

template <typename T>
PerHandleRepair apply_closures(RepairRound<T>& round, std::vector<Cluster>& clusters, const std::vector<int>& handle_of,
                               const Selection& selection, int handles_to_remove) {
  T* values = round.field.values.data();
  int goal = selection.removes, removed = 0;
  if (handles_to_remove >= 0) goal = std::min(goal, handles_to_remove);
  const auto split_search_budget = std::min<std::int64_t>(
      static_cast<std::int64_t>(std::ceil(kSplitSearchVolume / std::pow(round.field.spacing, 3))),
      kSplitSearchMostSamples);
  PerHandleRepair repair;
  for (const int h : closing_order(clusters, handle_of, selection)) {
    if (removed >= goal) break;
    auto& closure = clusters[static_cast<std::size_t>(handle_of[static_cast<std::size_t>(h)])].closure;
    closure.handles_removed = round.euler_change(closure.samples, closure.kind);
    if (closure.handles_removed <= 0) continue;
    closure.area_change = round.area_change(closure.samples, closure.kind);
    closure.original_values.reserve(closure.samples.size());
    for (const auto v : closure.samples) {
      closure.original_values.push_back(static_cast<double>(values[v]));
      values[v] = round.moved_value(closure.kind);
    }
    // A closure can raise the Euler characteristic by splitting off a piece of the solid, or closing a
    // pocket of the outside into a void, instead of removing a handle: the second of two cuts across one
    // ring, the second of two fills across one pipe. It is not applied: it would drop the piece or the
    // pocket's lining from the outer surface and leave the handle it was counted for, which the clusters
    // not chosen then remove if they can (else the next round).
    if (closure_splits_its_side(round.field, round.level, closure.samples, closure.kind, split_search_budget)) {
      restore(values, closure);
      closure.original_values.clear();
      continue;
    }
    removed += closure.handles_removed;
    repair.samples_changed += static_cast<std::int64_t>(closure.samples.size());
    repair.area_change += closure.area_change;
    repair.closures.push_back(std::move(closure));
  }
  return repair;
}

template PerHandleRepair apply_closures(RepairRound<double>&, std::vector<Cluster>&, const std::vector<int>&,
                                        const Selection&, int);
template PerHandleRepair apply_closures(RepairRound<float>&, std::vector<Cluster>&, const std::vector<int>&,
                                        const Selection&, int);

}  // namespace spheremap::detail
