#include "repair_round.hpp"

#include "../util/parallel.hpp"
#include "area_change.hpp"
#include "euler_change.hpp"
#include "growth.hpp"

namespace spheremap::detail {

template <typename T>
RepairRound<T>::RepairRound(Grid3<T>& grid, double level_, double minimum_fraction_, int threads_)
    : field(grid),
      level(level_),
      minimum_fraction(minimum_fraction_),
      threads(surface_threads(threads_)),
      lattice(grid.size),
      state(grow_both(grid, level_, threads)),
      moved_value(level_, grid.spacing) {}

template <typename T>
bool RepairRound<T>::touches(const std::vector<std::int64_t>& samples, std::uint8_t bits) const {
  for (const auto s : samples) {
    bool found = false;
    lattice.neighbours(
        s, [&](int, std::int64_t t) { found = found || (t >= 0 && (state[static_cast<std::size_t>(t)] & bits)); });
    if (found) return true;
  }
  return false;
}

template <typename T>
int RepairRound<T>::euler_change(const std::vector<std::int64_t>& samples, ClosureKind kind) {
  return detail::euler_change(field, level, samples, kind, state.data());
}

template <typename T>
double RepairRound<T>::area_change(const std::vector<std::int64_t>& samples, ClosureKind kind) {
  return detail::area_change(field, level, minimum_fraction, samples, moved_value(kind));
}

template struct RepairRound<double>;
template struct RepairRound<float>;

}  // namespace spheremap::detail
