#include "spheremap/graph/max_flow.hpp"

#include <algorithm>
#include <cstddef>
#include <stdexcept>
#include <string>
#include <utility>

namespace spheremap {
namespace {

// The residual graph: each arc of the network gives a slot at its tail (its capacity) and one at its
// head (the reverse direction, capacity 0), so that pushing flow along a slot frees capacity on its
// mate. Slots are grouped by the node they leave (compressed rows): a node's slots are contiguous.
struct Residual {
  std::vector<std::int32_t> first;     // node x leaves by slots first[x] .. first[x + 1] - 1
  std::vector<std::int32_t> head;      // the node a slot leads to
  std::vector<std::int32_t> mate;      // the slot of the opposite direction
  std::vector<std::int64_t> capacity;  // residual capacity
};

void check(const FlowNetwork& network, std::int32_t source, std::int32_t sink, const MaxFlowOptions& options) {
  const auto fail = [](const std::string& what) { throw std::invalid_argument("maximum_flow: " + what); };
  const auto is_node = [&](std::int32_t v) { return v >= 0 && v < network.nodes; };
  if (!is_node(source) || !is_node(sink)) fail("the source or the sink is not a node of the network");
  if (source == sink) fail("the source is the sink");
  if (network.arcs.size() >= (std::size_t{1} << 30)) fail("more than 2^30 arcs");
  if (options.limit < 0) fail("the limit is negative");
  for (const auto& arc : network.arcs) {
    if (!is_node(arc.from) || !is_node(arc.to)) fail("an arc's end is not a node of the network");
    if (arc.capacity < 0 || arc.capacity > kUnboundedCapacity) fail("a capacity is outside [0, kUnboundedCapacity]");
  }
}

Residual residual_graph(const FlowNetwork& network) {
  Residual r;
  const auto nodes = static_cast<std::size_t>(network.nodes);
  r.first.assign(nodes + 1, 0);
  for (const auto& arc : network.arcs)
    ++r.first[static_cast<std::size_t>(arc.from) + 1], ++r.first[static_cast<std::size_t>(arc.to) + 1];
  for (std::size_t x = 0; x < nodes; ++x) r.first[x + 1] += r.first[x];
  const std::size_t slots = 2 * network.arcs.size();
  r.head.resize(slots);
  r.mate.resize(slots);
  r.capacity.resize(slots);
  std::vector<std::int32_t> next(r.first.begin(), r.first.end() - 1);
  for (const auto& arc : network.arcs) {
    const auto forward = next[static_cast<std::size_t>(arc.from)]++;
    const auto backward = next[static_cast<std::size_t>(arc.to)]++;
    const auto f = static_cast<std::size_t>(forward), b = static_cast<std::size_t>(backward);
    r.head[f] = arc.to, r.mate[f] = backward, r.capacity[f] = arc.capacity;
    r.head[b] = arc.from, r.mate[b] = forward, r.capacity[b] = 0;
  }
  return r;
}

class Solver {
 public:
  Solver(const FlowNetwork& network, std::int32_t source, std::int32_t sink, std::int64_t limit)
      : r_(residual_graph(network)),
        nodes_(static_cast<std::size_t>(network.nodes)),
        source_(source),
        sink_(sink),
        limit_(limit) {}

  [[nodiscard]] std::int64_t flow() const { return flow_; }
  [[nodiscard]] bool done() const { return flow_ >= limit_; }

  // Dinic's phases, at most `phases` of them, each a breadth-first layering of the residual graph from
  // the source and a blocking flow of shortest paths in it (depth-first, a current slot per node).
  void shortest_path_phases(int phases) {
    level_.assign(nodes_, -1);
    current_.resize(nodes_);
    for (int phase = 0; phase < phases && !done(); ++phase) {
      if (!layer()) break;
      const std::int64_t before = flow_;
      blocking_flow();
      for (const auto x : queue_) level_[static_cast<std::size_t>(x)] = -1;
      if (flow_ == before) break;
    }
  }

  // Boykov & Kolmogorov's algorithm (2004): a search tree grows from the source and one from the sink;
  // where they touch, the path between the roots is augmented; the nodes cut off by saturated slots
  // (orphans) find new parents in their tree or are freed. The trees are kept from one path to the next.
  void search_trees() {
    tree_.assign(nodes_, kFree);
    parent_.assign(nodes_, kNoParent);
    stamp_.assign(nodes_, 0);
    depth_.assign(nodes_, 0);
    in_queue_.assign(nodes_, 0);
    active_.clear();
    head_ = 0;
    join(source_, kSourceTree, kRoot, 0);
    join(sink_, kSinkTree, kRoot, 0);
    std::int32_t time = 0;
    while (!done()) {
      const auto [from, via] = grow();
      if (from < 0) return;
      augment_between_trees(from, via);
      adopt_orphans(++time);
    }
  }

  // The nodes the source reaches in the residual graph.
  std::vector<std::uint8_t> source_side() const {
    std::vector<std::uint8_t> reached(nodes_, 0);
    std::vector<std::int32_t> queue{source_};
    reached[static_cast<std::size_t>(source_)] = 1;
    for (std::size_t at = 0; at < queue.size(); ++at) {
      const auto x = static_cast<std::size_t>(queue[at]);
      for (auto s = r_.first[x]; s < r_.first[x + 1]; ++s) {
        const auto y = r_.head[static_cast<std::size_t>(s)];
        if (r_.capacity[static_cast<std::size_t>(s)] > 0 && !reached[static_cast<std::size_t>(y)])
          reached[static_cast<std::size_t>(y)] = 1, queue.push_back(y);
      }
    }
    return reached;
  }

 private:
  static constexpr std::uint8_t kFree = 0, kSourceTree = 1, kSinkTree = 2;
  // A node's parent slot (at the node, leading to its parent) when it has none (orphan or free), or is a root.
  static constexpr std::int32_t kNoParent = -1, kRoot = -2;

  [[nodiscard]] std::int64_t& capacity(std::int32_t slot) { return r_.capacity[static_cast<std::size_t>(slot)]; }
  [[nodiscard]] std::int32_t head(std::int32_t slot) const { return r_.head[static_cast<std::size_t>(slot)]; }
  [[nodiscard]] std::int32_t mate(std::int32_t slot) const { return r_.mate[static_cast<std::size_t>(slot)]; }
  [[nodiscard]] std::int32_t begin(std::int32_t x) const { return r_.first[static_cast<std::size_t>(x)]; }
  [[nodiscard]] std::int32_t end(std::int32_t x) const { return r_.first[static_cast<std::size_t>(x) + 1]; }

  // Adds `amount` (at most what is left below the limit) to the flow; the caller pushes it.
  std::int64_t take(std::int64_t bottleneck) {
    const std::int64_t amount = std::min(bottleneck, limit_ - flow_);
    flow_ += amount;
    if (flow_ >= kUnboundedCapacity)
      throw std::invalid_argument("maximum_flow: the flow is unbounded (a path of unbounded arcs)");
    return amount;
  }

  void push(std::int32_t slot, std::int64_t amount) {
    capacity(slot) -= amount;
    capacity(mate(slot)) += amount;
  }

  // Layers the residual graph by breadth-first distance from the source, up to the sink's layer.
  // Returns whether the sink is reached. queue_ holds the nodes layered.
  bool layer() {
    queue_.assign(1, source_);
    level_[static_cast<std::size_t>(source_)] = 0;
    std::int32_t sink_level = -1;
    for (std::size_t at = 0; at < queue_.size(); ++at) {
      const auto x = queue_[at];
      const auto lx = level_[static_cast<std::size_t>(x)];
      if (sink_level >= 0 && lx >= sink_level) break;
      current_[static_cast<std::size_t>(x)] = begin(x);
      for (auto s = begin(x); s < end(x); ++s) {
        const auto y = head(s);
        if (capacity(s) <= 0 || level_[static_cast<std::size_t>(y)] >= 0) continue;
        level_[static_cast<std::size_t>(y)] = lx + 1;
        queue_.push_back(y);
        if (y == sink_) sink_level = lx + 1;
      }
    }
    if (sink_level < 0) {
      for (const auto x : queue_) level_[static_cast<std::size_t>(x)] = -1;
      return false;
    }
    current_[static_cast<std::size_t>(sink_)] = end(sink_);
    return true;
  }

  // Augments shortest paths (each slot from layer k to layer k + 1) until none is left.
  void blocking_flow() {
    const auto sink_level = level_[static_cast<std::size_t>(sink_)];
    while (!done()) {
      path_.clear();
      std::int32_t x = source_;
      while (x != sink_) {
        auto& at = current_[static_cast<std::size_t>(x)];
        const auto lx = level_[static_cast<std::size_t>(x)];
        if (lx < sink_level)
          for (; at < end(x); ++at) {
            const auto y = head(at);
            if (capacity(at) > 0 && level_[static_cast<std::size_t>(y)] == lx + 1) break;
          }
        if (lx < sink_level && at < end(x)) {
          path_.push_back(at);
          x = head(at);
          continue;
        }
        level_[static_cast<std::size_t>(x)] = -2;  // a dead end for the rest of the phase
        if (path_.empty()) return;
        x = head(mate(path_.back()));
        path_.pop_back();
        ++current_[static_cast<std::size_t>(x)];
      }
      std::int64_t bottleneck = kUnboundedCapacity;
      for (const auto s : path_) bottleneck = std::min(bottleneck, capacity(s));
      const std::int64_t amount = take(bottleneck);
      for (const auto s : path_) push(s, amount);
    }
  }

  void activate(std::int32_t x) {
    if (in_queue_[static_cast<std::size_t>(x)]) return;
    in_queue_[static_cast<std::size_t>(x)] = 1;
    active_.push_back(x);
  }

  // Adds x to `tree` below the node its slot `slot` leads to (kRoot: x is the root).
  void join(std::int32_t x, std::uint8_t tree, std::int32_t slot, std::int32_t parent_depth) {
    const auto ux = static_cast<std::size_t>(x);
    tree_[ux] = tree;
    parent_[ux] = slot;
    if (slot == kRoot) {
      depth_[ux] = 0;
    } else {
      stamp_[ux] = stamp_[static_cast<std::size_t>(head(slot))];
      depth_[ux] = parent_depth + 1;
    }
    activate(x);
  }

  // Grows the trees from their active nodes until they touch. Returns the source-tree node and its slot
  // into the sink tree where they touch, or {-1, 0} if they cannot grow further (the flow is maximal).
  std::pair<std::int32_t, std::int32_t> grow() {
    while (head_ < active_.size()) {
      const auto x = active_[head_];
      const auto ux = static_cast<std::size_t>(x);
      const auto tree = tree_[ux];
      for (auto s = begin(x); tree != kFree && s < end(x); ++s) {
        const auto y = head(s);
        const auto other = tree_[static_cast<std::size_t>(y)];
        if (tree == kSourceTree && capacity(s) > 0) {
          if (other == kFree)
            join(y, kSourceTree, mate(s), depth_[ux]);
          else if (other == kSinkTree)
            return {x, s};
        } else if (tree == kSinkTree && capacity(mate(s)) > 0) {
          if (other == kFree)
            join(y, kSinkTree, mate(s), depth_[ux]);
          else if (other == kSourceTree)
            return {y, mate(s)};
        }
      }
      // Done with x (a node that touched the other tree stays first, for the next path).
      in_queue_[ux] = 0;
      ++head_;
      if (head_ > 4096 && 2 * head_ > active_.size()) {
        active_.erase(active_.begin(), active_.begin() + static_cast<std::ptrdiff_t>(head_));
        head_ = 0;
      }
    }
    return {-1, 0};
  }

  // Augments the path source -> ... -> from -> (via) -> to -> ... -> sink by its bottleneck; the nodes
  // below a saturated slot become orphans.
  void augment_between_trees(std::int32_t from, std::int32_t via) {
    const auto to = head(via);
    std::int64_t bottleneck = capacity(via);
    for (auto u = from; parent_[static_cast<std::size_t>(u)] != kRoot; u = head(parent_[static_cast<std::size_t>(u)]))
      bottleneck = std::min(bottleneck, capacity(mate(parent_[static_cast<std::size_t>(u)])));
    for (auto v = to; parent_[static_cast<std::size_t>(v)] != kRoot; v = head(parent_[static_cast<std::size_t>(v)]))
      bottleneck = std::min(bottleneck, capacity(parent_[static_cast<std::size_t>(v)]));
    const std::int64_t amount = take(bottleneck);
    push(via, amount);
    orphans_.clear();
    for (auto u = from; parent_[static_cast<std::size_t>(u)] != kRoot;) {
      const auto slot = parent_[static_cast<std::size_t>(u)];  // u -> parent; the flow runs parent -> u
      push(mate(slot), amount);
      if (capacity(mate(slot)) == 0) parent_[static_cast<std::size_t>(u)] = kNoParent, orphans_.push_back(u);
      u = head(slot);
    }
    for (auto v = to; parent_[static_cast<std::size_t>(v)] != kRoot;) {
      const auto slot = parent_[static_cast<std::size_t>(v)];  // v -> parent, the flow's direction
      push(slot, amount);
      if (capacity(slot) == 0) parent_[static_cast<std::size_t>(v)] = kNoParent, orphans_.push_back(v);
      v = head(slot);
    }
  }

  // The number of slots from x to its tree's root if its parents still lead there, else -1 (an orphan
  // on the way). The nodes walked are stamped with `time` and their depths.
  std::int32_t rooted_depth(std::int32_t x, std::int32_t time) {
    std::int32_t steps = 0;
    for (auto u = x;;) {
      const auto uu = static_cast<std::size_t>(u);
      if (stamp_[uu] == time) {
        steps += depth_[uu];
        break;
      }
      if (parent_[uu] == kNoParent) return -1;
      if (parent_[uu] == kRoot) break;
      ++steps;
      u = head(parent_[uu]);
    }
    std::int32_t at = steps;
    for (auto u = x; stamp_[static_cast<std::size_t>(u)] != time;) {
      const auto uu = static_cast<std::size_t>(u);
      stamp_[uu] = time;
      depth_[uu] = at--;
      if (parent_[uu] == kRoot) break;
      u = head(parent_[uu]);
    }
    return steps;
  }

  // Each orphan takes the shallowest neighbour of its tree that still leads to the root through a slot
  // with capacity; one that finds none is freed, its children become orphans and its tree neighbours
  // that could reach it again are activated.
  void adopt_orphans(std::int32_t time) {
    while (!orphans_.empty()) {
      const auto o = orphans_.back();
      orphans_.pop_back();
      const auto uo = static_cast<std::size_t>(o);
      const auto tree = tree_[uo];
      // In the source tree the flow comes from the parent (q -> o), in the sink tree it goes to it (o -> q).
      auto leads = [&](std::int32_t s) { return tree == kSourceTree ? capacity(mate(s)) > 0 : capacity(s) > 0; };
      std::int32_t best = kNoParent, best_depth = 0;
      for (auto s = begin(o); s < end(o); ++s) {
        const auto q = head(s);
        if (tree_[static_cast<std::size_t>(q)] != tree || !leads(s)) continue;
        const auto d = rooted_depth(q, time);
        if (d >= 0 && (best == kNoParent || d < best_depth)) best = s, best_depth = d;
      }
      if (best != kNoParent) {
        parent_[uo] = best;
        stamp_[uo] = time;
        depth_[uo] = best_depth + 1;
        continue;
      }
      tree_[uo] = kFree;
      for (auto s = begin(o); s < end(o); ++s) {
        const auto q = head(s);
        const auto uq = static_cast<std::size_t>(q);
        if (tree_[uq] != tree) continue;
        if (leads(s)) activate(q);
        if (parent_[uq] >= 0 && head(parent_[uq]) == o) parent_[uq] = kNoParent, orphans_.push_back(q);
      }
    }
  }

  Residual r_;
  std::size_t nodes_;
  std::int32_t source_, sink_;
  std::int64_t limit_, flow_ = 0;
  // Dinic's phases
  std::vector<std::int32_t> level_, current_, queue_, path_;
  // the search trees
  std::vector<std::uint8_t> tree_, in_queue_;
  std::vector<std::int32_t> parent_, stamp_, depth_, active_, orphans_;
  std::size_t head_ = 0;
};

}  // namespace

MaxFlow maximum_flow(const FlowNetwork& network, std::int32_t source, std::int32_t sink,
                     const MaxFlowOptions& options) {
  check(network, source, sink, options);
  Solver solver(network, source, sink, options.limit);
  solver.shortest_path_phases(options.shortest_path_phases);
  if (!solver.done()) solver.search_trees();
  MaxFlow result;
  result.value = solver.flow();
  result.limit_reached = solver.done();
  if (!result.limit_reached) result.source_side = solver.source_side();
  return result;
}

}  // namespace spheremap
