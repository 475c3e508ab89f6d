// Private to the library (properties): sums of charges over a power of the distance, exact and by a
// treecode with Cartesian multipole expansions fitted to the kernel.
#pragma once

#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap::detail {

/// The kernel 1/r^(2a): 1/r (a = 1/2, a constant dielectric) or 1/r² (a = 1, ε = κr).
enum class PowerKernel { kInverseDistance, kInverseSquare };

struct TreecodeParameters {
  /// A source cell and a target cell interact through expansions when r_source + r_target < theta * the
  /// distance of their centres (r: the largest distance from a centre to its points); the truncation
  /// error then falls about as theta^(order + 1).
  double theta = 0.4;
  int order = 3;               // highest order of the expansions, 0 (charge) ... kMaxTreecodeOrder
  int source_leaf_size = 32;   // sources per leaf of the source tree
  int target_leaf_size = 128;  // targets per leaf of the target tree
  int threads = 0;             // 0: one per hardware thread
};

inline constexpr int kMaxTreecodeOrder = 6;

/// For every point x: Σ_i charges[i] * K(|x - positions[i]|), summed in the order of `positions`,
/// over blocks of points on `threads` threads (the same bytes whatever the thread count).
/// Preconditions: positions.size() == charges.size(); no point on a source (that term is infinite).
std::vector<double> direct_power_sum(const std::vector<Vec3>& positions, const std::vector<double>& charges,
                                     const std::vector<Vec3>& points, PowerKernel kernel, int threads);

/// The same sum by a treecode: sources and targets each in a binary tree of boxes split at the median of
/// their longest side; a dual-tree walk expands the pairs of cells far enough apart (source moments into
/// target local expansions, passed down to the target leaves) and sums the near leaf pairs exactly.
/// Deterministic: every target's terms are added in an order fixed by the input alone.
/// Preconditions: as direct_power_sum; 0 <= order <= kMaxTreecodeOrder, 0 < theta < 1, leaf sizes >= 1;
/// throws std::invalid_argument otherwise.
std::vector<double> treecode_power_sum(const std::vector<Vec3>& positions, const std::vector<double>& charges,
                                       const std::vector<Vec3>& points, PowerKernel kernel,
                                       const TreecodeParameters& parameters);

}  // namespace spheremap::detail
