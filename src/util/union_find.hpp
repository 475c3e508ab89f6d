// Private to the library (util/): union-find on dense integer nodes. The smaller root wins every join, so
// each set's root is its smallest node whatever the order of the joins (deterministic results).
#pragma once

#include <algorithm>
#include <cstddef>
#include <vector>

namespace spheremap::detail {

template <typename Index>
class UnionFind {
 public:
  /// Nodes [0, n), each its own set.
  explicit UnionFind(std::size_t n) : parent_(n) {
    for (std::size_t v = 0; v < n; ++v) parent_[v] = static_cast<Index>(v);
  }
  /// The root of v's set (path halving). Precondition: v in [0, n).
  Index find(Index v) {
    while (parent_[static_cast<std::size_t>(v)] != v) {
      auto& p = parent_[static_cast<std::size_t>(v)];
      p = parent_[static_cast<std::size_t>(p)];
      v = p;
    }
    return v;
  }
  /// Merges the sets of a and b. Preconditions: a and b in [0, n).
  void join(Index a, Index b) {
    a = find(a), b = find(b);
    if (a != b) parent_[static_cast<std::size_t>(std::max(a, b))] = std::min(a, b);
  }

 private:
  std::vector<Index> parent_;
};

}  // namespace spheremap::detail
