#include "spheremap/surface/handles.hpp"

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "spheremap/surface/contour.hpp"
#include "spheremap/topology/components.hpp"

namespace spheremap {
namespace {

// The 14 neighbours of a vertex in the Freudenthal triangulation: ±e1, ±e2, ±e3, ±(e1+e2), ±(e1+e3),
// ±(e2+e3), ±(e1+e2+e3) — the edges of the six tetrahedra per cell used by contour_isosurface.
constexpr std::array<std::array<int, 3>, 14> kNeighbour = {{{1, 0, 0},  {-1, 0, 0},  {0, 1, 0},  {0, -1, 0},  {0, 0, 1},
                                                            {0, 0, -1}, {1, 1, 0},   {-1, -1, 0}, {1, 0, 1},  {-1, 0, -1},
                                                            {0, 1, 1},  {0, -1, -1}, {1, 1, 1},  {-1, -1, -1}}};

// Two neighbours of a vertex are joined in its link when their difference is itself a lattice edge.
struct Link {
  std::array<std::array<bool, 14>, 14> adjacent{};
  Link() {
    for (int a = 0; a < 14; ++a)
      for (int b = 0; b < 14; ++b) {
        if (a == b) continue;
        const std::array<int, 3> d{kNeighbour[b][0] - kNeighbour[a][0], kNeighbour[b][1] - kNeighbour[a][1],
                                   kNeighbour[b][2] - kNeighbour[a][2]};
        for (const auto& n : kNeighbour) adjacent[a][b] = adjacent[a][b] || n == d;
      }
  }
};

const Link& lattice_link() {
  static const Link link;
  return link;
}

// Number of connected parts of the link vertices whose bit in `mask` equals `value`.
int parts(const Link& link, unsigned mask, bool value) {
  std::array<bool, 14> seen{};
  int count = 0;
  auto has = [&](int n) { return (((mask >> n) & 1u) != 0) == value; };
  for (int start = 0; start < 14; ++start) {
    if (!has(start) || seen[start]) continue;
    ++count;
    std::array<int, 14> stack{};
    int top = 0;
    stack[top++] = start;
    seen[start] = true;
    while (top > 0) {
      const int a = stack[--top];
      for (int b = 0; b < 14; ++b)
        if (!seen[b] && has(b) && link.adjacent[a][b]) seen[b] = true, stack[top++] = b;
    }
  }
  return count;
}

// simple[mask] for the 2^14 patterns of set membership among the 14 neighbours: adding the sample keeps
// the set's topology when the part of the link in the set, and the rest, are both non-empty and
// connected (for a full subcomplex of the link, a triangulated 2-sphere, this is contractibility by
// Alexander duality).
const std::array<bool, 1u << 14>& simple_table() {
  static const std::array<bool, 1u << 14> table = [] {
    std::array<bool, 1u << 14> simple{};
    const Link& link = lattice_link();
    for (unsigned mask = 0; mask < (1u << 14); ++mask) simple[mask] = parts(link, mask, true) == 1 && parts(link, mask, false) == 1;
    return simple;
  }();
  return table;
}

// Per-sample state bits, one byte per sample for the whole repair.
constexpr std::uint8_t kInSolid = 1;      // reached by the solid's growth
constexpr std::uint8_t kInOutside = 2;    // reached by the outside's growth
constexpr std::uint8_t kQueued = 4;       // in the growth's queue
constexpr std::uint8_t kClustered = 8;    // assigned to a cluster of left-out samples
constexpr std::uint8_t kToggled = 16;     // in the cluster whose Euler change is being counted
constexpr std::uint8_t kInside = 32;      // field > level (kept in the state so that growths read one array)

// Neighbour access: sample index offsets, and a border test only for samples on the grid's outer layer.
class Lattice {
 public:
  explicit Lattice(const std::array<std::int64_t, 3>& size) : nx_(size[0]), ny_(size[1]), nz_(size[2]) {
    for (int n = 0; n < 14; ++n) offset_[n] = kNeighbour[n][0] + nx_ * (kNeighbour[n][1] + ny_ * kNeighbour[n][2]);
  }
  [[nodiscard]] std::int64_t count() const { return nx_ * ny_ * nz_; }
  [[nodiscard]] bool on_border(std::int64_t s) const {
    const std::int64_t i = s % nx_, j = (s / nx_) % ny_, k = s / (nx_ * ny_);
    return i == 0 || j == 0 || k == 0 || i == nx_ - 1 || j == ny_ - 1 || k == nz_ - 1;
  }
  // Calls visit(n, t) for each neighbour n of s inside the grid (t its index), visit(n, -1) outside it.
  template <typename Visit>
  void neighbours(std::int64_t s, Visit&& visit) const {
    const std::int64_t i = s % nx_, j = (s / nx_) % ny_, k = s / (nx_ * ny_);
    if (i > 0 && j > 0 && k > 0 && i + 1 < nx_ && j + 1 < ny_ && k + 1 < nz_) {
      for (int n = 0; n < 14; ++n) visit(n, s + offset_[n]);
      return;
    }
    for (int n = 0; n < 14; ++n) {
      const std::int64_t a = i + kNeighbour[n][0], b = j + kNeighbour[n][1], c = k + kNeighbour[n][2];
      const bool inside = a >= 0 && b >= 0 && c >= 0 && a < nx_ && b < ny_ && c < nz_;
      visit(n, inside ? s + offset_[n] : std::int64_t{-1});
    }
  }

 private:
  std::int64_t nx_, ny_, nz_;
  std::array<std::int64_t, 14> offset_{};
};

// A priority queue over small integer keys (smaller key first): one FIFO per key, so pushes and pops
// are O(1) and the order (first offered first within a key, which grows fronts evenly) is
// deterministic. A push below the current key moves the front back, as a heap would.
class BucketQueue {
 public:
  explicit BucketQueue(std::size_t keys) : buckets_(keys) {}
  void push(std::size_t key, std::int64_t sample) {
    key = std::min(key, buckets_.size() - 1);
    buckets_[key].items.push_back(sample);
    front_ = std::min(front_, key);
    ++size_;
  }
  [[nodiscard]] bool empty() const { return size_ == 0; }
  std::int64_t pop() {
    while (buckets_[front_].head == buckets_[front_].items.size()) ++front_;
    Bucket& bucket = buckets_[front_];
    const std::int64_t s = bucket.items[bucket.head++];
    if (bucket.head == bucket.items.size()) bucket.items.clear(), bucket.head = 0;
    --size_;
    return s;
  }

 private:
  struct Bucket {
    std::vector<std::int64_t> items;
    std::size_t head = 0;
  };
  std::vector<Bucket> buckets_;
  std::size_t front_ = 0, size_ = 0;
};

// How far each outside sample lies from the solid: its squared distance (grid units², an integer) to
// the nearest inside sample. The SES field is flat (-probe) wherever a probe fits, so it cannot order
// the outside growth; this distance makes the two fronts entering a tunnel meet at its narrowest
// section, where a fill is smallest.
template <typename T>
std::vector<float> outside_depth(const Grid3<T>& field, double level) {
  Grid3<float> depth;
  depth.size = field.size;
  depth.values.resize(field.values.size());
  for (std::size_t s = 0; s < field.values.size(); ++s)
    depth.values[s] = field.values[s] > level ? 0.0f : std::numeric_limits<float>::infinity();
  squared_distance_transform_in_place(depth);
  return std::move(depth.values);
}

// Grows a set by simple samples only, deepest first, and marks its members with `member_bit` in
// `state`. For the inside (solid) the seed is the deepest sample of the largest inside piece and the set
// stays a ball; for the outside the seed is the whole grid border (with everything beyond the grid
// counted in), so the set stays a shell and what it encloses a ball. Depth: for the solid its field
// value (in buckets of spacing/256); for the outside the squared lattice distance to the solid.
template <typename T>
void grow(const Grid3<T>& field, double level, bool solid, std::vector<std::uint8_t>& state) {
  const std::uint8_t member_bit = solid ? kInSolid : kInOutside;
  const Lattice lattice(field.size);
  const auto total = lattice.count();
  const auto& simple = simple_table();
  const T* values = field.values.data();
  const std::uint8_t wanted = solid ? kInside : 0;
  auto candidate = [&](std::int64_t s) { return (state[s] & kInside) == wanted; };
  std::vector<float> depth;
  double top_value = level;
  if (solid) {
    for (std::int64_t s = 0; s < total; ++s)
      if (std::isfinite(values[s])) top_value = std::max(top_value, static_cast<double>(values[s]));
  } else {
    depth = outside_depth(field, level);
  }
  const double quantum = field.spacing / 256;
  constexpr std::size_t kOutsideKeys = 1u << 16;
  const std::size_t keys = solid ? static_cast<std::size_t>((top_value - level) / quantum) + 2 : kOutsideKeys;
  // Smaller key = deeper: for the solid, below the top value; for the outside, farther from the solid.
  auto key_of = [&](std::int64_t s) -> std::size_t {
    if (solid) return std::isfinite(values[s]) ? static_cast<std::size_t>((top_value - static_cast<double>(values[s])) / quantum) : 0;
    const float d = depth[static_cast<std::size_t>(s)];
    return d >= static_cast<float>(kOutsideKeys - 1) ? 0 : kOutsideKeys - 1 - static_cast<std::size_t>(d);
  };
  BucketQueue frontier(keys);
  auto offer_neighbours = [&](std::int64_t s) {
    lattice.neighbours(s, [&](int, std::int64_t t) {
      if (t >= 0 && !(state[t] & (member_bit | kQueued)) && candidate(t)) state[t] |= kQueued, frontier.push(key_of(t), t);
    });
  };
  if (solid) {
    // The seed is the deepest sample of the largest connected piece (by samples), so that the piece kept
    // whole is the main body even when a small detached piece is thicker. Pieces are labelled with the
    // queued bit, cleared afterwards.
    std::int64_t seed = -1, seed_piece_size = 0;
    std::vector<std::int64_t> stack;
    for (std::int64_t start = 0; start < total; ++start) {
      if (!candidate(start) || (state[start] & kQueued)) continue;
      std::int64_t size = 0, deepest = start;
      state[start] |= kQueued;
      stack.push_back(start);
      while (!stack.empty()) {
        const auto v = stack.back();
        stack.pop_back();
        ++size;
        if (values[v] > values[deepest] || (values[v] == values[deepest] && v < deepest)) deepest = v;
        lattice.neighbours(v, [&](int, std::int64_t t) {
          if (t >= 0 && !(state[t] & kQueued) && candidate(t)) state[t] |= kQueued, stack.push_back(t);
        });
      }
      if (size > seed_piece_size) seed_piece_size = size, seed = deepest;
    }
    for (auto& b : state) b &= static_cast<std::uint8_t>(~kQueued);
    if (seed < 0) throw std::invalid_argument("cut_handles: nothing is inside");
    state[seed] |= member_bit;
    offer_neighbours(seed);
  } else {
    for (std::int64_t s = 0; s < total; ++s) {
      if (!lattice.on_border(s)) continue;
      if (!candidate(s)) throw std::invalid_argument("cut_handles: the solid reaches the border of the grid");
      state[s] |= member_bit;
    }
    for (std::int64_t s = 0; s < total; ++s)
      if (lattice.on_border(s)) offer_neighbours(s);
  }
  // A sample refused now may become simple later, when more of its neighbours are in: it is offered again
  // whenever a neighbour joins (the queued bit is cleared on refusal). Each sample is offered at most 14 times.
  while (!frontier.empty()) {
    const auto s = frontier.pop();
    state[s] &= static_cast<std::uint8_t>(~kQueued);
    unsigned mask = 0;
    lattice.neighbours(s, [&](int n, std::int64_t t) {
      const bool member = t >= 0 ? (state[t] & member_bit) != 0 : !solid;  // beyond the grid is outside
      mask |= static_cast<unsigned>(member) << n;
    });
    if (simple[mask]) {
      state[s] |= member_bit;
      offer_neighbours(s);
    }
  }
}

// The simplices of the Freudenthal triangulation that contain a vertex, as lists of neighbour numbers:
// its 14 edges, 36 triangles (adjacent pairs in the link) and 24 tetrahedra (link triangles).
struct Star {
  std::vector<std::array<int, 2>> triangles;
  std::vector<std::array<int, 3>> tetrahedra;
  explicit Star(const Link& link) {
    for (int a = 0; a < 14; ++a)
      for (int b = a + 1; b < 14; ++b) {
        if (!link.adjacent[a][b]) continue;
        triangles.push_back({a, b});
        for (int c = b + 1; c < 14; ++c)
          if (link.adjacent[a][c] && link.adjacent[b][c]) tetrahedra.push_back({a, b, c});
      }
    if (triangles.size() != 36 || tetrahedra.size() != 24) throw std::logic_error("Freudenthal star miscounted");
  }
};

// Both growths, marked in one state byte per sample.
template <typename T>
std::vector<std::uint8_t> grow_both(const Grid3<T>& field, double level) {
  std::vector<std::uint8_t> state(static_cast<std::size_t>(field.count()), 0);
  for (std::size_t s = 0; s < state.size(); ++s) state[s] = field.values[s] > level ? kInside : 0;
  grow(field, level, true, state);
  grow(field, level, false, state);
  return state;
}

template <typename T>
HandleRepair repair_handles_impl(Grid3<T>& field, double level) {
  static const Star star(lattice_link());
  auto state = grow_both(field, level);
  const Lattice lattice(field.size);
  const auto total = lattice.count();
  T* values = field.values.data();
  auto left_out = [&](std::int64_t s) {
    return values[s] > level ? !(state[s] & kInSolid) : !(state[s] & kInOutside);
  };
  // Clusters of left-out samples (connected through samples on the same side that are also left out).
  std::vector<TopologyChange> clusters;
  std::vector<std::int64_t> stack;
  for (std::int64_t s = 0; s < total; ++s) {
    if ((state[s] & kClustered) || !left_out(s)) continue;
    const bool inside = values[s] > level;
    TopologyChange change;
    change.filled = !inside;
    stack.push_back(s);
    state[s] |= kClustered;
    while (!stack.empty()) {
      const auto v = stack.back();
      stack.pop_back();
      change.samples.push_back(v);
      lattice.neighbours(v, [&](int, std::int64_t t) {
        if (t < 0 || (state[t] & kClustered) || (values[t] > level) != inside || !left_out(t)) return;
        state[t] |= kClustered;
        stack.push_back(t);
      });
    }
    std::sort(change.samples.begin(), change.samples.end());
    clusters.push_back(std::move(change));
  }
  // Smallest first; ties by first sample (deterministic).
  std::vector<std::size_t> order(clusters.size());
  for (std::size_t c = 0; c < order.size(); ++c) order[c] = c;
  std::stable_sort(order.begin(), order.end(), [&](std::size_t a, std::size_t b) {
    return clusters[a].samples.size() != clusters[b].samples.size() ? clusters[a].samples.size() < clusters[b].samples.size()
                                                                    : clusters[a].samples.front() < clusters[b].samples.front();
  });
  const T below = std::nextafter(static_cast<T>(level), -std::numeric_limits<T>::max());
  const T above = std::nextafter(static_cast<T>(level), std::numeric_limits<T>::max());
  HandleRepair repair;
  for (const auto c : order) {
    auto& change = clusters[c];
    for (const auto v : change.samples) state[v] |= kToggled;
    // Euler characteristic of the solid's full subcomplex before and after toggling the cluster: each
    // simplex touching the cluster is counted once, from its smallest toggled vertex.
    auto inside_now = [&](std::int64_t t) { return t >= 0 && values[t] > level; };
    int before = 0, after = 0;
    for (const auto v : change.samples) {
      std::array<std::int64_t, 14> nb{};
      lattice.neighbours(v, [&](int n, std::int64_t t) { nb[n] = t; });
      auto counted_here = [&](std::int64_t t) { return t < 0 || !(state[t] & kToggled) || t > v; };
      auto inside_after = [&](std::int64_t t) { return t >= 0 && ((state[t] & kToggled) ? change.filled : values[t] > level); };
      const bool v_before = inside_now(v), v_after = change.filled;
      before += v_before ? 1 : 0;
      after += v_after ? 1 : 0;
      for (int a = 0; a < 14; ++a) {
        if (!counted_here(nb[a])) continue;
        before -= (v_before && inside_now(nb[a])) ? 1 : 0;
        after -= (v_after && inside_after(nb[a])) ? 1 : 0;
      }
      for (const auto& [a, b] : star.triangles) {
        if (!counted_here(nb[a]) || !counted_here(nb[b])) continue;
        before += (v_before && inside_now(nb[a]) && inside_now(nb[b])) ? 1 : 0;
        after += (v_after && inside_after(nb[a]) && inside_after(nb[b])) ? 1 : 0;
      }
      for (const auto& [a, b, d] : star.tetrahedra) {
        if (!counted_here(nb[a]) || !counted_here(nb[b]) || !counted_here(nb[d])) continue;
        before -= (v_before && inside_now(nb[a]) && inside_now(nb[b]) && inside_now(nb[d])) ? 1 : 0;
        after -= (v_after && inside_after(nb[a]) && inside_after(nb[b]) && inside_after(nb[d])) ? 1 : 0;
      }
    }
    for (const auto v : change.samples) state[v] &= static_cast<std::uint8_t>(~kToggled);
    change.euler_change = after - before;
    if (change.euler_change <= 0) continue;
    change.original_values.reserve(change.samples.size());
    for (const auto v : change.samples) {
      change.original_values.push_back(static_cast<double>(values[v]));
      values[v] = change.filled ? above : below;
    }
    repair.samples_changed += static_cast<std::int64_t>(change.samples.size());
    repair.changes.push_back(std::move(change));
  }
  return repair;
}

template <typename T>
void undo_impl(Grid3<T>& field, const HandleRepair& repair) {
  for (auto change = repair.changes.rbegin(); change != repair.changes.rend(); ++change)
    for (std::size_t k = 0; k < change->samples.size(); ++k)
      field.values[change->samples[k]] = static_cast<T>(change->original_values[k]);
}

template <typename T>
HandleCut cut_handles_impl(Grid3<T>& field, double level) {
  const auto state = grow_both(field, level);
  std::vector<std::int64_t> cuts, fills;
  for (std::int64_t s = 0; s < field.count(); ++s) {
    if (field.values[s] > level && !(state[s] & kInSolid)) cuts.push_back(s);
    if (field.values[s] <= level && !(state[s] & kInOutside)) fills.push_back(s);
  }
  HandleCut result;
  // The smaller change wins: cutting every handle, or filling every tunnel (and cavity).
  result.filled = fills.size() < cuts.size();
  const T below = std::nextafter(static_cast<T>(level), -std::numeric_limits<T>::max());
  const T above = std::nextafter(static_cast<T>(level), std::numeric_limits<T>::max());
  if (result.filled) {
    for (auto s : fills) field.values[s] = above;
    result.removed_samples = std::move(fills);
  } else {
    for (auto s : cuts) field.values[s] = below;
    result.removed_samples = std::move(cuts);
  }
  result.samples_removed = static_cast<std::int64_t>(result.removed_samples.size());
  return result;
}

template <typename T>
int outer_genus(const Grid3<T>& field, double level, int threads) {
  const auto components = mesh_components(contour_isosurface(field, level, threads));
  return components.empty() ? 0 : components.front().genus;
}

// The contour of the field and the genus of its largest component; the contour is kept in *mesh if given.
template <typename T>
int contour_genus(const Grid3<T>& field, double level, int threads, double minimum_fraction, Mesh* mesh) {
  Mesh contour = contour_isosurface(field, level, threads, minimum_fraction);
  const auto components = mesh_components(contour);
  if (mesh) *mesh = std::move(contour);
  return components.empty() ? 0 : components.front().genus;
}

template <typename T>
GenusRepair repair_outer_genus_impl(Grid3<T>& field, double level, int genus_before, int threads, double minimum_fraction,
                                    Mesh* final_contour) {
  GenusRepair result;
  result.outer_genus_before = genus_before >= 0 ? genus_before : outer_genus(field, level, threads);
  if (result.outer_genus_before == 0) {
    if (final_contour) *final_contour = contour_isosurface(field, level, threads, minimum_fraction);
    return result;
  }
  // The clusters of one round are judged against each other's original surroundings; a handle whose two
  // membranes interact may survive a round, so the growths are redone on the changed field (a few rounds).
  constexpr int kRounds = 4;
  for (int round = 0; round < kRounds; ++round) {
    HandleRepair more = repair_handles_impl(field, level);
    const bool changed = !more.changes.empty();
    result.per_handle.samples_changed += more.samples_changed;
    for (auto& change : more.changes) result.per_handle.changes.push_back(std::move(change));
    if (final_contour) *final_contour = Mesh{};  // the previous round's contour, freed before the next one
    if (contour_genus(field, level, threads, minimum_fraction, final_contour) == 0) {
      result.method = "per-handle";
      result.samples_changed = result.per_handle.samples_changed;
      return result;
    }
    if (!changed) break;
  }
  undo_impl(field, result.per_handle);
  result.per_handle = {};
  result.global = cut_handles_impl(field, level);
  result.method = result.global.filled ? "fill" : "cut";
  result.samples_changed = result.global.samples_removed;
  if (final_contour) *final_contour = contour_isosurface(field, level, threads, minimum_fraction);
  return result;
}

}  // namespace

HandleRepair repair_handles(Grid3<double>& field, double level) { return repair_handles_impl(field, level); }
HandleRepair repair_handles(Grid3<float>& field, double level) { return repair_handles_impl(field, level); }
void undo_handle_repair(Grid3<double>& field, const HandleRepair& repair) { undo_impl(field, repair); }
void undo_handle_repair(Grid3<float>& field, const HandleRepair& repair) { undo_impl(field, repair); }
HandleCut cut_handles(Grid3<double>& field, double level) { return cut_handles_impl(field, level); }
HandleCut cut_handles(Grid3<float>& field, double level) { return cut_handles_impl(field, level); }
GenusRepair repair_outer_genus(Grid3<double>& field, double level, int threads) {
  return repair_outer_genus_impl(field, level, -1, threads, kContourMinimumFraction, nullptr);
}
GenusRepair repair_outer_genus(Grid3<float>& field, double level, int threads) {
  return repair_outer_genus_impl(field, level, -1, threads, kContourMinimumFraction, nullptr);
}
GenusRepair repair_outer_genus(Grid3<float>& field, double level, int outer_genus_before, int threads,
                               double minimum_fraction, Mesh& final_contour) {
  return repair_outer_genus_impl(field, level, outer_genus_before, threads, minimum_fraction, &final_contour);
}

}  // namespace spheremap
