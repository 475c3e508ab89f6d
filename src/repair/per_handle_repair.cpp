#include "spheremap/repair/per_handle_repair.hpp"

#include "apply_closures.hpp"
#include "cluster_selection.hpp"
#include "clusters.hpp"
#include "move_membranes.hpp"
#include "repair_round.hpp"

namespace spheremap {
namespace {

template <typename T>
PerHandleRepair repair_handles_impl(Grid3<T>& field, double level, double minimum_fraction, int threads,
                                    int handles_to_remove) {
  detail::RepairRound<T> round(field, level, minimum_fraction, threads);
  auto clusters = detail::find_clusters(round);
  detail::count_handles(round, clusters);
  detail::move_membranes(round, clusters);
  const auto handle_of = detail::handle_clusters(clusters);
  if (handle_of.empty()) return {};
  const auto interactions = detail::cluster_interactions(round, clusters, handle_of);
  const auto selection = detail::select_clusters(clusters, handle_of, interactions, handles_to_remove);
  return detail::apply_closures(round, clusters, handle_of, selection, handles_to_remove);
}

template <typename T>
void undo_impl(Grid3<T>& field, const PerHandleRepair& repair) {
  for (auto closure = repair.closures.rbegin(); closure != repair.closures.rend(); ++closure)
    for (std::size_t k = 0; k < closure->samples.size(); ++k)
      field.values[static_cast<std::size_t>(closure->samples[k])] = static_cast<T>(closure->original_values[k]);
}

}  // namespace

PerHandleRepair repair_handles(Grid3<double>& field, double level, double minimum_fraction, int threads,
                               int handles_to_remove) {
  return repair_handles_impl(field, level, minimum_fraction, threads, handles_to_remove);
}
PerHandleRepair repair_handles(Grid3<float>& field, double level, double minimum_fraction, int threads,
                               int handles_to_remove) {
  return repair_handles_impl(field, level, minimum_fraction, threads, handles_to_remove);
}
void undo_handle_repair(Grid3<double>& field, const PerHandleRepair& repair) { undo_impl(field, repair); }
void undo_handle_repair(Grid3<float>& field, const PerHandleRepair& repair) { undo_impl(field, repair); }

}  // namespace spheremap
