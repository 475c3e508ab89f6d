#include <gtest/gtest.h>

#include <algorithm>
#include <cstdint>
#include <numeric>
#include <random>
#include <utility>
#include <vector>

#include "../../src/util/union_find.hpp"

namespace spheremap {
namespace {

TEST(UnionFind, EachSetsRootIsItsSmallestNodeWhateverTheOrderOfTheJoins) {
  std::mt19937 random(9);
  std::vector<std::pair<std::int32_t, std::int32_t>> joins;
  for (int k = 0; k < 300; ++k)
    joins.emplace_back(static_cast<std::int32_t>(random() % 500), static_cast<std::int32_t>(random() % 500));
  std::vector<std::int32_t> first_roots;
  for (int order = 0; order < 3; ++order) {
    std::shuffle(joins.begin(), joins.end(), random);
    detail::UnionFind<std::int32_t> sets(500);
    for (const auto& [a, b] : joins) sets.join(a, b);
    std::vector<std::int32_t> roots(500);
    for (std::int32_t v = 0; v < 500; ++v) roots[v] = sets.find(v);
    for (std::int32_t v = 0; v < 500; ++v) {
      EXPECT_LE(roots[v], v);
      EXPECT_EQ(roots[roots[v]], roots[v]);
    }
    for (const auto& [a, b] : joins) EXPECT_EQ(roots[a], roots[b]);
    if (order == 0) first_roots = roots;
    EXPECT_EQ(roots, first_roots);
  }
}

TEST(UnionFind, UnjoinedNodesStayAlone) {
  detail::UnionFind<std::int64_t> sets(4);
  sets.join(3, 1);
  EXPECT_EQ(sets.find(3), 1);
  EXPECT_EQ(sets.find(0), 0);
  EXPECT_EQ(sets.find(2), 2);
}

}  // namespace
}  // namespace spheremap
