// Private to the handle repair: what the steps of one round of repair_handles share.
#pragma once

#include <cstdint>
#include <vector>

#include "lattice.hpp"
#include "moved_sample_values.hpp"
#include "spheremap/repair/closure.hpp"
#include "spheremap/surface/grid.hpp"

namespace spheremap::detail {

// The field of one round, both growths of it (the state bytes, sample_state.hpp), and the measures of a
// closure on it.
template <typename T>
struct RepairRound {
  // Runs both growths (grow_both). `threads`: 0 for one per hardware thread.
  RepairRound(Grid3<T>& field, double level, double minimum_fraction, int threads);

  [[nodiscard]] bool inside(std::int64_t s) const { return field.values[static_cast<std::size_t>(s)] > level; }
  // Whether a neighbour of one of `samples` has one of `bits` in its state.
  [[nodiscard]] bool touches(const std::vector<std::int64_t>& samples, std::uint8_t bits) const;
  // What closing `samples` (all on the side the closure leaves) would change on the field as it is now.
  int euler_change(const std::vector<std::int64_t>& samples, ClosureKind kind);
  double area_change(const std::vector<std::int64_t>& samples, ClosureKind kind);

  Grid3<T>& field;
  double level, minimum_fraction;
  int threads;  // at least 1
  Lattice lattice;
  std::vector<std::uint8_t> state;
  MovedSampleValues<T> moved_value;  // what a closure's samples become
};

}  // namespace spheremap::detail
