#include "spheremap/repair/handle_repair.hpp"

#include <utility>

#include "spheremap/surface/contour.hpp"

namespace spheremap {
namespace {

// Rounds of repair_handles before the global closure: interactions beyond those counted can leave
// handles after a round (a closure that splits off a piece larger than closure_splits_its_side searches
// counts as a handle removed; the clusters left out may not complete the count), and the growths of the
// next round, on the changed field, find them.
constexpr int kRounds = 4;

// The genus of the largest component of the field's contour; the contour is kept in *mesh if given, with
// its components in *kept_components when its genus is 0.
template <typename T>
int contour_genus(const Grid3<T>& field, double level, int threads, double minimum_fraction, Mesh* mesh,
                  std::optional<std::vector<MeshComponent>>* kept_components = nullptr) {
  Mesh contour = contour_isosurface(field, level, threads, minimum_fraction);
  auto components = mesh_components(contour);
  if (mesh) *mesh = std::move(contour);
  const int genus = components.empty() ? 0 : components.front().genus;
  if (kept_components && genus == 0) *kept_components = std::move(components);
  return genus;
}

// Rounds of repair_handles until the outer surface has genus 0 (result.method kPerHandle) or a round
// changes nothing (the field keeps the rounds' closures, listed in result.closures).
template <typename T>
void repair_per_handle(Grid3<T>& field, double level, int threads, double minimum_fraction, Mesh* final_contour,
                       OuterGenusRepair& result) {
  int genus = result.outer_genus_before;
  for (int round = 0; round < kRounds; ++round) {
    // The previous round's contour is freed before this round's growths: at fine grids it is large.
    if (final_contour) *final_contour = Mesh{};
    PerHandleRepair more = repair_handles(field, level, minimum_fraction, threads, genus);
    const bool changed = !more.closures.empty();
    result.samples_changed += more.samples_changed;
    result.area_change += more.area_change;
    for (auto& closure : more.closures) result.closures.push_back(std::move(closure));
    genus = contour_genus(field, level, threads, minimum_fraction, final_contour,
                          final_contour ? &result.final_components : nullptr);
    if (genus == 0) {
      result.method = RepairMethod::kPerHandle;
      result.rounds = round + 1;
      return;
    }
    if (!changed) return;
  }
}

template <typename T>
OuterGenusRepair repair_outer_genus_impl(Grid3<T>& field, double level, int genus_before, int threads,
                                         double minimum_fraction, Mesh* final_contour) {
  OuterGenusRepair result;
  result.outer_genus_before =
      genus_before >= 0 ? genus_before : contour_genus(field, level, threads, minimum_fraction, nullptr);
  if (result.outer_genus_before == 0) {
    if (final_contour) *final_contour = contour_isosurface(field, level, threads, minimum_fraction);
    return result;
  }
  repair_per_handle(field, level, threads, minimum_fraction, final_contour, result);
  if (result.method == RepairMethod::kPerHandle) return result;
  // The per-handle rounds left handles: undone, and the global closure instead.
  undo_handle_repair(field, PerHandleRepair{std::move(result.closures), 0, 0});
  result.closures.clear();
  result.area_change = 0;
  Closure global = close_all_handles(field, level, minimum_fraction, threads);
  result.method = global.kind == ClosureKind::kFill ? RepairMethod::kGlobalFill : RepairMethod::kGlobalCut;
  result.samples_changed = static_cast<std::int64_t>(global.samples.size());
  result.area_change = global.area_change;
  global.handles_removed = result.outer_genus_before;
  if (!global.samples.empty()) result.closures.push_back(std::move(global));
  if (final_contour) *final_contour = contour_isosurface(field, level, threads, minimum_fraction);
  return result;
}

}  // namespace

const char* to_string(RepairMethod method) {
  switch (method) {
    case RepairMethod::kPerHandle: return "per-handle";
    case RepairMethod::kGlobalFill: return "fill";
    case RepairMethod::kGlobalCut: return "cut";
    case RepairMethod::kNone: break;
  }
  return "none";
}

OuterGenusRepair repair_outer_genus(Grid3<double>& field, double level, int threads) {
  return repair_outer_genus_impl(field, level, -1, threads, kContourMinimumFraction, nullptr);
}
OuterGenusRepair repair_outer_genus(Grid3<float>& field, double level, int threads) {
  return repair_outer_genus_impl(field, level, -1, threads, kContourMinimumFraction, nullptr);
}
OuterGenusRepair repair_outer_genus(Grid3<float>& field, double level, int outer_genus_before, int threads,
                                    double minimum_fraction, Mesh& final_contour) {
  return repair_outer_genus_impl(field, level, outer_genus_before, threads, minimum_fraction, &final_contour);
}

}  // namespace spheremap
