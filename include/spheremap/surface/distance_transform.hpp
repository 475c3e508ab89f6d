// The exact Euclidean distance transform on a regular grid (stage: surface).
#pragma once

#include <cstdint>

#include "spheremap/surface/grid.hpp"

namespace spheremap {

/// Exact squared Euclidean distance, in grid units², from every sample to the nearest sample where
/// `is_target` is nonzero (Felzenszwalb & Huttenlocher 2012, separable lower envelopes of parabolas):
/// O(samples). Samples farther than any target (no target at all) get +infinity.
/// `threads`: 0 = one per hardware thread; the result does not depend on it.
/// Precondition: is_target.values.size() == is_target.count().
Grid3<double> squared_distance_transform(const Grid3<std::uint8_t>& is_target, int threads = 0);

/// The same transform in place, for any initial values f >= 0 (+infinity allowed): afterwards each
/// sample q holds min over samples p of |q - p|² (grid units²) + f(p). With f = 0 on targets and
/// +infinity elsewhere this is squared_distance_transform without a second grid. Lines are computed in
/// double; with T = float the result is exact as long as the squared distances are integers below 2^24
/// (a 0/infinity start on grids up to 4096 samples per axis). Precondition: values.size() == count().
/// Both throw nothing beyond std::bad_alloc.
template <typename T>
void squared_distance_transform_in_place(Grid3<T>& grid, int threads = 0);

extern template void squared_distance_transform_in_place<double>(Grid3<double>&, int);
extern template void squared_distance_transform_in_place<float>(Grid3<float>&, int);

}  // namespace spheremap
