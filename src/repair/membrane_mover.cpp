#include "membrane_mover.hpp"

#include <algorithm>

#include "sample_state.hpp"
#include "tuning.hpp"

namespace spheremap::detail {
namespace {

// Dinic's phases before the search trees, for membranes of membrane_shortest_paths_from() samples or
// more (MaxFlowOptions::shortest_path_phases): they find most of a large flow along short paths, and pay
// off on large membranes only (BENCHMARKS.md).
constexpr int kShortestPathPhases = 12;

}  // namespace

std::vector<std::int64_t> MembraneMover::move(const std::vector<std::int64_t>& membrane, std::uint8_t member_bit) {
  if (!set_box(membrane)) return {};
  label_.assign(static_cast<std::size_t>(count_), 0);
  distance_.assign(static_cast<std::size_t>(count_), 0);
  region_.clear();
  for (const auto s : membrane) label_[static_cast<std::size_t>(local(s))] = kFace;
  const int faces = label_sides(membrane, member_bit);
  if (faces < 2) return {};
  const auto limit = static_cast<std::int64_t>(membrane.size());
  if (faces == 2) return minimum_cut(1, limit);
  std::vector<std::vector<std::int64_t>> isolating;
  std::int64_t total = 0;
  for (int side = 1; side <= faces; ++side) {
    isolating.push_back(minimum_cut(side, limit));
    if (isolating.back().empty()) return {};
    total += static_cast<std::int64_t>(isolating.back().size());
  }
  std::size_t largest = 0;
  for (std::size_t k = 1; k < isolating.size(); ++k)
    if (isolating[k].size() > isolating[largest].size()) largest = k;
  if (total - static_cast<std::int64_t>(isolating[largest].size()) >= limit) return {};
  std::vector<std::int64_t> cut;
  for (std::size_t k = 0; k < isolating.size(); ++k)
    if (k != largest) cut.insert(cut.end(), isolating[k].begin(), isolating[k].end());
  std::sort(cut.begin(), cut.end());
  cut.erase(std::unique(cut.begin(), cut.end()), cut.end());
  return cut;
}

bool MembraneMover::complete(std::vector<std::int64_t>& membrane, bool inside) {
  seen_.assign(static_cast<std::size_t>(count_), 0);
  for (const auto s : membrane) seen_[static_cast<std::size_t>(local(s))] = 1;
  bool touches_outside = false;
  std::vector<std::int64_t> enclosed, group, stack;
  const std::size_t size = membrane.size();
  for (std::size_t k = 0; k < size; ++k) {
    const std::int64_t b = local(membrane[k]);
    for (int n = 0; n < 14; ++n) {
      const std::int64_t start = b + offset_[n];
      const bool side = is_inside(start);
      touches_outside = touches_outside || !side;
      if (seen_[static_cast<std::size_t>(start)] || side != inside) continue;
      bool escapes = false;  // one connected group of the side's samples next to the membrane
      group.assign(1, start);
      stack.assign(1, start);
      seen_[static_cast<std::size_t>(start)] = 1;
      while (!stack.empty()) {
        const auto v = stack.back();
        stack.pop_back();
        if (!interior(v)) {
          escapes = true;
          continue;
        }
        for (int m = 0; m < 14; ++m) {
          const std::int64_t t = v + offset_[m];
          if (seen_[static_cast<std::size_t>(t)] || is_inside(t) != inside) continue;
          seen_[static_cast<std::size_t>(t)] = 1;
          stack.push_back(t);
          group.push_back(t);
        }
      }
      if (!escapes)
        for (const auto v : group) enclosed.push_back(global(v));
    }
  }
  if (inside && !touches_outside) return false;
  membrane.insert(membrane.end(), enclosed.begin(), enclosed.end());
  std::sort(membrane.begin(), membrane.end());
  return true;
}

bool MembraneMover::set_box(const std::vector<std::int64_t>& membrane) {
  std::array<std::int64_t, 3> low{size_[0], size_[1], size_[2]}, high{-1, -1, -1};
  for (const auto s : membrane) {
    const auto c = lattice_.coordinates(s);
    for (int d = 0; d < 3; ++d) low[d] = std::min(low[d], c[d]), high[d] = std::max(high[d], c[d]);
  }
  count_ = 1;
  for (int d = 0; d < 3; ++d) {
    low_[d] = std::max<std::int64_t>(0, low[d] - reach_ - 1);
    extent_[d] = std::min(size_[d] - 1, high[d] + reach_ + 1) - low_[d] + 1;
    count_ *= extent_[d];
  }
  if (count_ > kMaxBoxSamples) return false;
  for (int n = 0; n < 14; ++n)
    offset_[n] = kNeighbour[n][0] + extent_[0] * (kNeighbour[n][1] + extent_[1] * kNeighbour[n][2]);
  return true;
}

std::int64_t MembraneMover::local(std::int64_t s) const {
  const auto c = lattice_.coordinates(s);
  return (c[0] - low_[0]) + extent_[0] * ((c[1] - low_[1]) + extent_[1] * (c[2] - low_[2]));
}

std::int64_t MembraneMover::global(std::int64_t b) const {
  const std::int64_t a = b % extent_[0], c = (b / extent_[0]) % extent_[1], d = b / (extent_[0] * extent_[1]);
  return (low_[0] + a) + size_[0] * ((low_[1] + c) + size_[1] * (low_[2] + d));
}

// Off the box's outer layer: the box's margin (reach + 1) keeps every labelled sample there, and where
// the box is clipped by the grid this also keeps the grid's border out of any membrane.
bool MembraneMover::interior(std::int64_t b) const {
  const std::int64_t a = b % extent_[0], c = (b / extent_[0]) % extent_[1], d = b / (extent_[0] * extent_[1]);
  return a > 0 && c > 0 && d > 0 && a + 1 < extent_[0] && c + 1 < extent_[1] && d + 1 < extent_[2];
}

bool MembraneMover::is_inside(std::int64_t b) const { return (state_[global(b)] & kInside) != 0; }

// Labels the grown samples next to the membrane (kPending, then by face: their connected groups), and
// puts them in region_. Returns the number of faces (0 if more than kMaxFaces).
int MembraneMover::label_faces(const std::vector<std::int64_t>& membrane, std::uint8_t member_bit) {
  for (const auto s : membrane) {
    const std::int64_t b = local(s);
    for (int n = 0; n < 14; ++n) {
      const std::int64_t t = b + offset_[n];
      if (label_[static_cast<std::size_t>(t)] == kNone && interior(t) && (state_[global(t)] & member_bit) != 0)
        label_[static_cast<std::size_t>(t)] = kPending, region_.push_back(t);
    }
  }
  int faces = 0;
  std::vector<std::int64_t> stack;
  for (const auto start : region_) {
    if (label_[static_cast<std::size_t>(start)] != kPending) continue;
    if (++faces > kMaxFaces) return 0;
    label_[static_cast<std::size_t>(start)] = static_cast<std::uint8_t>(faces);
    stack.push_back(start);
    while (!stack.empty()) {
      const auto b = stack.back();
      stack.pop_back();
      for (int n = 0; n < 14; ++n) {
        const std::int64_t t = b + offset_[n];
        if (label_[static_cast<std::size_t>(t)] == kPending)
          label_[static_cast<std::size_t>(t)] = static_cast<std::uint8_t>(faces), stack.push_back(t);
      }
    }
  }
  return faces;
}

// Labels the membrane's faces (label_faces), then the grown samples within reach by the face they are
// reached from first; finds the terminals (labelled by side); region_ gets every labelled sample.
// Returns the number of faces (0 if fewer than 2 or more than kMaxFaces, or if some face has no terminal).
int MembraneMover::label_sides(const std::vector<std::int64_t>& membrane, std::uint8_t member_bit) {
  const int faces = label_faces(membrane, member_bit);
  if (faces < 2) return 0;
  auto member = [&](std::int64_t b) { return interior(b) && (state_[global(b)] & member_bit) != 0; };
  for (const auto b : region_) distance_[static_cast<std::size_t>(b)] = 1;
  for (std::size_t head = 0; head < region_.size(); ++head) {
    const auto b = region_[head];
    if (distance_[static_cast<std::size_t>(b)] >= reach_) continue;
    for (int n = 0; n < 14; ++n) {
      const std::int64_t t = b + offset_[n];
      if (label_[static_cast<std::size_t>(t)] != kNone || !member(t)) continue;
      label_[static_cast<std::size_t>(t)] = label_[static_cast<std::size_t>(b)];
      distance_[static_cast<std::size_t>(t)] = static_cast<std::uint16_t>(distance_[static_cast<std::size_t>(b)] + 1);
      region_.push_back(t);
    }
  }
  // Terminals: where the race stopped, and where two sides met again (around the handle).
  terminal_.assign(static_cast<std::size_t>(count_), 0);
  std::vector<bool> has_terminal(static_cast<std::size_t>(faces) + 1, false);
  for (const auto b : region_) {
    const auto side = label_[static_cast<std::size_t>(b)];
    bool far = distance_[static_cast<std::size_t>(b)] >= reach_;
    for (int n = 0; n < 14 && !far; ++n) {
      const auto other = label_[static_cast<std::size_t>(b + offset_[n])];
      far = is_side(other) && other != side;
    }
    if (!far) continue;
    terminal_[static_cast<std::size_t>(b)] = side;
    has_terminal[side] = true;
  }
  for (int side = 1; side <= faces; ++side)
    if (!has_terminal[static_cast<std::size_t>(side)]) return 0;
  for (const auto s : membrane) region_.push_back(local(s));
  return faces;
}

// The minimum vertex cut between the terminals of `side` and those of the other sides, unless it has
// `limit` samples or more. Returns the cut's samples (sorted global indices), else empty. Each sample of
// region_ is two nodes, "into" (2k) and "out of" (2k + 1) it, joined by an arc of capacity 1; out of a
// sample leads into each labelled neighbour not on another side (unbounded); the source leads into the
// side's terminals, the other terminals out to the sink.
std::vector<std::int64_t> MembraneMover::minimum_cut(int side, std::int64_t limit) {
  const auto samples = static_cast<std::int32_t>(region_.size());
  node_.resize(static_cast<std::size_t>(count_));
  for (std::int32_t k = 0; k < samples; ++k) node_[static_cast<std::size_t>(region_[static_cast<std::size_t>(k)])] = k;
  const std::int32_t source = 2 * samples, sink = source + 1;
  network_.nodes = 2 * samples + 2;
  network_.arcs.clear();
  for (std::int32_t k = 0; k < samples; ++k) {
    const auto b = region_[static_cast<std::size_t>(k)];
    const auto ub = static_cast<std::size_t>(b);
    network_.arcs.push_back({2 * k, 2 * k + 1, 1});
    if (terminal_[ub] == side)
      network_.arcs.push_back({source, 2 * k, kUnboundedCapacity});
    else if (terminal_[ub] != 0)
      network_.arcs.push_back({2 * k + 1, sink, kUnboundedCapacity});
    for (int n = 0; n < 14; ++n) {
      const auto t = static_cast<std::size_t>(b + offset_[n]);
      if (joined(label_[ub], label_[t])) network_.arcs.push_back({2 * k + 1, 2 * node_[t], kUnboundedCapacity});
    }
  }
  MaxFlowOptions options;
  options.limit = limit;
  options.shortest_path_phases = limit >= membrane_shortest_paths_from() ? kShortestPathPhases : 0;
  const MaxFlow flow = maximum_flow(network_, source, sink, options);
  if (flow.limit_reached) return {};
  // The cut: samples whose "into" node the source reaches in the residual graph, but not their "out of".
  std::vector<std::int64_t> cut;
  for (std::int32_t k = 0; k < samples; ++k)
    if (flow.source_side[static_cast<std::size_t>(2 * k)] && !flow.source_side[static_cast<std::size_t>(2 * k + 1)])
      cut.push_back(global(region_[static_cast<std::size_t>(k)]));
  std::sort(cut.begin(), cut.end());
  if (static_cast<std::int64_t>(cut.size()) != flow.value) return {};  // cannot happen with an exact maximum flow
  return cut;
}

}  // namespace spheremap::detail
