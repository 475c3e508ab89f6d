#include "spheremap/repair/global_closure.hpp"

#include <utility>

#include "area_change.hpp"
#include "growth.hpp"
#include "moved_sample_values.hpp"
#include "sample_state.hpp"

namespace spheremap {
namespace {

template <typename T>
Closure close_all_handles_impl(Grid3<T>& field, double level, double minimum_fraction, int threads) {
  const auto state = detail::grow_both(field, level, threads);
  std::vector<std::int64_t> cuts, fills;
  for (std::int64_t s = 0; s < field.count(); ++s) {
    if (field.values[s] > level && !(state[s] & detail::kInSolid)) cuts.push_back(s);
    if (field.values[s] <= level && !(state[s] & detail::kInOutside)) fills.push_back(s);
  }
  Closure closure;
  // The smaller closure wins: cutting every handle, or filling every tunnel (and cavity).
  closure.kind = fills.size() < cuts.size() ? ClosureKind::kFill : ClosureKind::kCut;
  const detail::MovedSampleValues<T> moved_value(level, field.spacing);
  const T value = moved_value(closure.kind);
  auto& chosen = closure.kind == ClosureKind::kFill ? fills : cuts;
  closure.area_change = detail::area_change(field, level, minimum_fraction, chosen, value);
  for (const auto s : chosen) field.values[s] = value;
  closure.samples = std::move(chosen);
  return closure;
}

}  // namespace

Closure close_all_handles(Grid3<double>& field, double level, double minimum_fraction, int threads) {
  return close_all_handles_impl(field, level, minimum_fraction, threads);
}
Closure close_all_handles(Grid3<float>& field, double level, double minimum_fraction, int threads) {
  return close_all_handles_impl(field, level, minimum_fraction, threads);
}

}  // namespace spheremap
