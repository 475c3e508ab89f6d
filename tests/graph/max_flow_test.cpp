#include "spheremap/graph/max_flow.hpp"

#include <gtest/gtest.h>

#include <cstdint>
#include <limits>
#include <random>
#include <stdexcept>
#include <vector>

namespace spheremap {
namespace {

// Dinic's phases alone (more phases than any of these graphs needs), the search trees alone, and both.
const std::vector<int> kPhaseCounts{0, 1, 3, 1000};

FlowNetwork network(std::int32_t nodes, const std::vector<FlowArc>& arcs) { return FlowNetwork{nodes, arcs}; }

std::vector<std::uint8_t> side(std::int32_t nodes, const std::vector<std::int32_t>& members) {
  std::vector<std::uint8_t> s(static_cast<std::size_t>(nodes), 0);
  for (const auto v : members) s[static_cast<std::size_t>(v)] = 1;
  return s;
}

// The capacity of the arcs from `source_side` to the rest.
std::int64_t cut_value(const FlowNetwork& g, const std::vector<std::uint8_t>& source_side) {
  std::int64_t value = 0;
  for (const auto& a : g.arcs)
    if (source_side[static_cast<std::size_t>(a.from)] && !source_side[static_cast<std::size_t>(a.to)])
      value += a.capacity;
  return value;
}

// Every s-t cut, tried: the minimum cut's value and the smallest minimum cut's source side (the
// intersection of every minimum cut's source side, itself a minimum cut).
struct BruteForce {
  std::int64_t value = std::numeric_limits<std::int64_t>::max();
  std::vector<std::uint8_t> smallest_side;
};

BruteForce brute_force_minimum_cut(const FlowNetwork& g, std::int32_t source, std::int32_t sink) {
  BruteForce best;
  const auto n = static_cast<std::size_t>(g.nodes);
  for (std::uint32_t mask = 0; mask < (1u << n); ++mask) {
    if (!((mask >> source) & 1u) || ((mask >> sink) & 1u)) continue;
    std::vector<std::uint8_t> s(n);
    for (std::size_t v = 0; v < n; ++v) s[v] = static_cast<std::uint8_t>((mask >> v) & 1u);
    const auto value = cut_value(g, s);
    if (value < best.value) {
      best.value = value;
      best.smallest_side = s;
    } else if (value == best.value) {
      for (std::size_t v = 0; v < n; ++v) best.smallest_side[v] = best.smallest_side[v] && s[v];
    }
  }
  return best;
}

// Cormen, Leiserson, Rivest & Stein, Introduction to Algorithms (3rd ed.), figure 26.1: s = 0, v1..v4 =
// 1..4, t = 5. Maximum flow 23; the only minimum cut is {s, v1, v2, v4} (v1->v3 12, v4->v3 7, v4->t 4).
FlowNetwork textbook_network() {
  return network(
      6, {{0, 1, 16}, {0, 2, 13}, {2, 1, 4}, {1, 3, 12}, {3, 2, 9}, {2, 4, 14}, {4, 3, 7}, {3, 5, 20}, {4, 5, 4}});
}

TEST(MaxFlow, TheTextbookNetworkCarries23AcrossItsOnlyMinimumCut) {
  for (const int phases : kPhaseCounts) {
    SCOPED_TRACE(testing::Message() << phases << " shortest-path phases");
    const auto flow = maximum_flow(textbook_network(), 0, 5, {.shortest_path_phases = phases});
    EXPECT_EQ(flow.value, 23);
    EXPECT_FALSE(flow.limit_reached);
    EXPECT_EQ(flow.source_side, side(6, {0, 1, 2, 4}));
  }
}

TEST(MaxFlow, OfSeveralMinimumCutsTheOneWithTheFewestNodesIsReturned) {
  // s -> a -> t, both arcs of capacity 1: {s} and {s, a} are both minimum cuts.
  for (const int phases : kPhaseCounts) {
    const auto flow = maximum_flow(network(3, {{0, 1, 1}, {1, 2, 1}}), 0, 2, {.shortest_path_phases = phases});
    EXPECT_EQ(flow.value, 1);
    EXPECT_EQ(flow.source_side, side(3, {0}));
  }
}

TEST(MaxFlow, ParallelAndOpposedArcsAddUpAndUnreachableSinksCarryNothing) {
  const auto parallel = maximum_flow(network(2, {{0, 1, 3}, {0, 1, 4}, {1, 0, 10}, {0, 0, 5}}), 0, 1);
  EXPECT_EQ(parallel.value, 7);
  EXPECT_EQ(parallel.source_side, side(2, {0}));
  const auto apart = maximum_flow(network(4, {{0, 1, 5}, {2, 3, 5}, {3, 1, 2}}), 0, 3);
  EXPECT_EQ(apart.value, 0);
  EXPECT_EQ(apart.source_side, side(4, {0, 1}));
}

TEST(MaxFlow, UnitNodeCapacitiesBySplittingNodes) {
  // Node-disjoint paths in the graph s -> {a, b}, a -> c, b -> c, c -> t, a -> t: each of a, b, c split
  // into an "in" and an "out" node joined by capacity 1, the other arcs unbounded. Two node-disjoint
  // paths (s a t, s b c t); of the two minimum cuts, {a, b} and {a, c}, the first has the fewer nodes.
  enum : std::int32_t { s, a_in, a_out, b_in, b_out, c_in, c_out, t, count };
  const auto u = kUnboundedCapacity;
  const auto g = network(count, {{s, a_in, u},
                                 {s, b_in, u},
                                 {a_in, a_out, 1},
                                 {b_in, b_out, 1},
                                 {c_in, c_out, 1},
                                 {a_out, c_in, u},
                                 {b_out, c_in, u},
                                 {c_out, t, u},
                                 {a_out, t, u}});
  for (const int phases : kPhaseCounts) {
    const auto flow = maximum_flow(g, s, t, {.shortest_path_phases = phases});
    EXPECT_EQ(flow.value, 2);
    EXPECT_EQ(flow.source_side, side(count, {s, a_in, b_in}));
  }
}

TEST(MaxFlow, TheLimitStopsTheFlowAndLeavesNoCut) {
  for (const int phases : kPhaseCounts) {
    SCOPED_TRACE(testing::Message() << phases << " shortest-path phases");
    for (const std::int64_t limit : {0, 1, 10, 22, 23}) {
      const auto flow = maximum_flow(textbook_network(), 0, 5, {.limit = limit, .shortest_path_phases = phases});
      EXPECT_EQ(flow.value, limit);
      EXPECT_TRUE(flow.limit_reached);
      EXPECT_TRUE(flow.source_side.empty());
    }
    const auto flow = maximum_flow(textbook_network(), 0, 5, {.limit = 24, .shortest_path_phases = phases});
    EXPECT_EQ(flow.value, 23);
    EXPECT_FALSE(flow.limit_reached);
  }
}

TEST(MaxFlow, BadNetworksAndUnboundedFlowsAreRefused) {
  const auto g = textbook_network();
  EXPECT_THROW(maximum_flow(g, 0, 0), std::invalid_argument);
  EXPECT_THROW(maximum_flow(g, 0, 6), std::invalid_argument);
  EXPECT_THROW(maximum_flow(g, -1, 5), std::invalid_argument);
  EXPECT_THROW(maximum_flow(g, 0, 5, {.limit = -1}), std::invalid_argument);
  EXPECT_THROW(maximum_flow(network(2, {{0, 2, 1}}), 0, 1), std::invalid_argument);
  EXPECT_THROW(maximum_flow(network(2, {{0, 1, -1}}), 0, 1), std::invalid_argument);
  EXPECT_THROW(maximum_flow(network(2, {{0, 1, kUnboundedCapacity + 1}}), 0, 1), std::invalid_argument);
  const auto unbounded = network(3, {{0, 1, kUnboundedCapacity}, {1, 2, kUnboundedCapacity}});
  for (const int phases : kPhaseCounts) {
    EXPECT_THROW(maximum_flow(unbounded, 0, 2, {.shortest_path_phases = phases}), std::invalid_argument);
    EXPECT_EQ(maximum_flow(unbounded, 0, 2, {.limit = 5, .shortest_path_phases = phases}).value, 5);
  }
}

TEST(MaxFlow, RandomNetworksAgreeWithEveryCutTried) {
  std::mt19937 random(17);
  int graphs = 0;
  for (int trial = 0; trial < 400; ++trial) {
    const auto nodes = static_cast<std::int32_t>(2 + random() % 9);
    const auto arc_count = static_cast<unsigned>(nodes) + random() % (4 * static_cast<unsigned>(nodes));
    FlowNetwork g{nodes, {}};
    for (unsigned a = 0; a < arc_count; ++a) {
      const auto from = static_cast<std::int32_t>(random() % static_cast<unsigned>(nodes));
      const auto to = static_cast<std::int32_t>(random() % static_cast<unsigned>(nodes));
      // Mostly small capacities (ties between cuts), some zero, some large.
      const unsigned kind = random() % 10;
      const std::int64_t capacity = kind == 0 ? 0 : kind == 1 ? 1'000'000'000'000LL + random() % 1000 : random() % 6;
      g.arcs.push_back({from, to, capacity});
    }
    const std::int32_t source = 0, sink = nodes - 1;
    const auto expected = brute_force_minimum_cut(g, source, sink);
    for (const int phases : kPhaseCounts) {
      const auto flow = maximum_flow(g, source, sink, {.shortest_path_phases = phases});
      ASSERT_EQ(flow.value, expected.value) << "trial " << trial << ", " << phases << " phases";
      ASSERT_EQ(flow.source_side, expected.smallest_side) << "trial " << trial << ", " << phases << " phases";
      EXPECT_EQ(cut_value(g, flow.source_side), flow.value);
      if (flow.value > 0) {
        const auto limited = maximum_flow(g, source, sink, {.limit = flow.value, .shortest_path_phases = phases});
        EXPECT_TRUE(limited.limit_reached);
        EXPECT_EQ(limited.value, flow.value);
      }
    }
    graphs += expected.value > 0;
  }
  EXPECT_GT(graphs, 200);
}

// Grids of unit node capacities, as the handle repair builds them (node splitting), large enough for the
// search trees to adopt orphans many times: the flow equals the cut, and all phase counts agree.
TEST(MaxFlow, LargeSplitGridsGiveTheSameCutWithAnyNumberOfPhases) {
  std::mt19937 random(3);
  for (int trial = 0; trial < 6; ++trial) {
    const std::int32_t w = 30, h = 20;
    auto in = [&](std::int32_t i, std::int32_t j) { return 2 * (i + w * j); };
    FlowNetwork g{2 * w * h + 2, {}};
    const std::int32_t source = 2 * w * h, sink = source + 1;
    for (std::int32_t j = 0; j < h; ++j)
      for (std::int32_t i = 0; i < w; ++i) {
        if (random() % 5 == 0) continue;  // a hole: no capacity through this node
        g.arcs.push_back({in(i, j), in(i, j) + 1, 1});
        for (const auto& [di, dj] : {std::pair{1, 0}, {-1, 0}, {0, 1}, {0, -1}, {1, 1}, {-1, -1}}) {
          const std::int32_t a = i + di, b = j + dj;
          if (a >= 0 && b >= 0 && a < w && b < h) g.arcs.push_back({in(i, j) + 1, in(a, b), kUnboundedCapacity});
        }
        if (i == 0) g.arcs.push_back({source, in(i, j), kUnboundedCapacity});
        if (i == w - 1) g.arcs.push_back({in(i, j) + 1, sink, kUnboundedCapacity});
      }
    const auto reference = maximum_flow(g, source, sink, {.shortest_path_phases = 0});
    EXPECT_GT(reference.value, 0);
    EXPECT_EQ(cut_value(g, reference.source_side), reference.value);
    for (const int phases : kPhaseCounts) {
      const auto flow = maximum_flow(g, source, sink, {.shortest_path_phases = phases});
      EXPECT_EQ(flow.value, reference.value);
      EXPECT_EQ(flow.source_side, reference.source_side);
    }
  }
}

}  // namespace
}  // namespace spheremap
