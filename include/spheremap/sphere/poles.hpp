// The default poles of the map: the two vertices farthest apart (stage: sphere).
#pragma once

#include <cstdint>
#include <utility>
#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// The two vertices farthest apart (exact maximum of the squared distances as computed in double),
/// found with a k-d tree and branch-and-bound instead of all pairs. Ties go to the smallest index
/// pair; the first index is smaller than the second.
/// Preconditions: at least 2 positions, all finite. Throws std::invalid_argument with fewer than 2.
std::pair<std::int32_t, std::int32_t> farthest_pair(const std::vector<Vec3>& positions);

}  // namespace spheremap
