// Private to the handle repair: how far each outside sample lies from the solid, which orders the
// outside's growth.
#pragma once

#include <cstdint>
#include <vector>

#include "spheremap/surface/grid.hpp"

namespace spheremap::detail {

// The cap of outside_depth: two bytes per sample.
constexpr std::uint32_t kDepthCap = 65535;

// The squared lattice distance (grid units², an integer) from each outside sample of {field > level} to
// the nearest inside sample, capped at kDepthCap (exact below it); 0 for inside samples. The SES field is
// flat (-probe) wherever a probe fits, so it cannot order the outside growth; this distance makes the two
// fronts entering a tunnel meet at its narrowest section. `threads` >= 1. Deterministic.
template <typename T>
std::vector<std::uint16_t> outside_depth(const Grid3<T>& field, double level, int threads);

}  // namespace spheremap::detail
