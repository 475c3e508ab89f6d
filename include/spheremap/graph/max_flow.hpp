// Maximum flows and minimum cuts in directed graphs with integer capacities.
#pragma once

#include <cstdint>
#include <limits>
#include <vector>

namespace spheremap {

/// A capacity no minimum cut crosses, for arcs that must never be cut: larger than any finite cut a
/// caller builds (the finite capacities of a network must add up to less).
inline constexpr std::int64_t kUnboundedCapacity = std::numeric_limits<std::int64_t>::max() / 4;

/// One arc of a FlowNetwork: from -> to, with a capacity in [0, kUnboundedCapacity].
struct FlowArc {
  std::int32_t from = 0, to = 0;
  std::int64_t capacity = 0;
};

/// A directed graph with capacities: nodes 0 .. nodes - 1, arcs in any order (parallel arcs, arcs both
/// ways between two nodes and loops are allowed).
struct FlowNetwork {
  std::int32_t nodes = 0;
  std::vector<FlowArc> arcs;
};

struct MaxFlowOptions {
  /// Stop as soon as the flow reaches this value: for a caller that only wants a cut below it.
  std::int64_t limit = std::numeric_limits<std::int64_t>::max();
  /// Phases of Dinic's algorithm (a breadth-first layering, then a blocking flow of shortest paths) run
  /// before Boykov & Kolmogorov's search trees finish the flow. The phases find most of a large flow
  /// along short paths cheaply; the trees, kept from one path to the next, finish it. Any value gives the
  /// same flow value and cut.
  int shortest_path_phases = 0;
};

struct MaxFlow {
  std::int64_t value = 0;      // the maximum flow's value, or options.limit if the flow reached it
  bool limit_reached = false;  // the flow reached options.limit: value is a lower bound, no cut computed
  /// source_side[v] != 0: node v is reachable from the source in the residual graph of the maximum
  /// flow. This is the source side of the minimum cut with the fewest nodes, the same whichever maximum
  /// flow was found; its arcs to the other side add up to `value`. Empty when limit_reached.
  std::vector<std::uint8_t> source_side;
};

/// The maximum flow from `source` to `sink` in `network`, and its minimum cut (MaxFlow::source_side).
/// Deterministic. Time: Dinic's phases O(V² E) each, the search trees O(V E² |cut|) at worst, much less
/// on grid-like graphs. Memory: about 40 bytes per arc and 40 per node.
/// Preconditions: source != sink, both nodes of the network; every arc's ends are nodes; capacities in
/// [0, kUnboundedCapacity]; the finite capacities add up to less than kUnboundedCapacity; fewer than
/// 2^30 arcs; options.limit >= 0.
/// Throws std::invalid_argument if a precondition does not hold, and if the flow is unbounded (a path
/// of unbounded arcs only from source to sink) unless options.limit stops it first.
MaxFlow maximum_flow(const FlowNetwork& network, std::int32_t source, std::int32_t sink,
                     const MaxFlowOptions& options = {});

}  // namespace spheremap
