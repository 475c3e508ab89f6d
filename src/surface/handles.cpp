#include "spheremap/surface/handles.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstring>
#include <limits>
#include <stdexcept>

#include "parallel.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/surface/contour.hpp"
#include "spheremap/topology/components.hpp"

namespace spheremap {
namespace {

// The 14 neighbours of a vertex in the Freudenthal triangulation: ±e1, ±e2, ±e3, ±(e1+e2), ±(e1+e3),
// ±(e2+e3), ±(e1+e2+e3) — the edges of the six tetrahedra per cell used by contour_isosurface.
// Neighbour n ^ 1 is the opposite of neighbour n.
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

const Star& lattice_star() {
  static const Star star(lattice_link());
  return star;
}

// Per-sample state bits, one byte per sample for the whole repair.
constexpr std::uint8_t kInSolid = 1;      // reached by the solid's growth
constexpr std::uint8_t kInOutside = 2;    // reached by the outside's growth
constexpr std::uint8_t kQueued = 4;       // in the growth's queue
constexpr std::uint8_t kClustered = 8;    // in a cluster of left-out samples
constexpr std::uint8_t kToggled = 16;     // in the set whose Euler change is being counted
constexpr std::uint8_t kInside = 32;      // field > level (kept in the state so that growths read one array)
constexpr std::uint8_t kMark = 64;        // in the cluster being moved

// Neighbour access: sample index offsets, and a border test only for samples on the grid's outer layer.
// Samples that are inside, or outside but not on the border, have all 14 neighbours in the grid (the
// border is outside by precondition), which is what lets the growths use plain offsets.
class Lattice {
 public:
  explicit Lattice(const std::array<std::int64_t, 3>& size) : nx_(size[0]), ny_(size[1]), nz_(size[2]) {
    for (int n = 0; n < 14; ++n) offset_[n] = kNeighbour[n][0] + nx_ * (kNeighbour[n][1] + ny_ * kNeighbour[n][2]);
  }
  [[nodiscard]] std::int64_t count() const { return nx_ * ny_ * nz_; }
  [[nodiscard]] std::int64_t offset(int n) const { return offset_[n]; }
  [[nodiscard]] std::array<std::int64_t, 3> coordinates(std::int64_t s) const { return {s % nx_, (s / nx_) % ny_, s / (nx_ * ny_)}; }
  [[nodiscard]] bool on_border(std::int64_t s) const {
    const auto [i, j, k] = coordinates(s);
    return i == 0 || j == 0 || k == 0 || i == nx_ - 1 || j == ny_ - 1 || k == nz_ - 1;
  }
  // Calls visit(n, t) for each neighbour n of s inside the grid (t its index), visit(n, -1) outside it.
  template <typename Visit>
  void neighbours(std::int64_t s, Visit&& visit) const {
    const auto [i, j, k] = coordinates(s);
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
  // Calls visit(s) for every sample of the grid's outer layer, by increasing index.
  template <typename Visit>
  void border(Visit&& visit) const {
    for (std::int64_t k = 0; k < nz_; ++k)
      for (std::int64_t j = 0; j < ny_; ++j) {
        const std::int64_t row = nx_ * (j + ny_ * k);
        if (k == 0 || k == nz_ - 1 || j == 0 || j == ny_ - 1) {
          for (std::int64_t i = 0; i < nx_; ++i) visit(row + i);
        } else {
          visit(row);
          if (nx_ > 1) visit(row + nx_ - 1);
        }
      }
  }

 private:
  std::int64_t nx_, ny_, nz_;
  std::array<std::int64_t, 14> offset_{};
};

// The growths visit samples in the order of their depth, all over the grid, so nearly every visit
// misses the caches: the neighbourhood of a sample a few visits ahead is fetched early. Its 14 neighbours
// lie in 7 rows (offsets from the sample's row start: here, +y, -y, +z, +y+z, -z, -y-z), one or two
// cache lines each per array.
class Prefetch {
 public:
  explicit Prefetch(const std::array<std::int64_t, 3>& size) {
    const std::int64_t nx = size[0], plane = size[0] * size[1];
    rows_ = {0, nx, -nx, plane, plane + nx, -plane, -plane - nx};
  }
  template <typename V>
  void neighbourhood(const V* values, std::int64_t s) const {
    for (const auto r : rows_) __builtin_prefetch(values + s + r);
  }

 private:
  std::array<std::int64_t, 7> rows_{};
};

// A priority queue over small integer keys (smaller key first): one FIFO per key, so pushes and pops
// are O(1) and the order (first offered first within a key, which grows fronts evenly) is
// deterministic. A push below the current key moves the front back, as a heap would. Index is the
// sample index type: 32 bits whenever the grid allows, which halves the queue's memory.
template <typename Index>
class BucketQueue {
 public:
  explicit BucketQueue(std::size_t keys) : buckets_(std::max<std::size_t>(keys, 1)) {}
  void push(std::size_t key, Index sample) {
    key = std::min(key, buckets_.size() - 1);
    buckets_[key].items.push_back(sample);
    front_ = std::min(front_, key);
    ++size_;
  }
  [[nodiscard]] bool empty() const { return size_ == 0; }
  // The sample that pop() will return `ahead` calls after the next one, if it is already in the current
  // bucket (for prefetching); else null.
  [[nodiscard]] const Index* peek(std::size_t ahead) const {
    const Bucket& bucket = buckets_[front_];
    const std::size_t at = bucket.head + ahead;
    return at < bucket.items.size() ? &bucket.items[at] : nullptr;
  }
  Index pop() {
    while (buckets_[front_].head == buckets_[front_].items.size()) ++front_;
    Bucket& bucket = buckets_[front_];
    const Index s = bucket.items[bucket.head++];
    if (bucket.head == bucket.items.size()) {
      // A drained bucket gives its memory back when it held many samples (a front passing through): the
      // queue then stays as large as the fronts, not as the sum of every bucket's peak.
      if (bucket.items.capacity() > kKeptCapacity) std::vector<Index>().swap(bucket.items);
      bucket.items.clear();
      bucket.head = 0;
    }
    --size_;
    return s;
  }

 private:
  static constexpr std::size_t kKeptCapacity = 4096;
  struct Bucket {
    std::vector<Index> items;
    std::size_t head = 0;
  };
  std::vector<Bucket> buckets_;
  std::size_t front_ = 0, size_ = 0;
};

// One line of a squared distance transform: d[q] = min(cap, min_p (q - p)² + f[p]) (Felzenszwalb &
// Huttenlocher's lower envelope of parabolas). Samples at the cap cannot lower any result below it, so
// they are left out of the envelope: far from the solid most lines have few others.
void envelope_line(const double* f, double* d, std::int64_t n, double cap, std::vector<std::int64_t>& v, std::vector<double>& z) {
  v.resize(static_cast<std::size_t>(n));
  z.resize(static_cast<std::size_t>(n) + 1);
  auto meet = [&](std::int64_t p, std::int64_t q) {  // where the parabolas rooted at p < q cross
    return ((f[q] + static_cast<double>(q * q)) - (f[p] + static_cast<double>(p * p))) / (2.0 * static_cast<double>(q - p));
  };
  std::int64_t k = -1;
  for (std::int64_t q = 0; q < n; ++q) {
    if (f[q] >= cap) continue;
    if (k < 0) {
      k = 0;
      v[0] = q;
      z[0] = -std::numeric_limits<double>::infinity();
      z[1] = std::numeric_limits<double>::infinity();
      continue;
    }
    double s = meet(v[k], q);
    while (s <= z[k]) s = meet(v[--k], q);  // ends at k = 0 at the latest: z[0] = -infinity
    ++k;
    v[k] = q;
    z[k] = s;
    z[k + 1] = std::numeric_limits<double>::infinity();
  }
  if (k < 0) {
    std::fill(d, d + n, cap);
    return;
  }
  std::int64_t j = 0;
  for (std::int64_t q = 0; q < n; ++q) {
    while (z[j + 1] < static_cast<double>(q)) ++j;
    const double offset = static_cast<double>(q - v[j]);
    d[q] = std::min(cap, offset * offset + f[v[j]]);
  }
}

// How far each outside sample lies from the solid: its squared lattice distance (grid units², an
// integer) to the nearest inside sample, capped at kDepthCap. The SES field is flat (-probe) wherever a
// probe fits, so it cannot order the outside growth; this distance makes the two fronts entering a
// tunnel meet at its narrowest section. Two bytes per sample: capping every pass at kDepthCap keeps
// every value below the cap exact (a capped input only ever yields results at or above the cap).
constexpr std::uint32_t kDepthCap = 65535;

template <typename T>
std::vector<std::uint16_t> outside_depth(const Grid3<T>& field, double level, int threads) {
  const std::int64_t nx = field.size[0], ny = field.size[1], nz = field.size[2];
  std::vector<std::uint16_t> depth(static_cast<std::size_t>(field.count()));
  auto capped = [](double d) { return static_cast<std::uint16_t>(std::min(d, static_cast<double>(kDepthCap))); };
  // Along x: distance to the nearest inside sample of the row.
  detail::parallel_chunks(nz, threads, [&](std::int64_t k, int) {
    for (std::int64_t j = 0; j < ny; ++j) {
      const std::int64_t row = nx * (j + ny * k);
      const T* values = field.values.data() + row;
      std::uint16_t* out = depth.data() + row;
      constexpr std::int64_t kFar = std::int64_t{1} << 20;
      std::int64_t last = -kFar;
      for (std::int64_t i = 0; i < nx; ++i) {
        if (static_cast<double>(values[i]) > level) last = i;
        const double gap = static_cast<double>(i - last);
        out[i] = capped(gap * gap);
      }
      std::int64_t next = nx + kFar;
      for (std::int64_t i = nx - 1; i >= 0; --i) {
        if (static_cast<double>(values[i]) > level) next = i;
        const double gap = static_cast<double>(next - i);
        out[i] = std::min(out[i], capped(gap * gap));
      }
    }
  });
  // Along y, then z: lines gathered kBlock at a time (neighbours along x) for cache-friendly strides.
  constexpr std::int64_t kBlock = 16;
  auto pass = [&](std::int64_t length, std::int64_t stride, std::int64_t planes, std::int64_t plane_stride, std::int64_t lines,
                  std::int64_t line_stride) {
    // Chunk = one plane of lines (lines at line_stride, each of `length` samples at `stride`).
    std::vector<std::vector<double>> in(static_cast<std::size_t>(detail::surface_threads(threads))),
        out(in.size());
    std::vector<std::vector<std::int64_t>> vs(in.size());
    std::vector<std::vector<double>> zs(in.size());
    detail::parallel_chunks(planes, threads, [&](std::int64_t plane, int worker) {
      auto& f = in[static_cast<std::size_t>(worker)];
      auto& d = out[static_cast<std::size_t>(worker)];
      f.resize(static_cast<std::size_t>(kBlock * length));
      d.resize(f.size());
      for (std::int64_t first = 0; first < lines; first += kBlock) {
        const std::int64_t count = std::min(kBlock, lines - first);
        const std::int64_t base = plane * plane_stride + first * line_stride;
        for (std::int64_t q = 0; q < length; ++q)
          for (std::int64_t b = 0; b < count; ++b)
            f[static_cast<std::size_t>(b * length + q)] = depth[static_cast<std::size_t>(base + b * line_stride + q * stride)];
        for (std::int64_t b = 0; b < count; ++b) {
          const double* line = f.data() + b * length;
          // A line that is all zero or all at the cap needs no work.
          bool trivial = line[0] == 0 || line[0] == kDepthCap;
          for (std::int64_t q = 1; q < length && trivial; ++q) trivial = line[q] == line[0];
          if (trivial) {
            std::copy(line, line + length, d.data() + b * length);
            continue;
          }
          envelope_line(line, d.data() + b * length, length, kDepthCap, vs[static_cast<std::size_t>(worker)],
                        zs[static_cast<std::size_t>(worker)]);
        }
        for (std::int64_t q = 0; q < length; ++q)
          for (std::int64_t b = 0; b < count; ++b)
            depth[static_cast<std::size_t>(base + b * line_stride + q * stride)] = capped(d[static_cast<std::size_t>(b * length + q)]);
      }
    });
  };
  pass(ny, nx, nz, nx * ny, nx, 1);       // along y: planes k, lines i
  pass(nz, nx * ny, ny, nx, nx, 1);       // along z: planes j, lines i
  return depth;
}

// How many visits ahead the growths fetch a sample's neighbourhood.
constexpr std::size_t kPrefetchAhead = 8;

// Grows the solid by simple samples only, deepest first (by field value, in buckets of spacing/256),
// from the deepest sample of its largest piece, and marks the members kInSolid: the set stays a ball.
template <typename T, typename Index>
void grow_solid(const Grid3<T>& field, double level, const Lattice& lattice, std::uint8_t* state) {
  const auto& simple = simple_table();
  const T* values = field.values.data();
  const auto total = lattice.count();
  std::array<std::int64_t, 14> offset{};
  for (int n = 0; n < 14; ++n) offset[n] = lattice.offset(n);
  double top_value = level;
  for (std::int64_t s = 0; s < total; ++s)
    if (std::isfinite(values[s])) top_value = std::max(top_value, static_cast<double>(values[s]));
  // The seed is the deepest sample of the largest connected piece (by samples), so that the piece kept
  // whole is the main body even when a small detached piece is thicker. Pieces are labelled with the
  // queued bit, cleared afterwards. Inside samples are never on the border: plain offsets.
  std::int64_t seed = -1, seed_piece_size = 0;
  {
    std::vector<Index> stack;
    for (std::int64_t start = 0; start < total; ++start) {
      if ((state[start] & (kInside | kQueued)) != kInside) continue;
      std::int64_t size = 0, deepest = start;
      state[start] |= kQueued;
      stack.push_back(static_cast<Index>(start));
      while (!stack.empty()) {
        const auto v = static_cast<std::int64_t>(stack.back());
        stack.pop_back();
        ++size;
        if (values[v] > values[deepest] || (values[v] == values[deepest] && v < deepest)) deepest = v;
        for (int n = 0; n < 14; ++n) {
          const std::int64_t t = v + offset[n];
          if ((state[t] & (kInside | kQueued)) == kInside) state[t] |= kQueued, stack.push_back(static_cast<Index>(t));
        }
      }
      if (size > seed_piece_size) seed_piece_size = size, seed = deepest;
    }
    for (std::int64_t s = 0; s < total; ++s) state[s] &= static_cast<std::uint8_t>(~kQueued);
  }
  if (seed < 0) throw std::invalid_argument("cut_handles: nothing is inside");
  const double quantum = field.spacing / 256;
  BucketQueue<Index> frontier(static_cast<std::size_t>((top_value - level) / quantum) + 2);
  // Smaller key = deeper (further below the top value).
  auto offer_neighbours = [&](std::int64_t s) {
    for (int n = 0; n < 14; ++n) {
      const std::int64_t t = s + offset[n];
      const std::uint8_t b = state[t];
      if ((b & (kInside | kInSolid | kQueued)) != kInside) continue;
      state[t] = b | kQueued;
      const double v = static_cast<double>(values[t]);
      frontier.push(std::isfinite(v) ? static_cast<std::size_t>((top_value - v) / quantum) : 0, static_cast<Index>(t));
    }
  };
  state[seed] |= kInSolid;
  offer_neighbours(seed);
  // A sample refused now may become simple later, when more of its neighbours are in: it is offered again
  // whenever a neighbour joins (the queued bit is cleared on refusal). Each sample is offered at most 14 times.
  const Prefetch prefetch(field.size);
  while (!frontier.empty()) {
    const auto s = static_cast<std::int64_t>(frontier.pop());
    if (const Index* later = frontier.peek(kPrefetchAhead)) {
      prefetch.neighbourhood(state, static_cast<std::int64_t>(*later));
      prefetch.neighbourhood(values, static_cast<std::int64_t>(*later));
    }
    state[s] &= static_cast<std::uint8_t>(~kQueued);
    unsigned mask = 0;
    for (int n = 0; n < 14; ++n) mask |= static_cast<unsigned>(state[s + offset[n]] & kInSolid) << n;
    if (simple[mask]) {
      state[s] |= kInSolid;
      offer_neighbours(s);
    }
  }
}

// Grows the outside the same way from the whole grid border (everything beyond the grid counted in), by
// decreasing distance to the solid, and marks the members kInOutside: the set stays a shell and what it
// encloses a ball.
template <typename T, typename Index>
void grow_outside(const Grid3<T>& field, double level, const Lattice& lattice, std::uint8_t* state, int threads) {
  const auto& simple = simple_table();
  std::array<std::int64_t, 14> offset{};
  for (int n = 0; n < 14; ++n) offset[n] = lattice.offset(n);
  const std::vector<std::uint16_t> depth = outside_depth(field, level, threads);
  BucketQueue<Index> frontier(std::size_t{kDepthCap} + 1);
  // Smaller key = farther from the solid.
  auto offer = [&](std::int64_t t) {
    const std::uint8_t b = state[t];
    if (b & (kInside | kInOutside | kQueued)) return;
    state[t] = b | kQueued;
    const std::uint32_t d = depth[static_cast<std::size_t>(t)];
    frontier.push(d >= kDepthCap ? 0 : kDepthCap - d, static_cast<Index>(t));
  };
  lattice.border([&](std::int64_t s) { state[s] |= kInOutside; });
  lattice.border([&](std::int64_t s) {
    lattice.neighbours(s, [&](int, std::int64_t t) {
      if (t >= 0) offer(t);
    });
  });
  // Border samples are members from the start, so every sample popped is off the border: plain offsets.
  const Prefetch prefetch(field.size);
  while (!frontier.empty()) {
    const auto s = static_cast<std::int64_t>(frontier.pop());
    if (const Index* later = frontier.peek(kPrefetchAhead)) {
      prefetch.neighbourhood(state, static_cast<std::int64_t>(*later));
      prefetch.neighbourhood(depth.data(), static_cast<std::int64_t>(*later));
    }
    state[s] &= static_cast<std::uint8_t>(~kQueued);
    unsigned mask = 0;
    for (int n = 0; n < 14; ++n) mask |= static_cast<unsigned>((state[s + offset[n]] & kInOutside) >> 1) << n;
    if (simple[mask]) {
      state[s] |= kInOutside;
      for (int n = 0; n < 14; ++n) offer(s + offset[n]);
    }
  }
}

// Both growths, marked in one state byte per sample (plus, while the outside grows, two bytes of
// distance per sample).
template <typename T>
std::vector<std::uint8_t> grow_both(const Grid3<T>& field, double level, int threads) {
  const Lattice lattice(field.size);
  std::vector<std::uint8_t> state(static_cast<std::size_t>(field.count()), 0);
  bool any_inside = false;
  for (std::size_t s = 0; s < state.size(); ++s) {
    const bool inside = field.values[s] > level;
    state[s] = inside ? kInside : 0;
    any_inside = any_inside || inside;
  }
  if (!any_inside) throw std::invalid_argument("cut_handles: nothing is inside");
  lattice.border([&](std::int64_t s) {
    if (state[static_cast<std::size_t>(s)] & kInside) throw std::invalid_argument("cut_handles: the solid reaches the border of the grid");
  });
  if (field.count() <= static_cast<std::int64_t>(std::numeric_limits<std::uint32_t>::max())) {
    grow_solid<T, std::uint32_t>(field, level, lattice, state.data());
    grow_outside<T, std::uint32_t>(field, level, lattice, state.data(), threads);
  } else {
    grow_solid<T, std::int64_t>(field, level, lattice, state.data());
    grow_outside<T, std::int64_t>(field, level, lattice, state.data(), threads);
  }
  return state;
}

// Change of the Euler characteristic of the solid's full subcomplex when `samples` (all on one side) move
// to the other side: each simplex touching them is counted once, from its smallest toggled vertex.
// Uses the kToggled bit of `state`, cleared again.
template <typename T>
int euler_change(const Grid3<T>& field, double level, const std::vector<std::int64_t>& samples, bool filled, std::uint8_t* state) {
  const Star& star = lattice_star();
  const Lattice lattice(field.size);
  const T* values = field.values.data();
  for (const auto v : samples) state[v] |= kToggled;
  auto inside_now = [&](std::int64_t t) { return t >= 0 && values[t] > level; };
  int before = 0, after = 0;
  for (const auto v : samples) {
    std::array<std::int64_t, 14> nb{};
    lattice.neighbours(v, [&](int n, std::int64_t t) { nb[n] = t; });
    auto counted_here = [&](std::int64_t t) { return t < 0 || !(state[t] & kToggled) || t > v; };
    auto inside_after = [&](std::int64_t t) { return t >= 0 && ((state[t] & kToggled) ? filled : values[t] > level); };
    const bool v_before = inside_now(v), v_after = filled;
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
  for (const auto v : samples) state[v] &= static_cast<std::uint8_t>(~kToggled);
  return after - before;
}

// The area of contour_isosurface's triangles in the cells that have a corner in `samples`, computed as
// contour_isosurface computes them (same tetrahedra, same vertex positions), so that the difference of
// two calls is exactly what a change does to the area of the contour.
constexpr std::array<std::array<int, 3>, 8> kCellCorner = {{{0, 0, 0}, {1, 0, 0}, {0, 1, 0}, {1, 1, 0},
                                                            {0, 0, 1}, {1, 0, 1}, {0, 1, 1}, {1, 1, 1}}};
constexpr std::array<std::array<int, 4>, 6> kCellTetrahedra = {{{0, 1, 3, 7}, {0, 1, 5, 7}, {0, 2, 3, 7},
                                                                {0, 2, 6, 7}, {0, 4, 5, 7}, {0, 4, 6, 7}}};

template <typename T>
double cell_area(const Grid3<T>& field, std::int64_t i, std::int64_t j, std::int64_t k, double level, double minimum_fraction) {
  std::array<double, 8> value{};
  std::array<Vec3, 8> point{};
  for (int c = 0; c < 8; ++c) {
    const auto a = i + kCellCorner[c][0], b = j + kCellCorner[c][1], d = k + kCellCorner[c][2];
    value[c] = static_cast<double>(field.values[static_cast<std::size_t>(field.index(a, b, d))]);
    point[c] = field.point(a, b, d);
  }
  // A vertex on the edge between corners c1 < c2: c1 is the lower sample, as in contour_isosurface.
  auto vertex = [&](int c1, int c2) {
    const int a = std::min(c1, c2), b = std::max(c1, c2);
    const double t = std::clamp((level - value[a]) / (value[b] - value[a]), minimum_fraction, 1 - minimum_fraction);
    return point[a] + t * (point[b] - point[a]);
  };
  double area = 0;
  for (const auto& tet : kCellTetrahedra) {
    std::array<int, 4> in{}, out{};
    int n_in = 0, n_out = 0;
    for (const int v : tet) (value[v] > level ? in[n_in++] : out[n_out++]) = v;
    if (n_in == 0 || n_out == 0) continue;
    if (n_in == 1) {
      area += triangle_area(vertex(in[0], out[0]), vertex(in[0], out[1]), vertex(in[0], out[2]));
    } else if (n_in == 3) {
      area += triangle_area(vertex(in[0], out[0]), vertex(in[1], out[0]), vertex(in[2], out[0]));
    } else {
      const Vec3 a = vertex(in[0], out[0]), b = vertex(in[0], out[1]), c = vertex(in[1], out[1]), d = vertex(in[1], out[0]);
      area += triangle_area(a, b, c) + triangle_area(a, c, d);
    }
  }
  return area;
}

// The change of the contour's area (all components) if `samples` take `value`. The field is left as it was.
template <typename T>
double area_change(Grid3<T>& field, double level, double minimum_fraction, const std::vector<std::int64_t>& samples, T value) {
  const auto [nx, ny, nz] = field.size;
  std::vector<std::int64_t> cells;
  cells.reserve(samples.size() * 8);
  for (const auto s : samples) {
    const std::int64_t i = s % nx, j = (s / nx) % ny, k = s / (nx * ny);
    for (std::int64_t dk = -1; dk <= 0; ++dk)
      for (std::int64_t dj = -1; dj <= 0; ++dj)
        for (std::int64_t di = -1; di <= 0; ++di)
          if (i + di >= 0 && j + dj >= 0 && k + dk >= 0 && i + di + 1 < nx && j + dj + 1 < ny && k + dk + 1 < nz)
            cells.push_back(field.index(i + di, j + dj, k + dk));
  }
  std::sort(cells.begin(), cells.end());
  cells.erase(std::unique(cells.begin(), cells.end()), cells.end());
  auto area = [&] {
    double sum = 0;
    for (const auto c : cells) sum += cell_area(field, c % nx, (c / nx) % ny, c / (nx * ny), level, minimum_fraction);
    return sum;
  };
  const double before = area();
  std::vector<T> original;
  original.reserve(samples.size());
  for (const auto s : samples) original.push_back(field.values[static_cast<std::size_t>(s)]), field.values[static_cast<std::size_t>(s)] = value;
  const double after = area();
  for (std::size_t k = 0; k < samples.size(); ++k) field.values[static_cast<std::size_t>(samples[k])] = original[k];
  return after - before;
}


template <typename T>
HandleRepair repair_handles_impl(Grid3<T>& field, double level, double minimum_fraction, int threads) {
  auto state = grow_both(field, level, threads);
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
    change.euler_change = euler_change(field, level, change.samples, change.filled, state.data());
    if (change.euler_change <= 0) continue;
    change.area_change = area_change(field, level, minimum_fraction, change.samples, change.filled ? above : below);
    change.original_values.reserve(change.samples.size());
    for (const auto v : change.samples) {
      change.original_values.push_back(static_cast<double>(values[v]));
      values[v] = change.filled ? above : below;
    }
    repair.samples_changed += static_cast<std::int64_t>(change.samples.size());
    repair.area_change += change.area_change;
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
HandleCut cut_handles_impl(Grid3<T>& field, double level, double minimum_fraction, int threads) {
  const auto state = grow_both(field, level, threads);
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
  auto& chosen = result.filled ? fills : cuts;
  result.area_change = area_change(field, level, minimum_fraction, chosen, result.filled ? above : below);
  for (auto s : chosen) field.values[s] = result.filled ? above : below;
  result.removed_samples = std::move(chosen);
  result.samples_removed = static_cast<std::int64_t>(result.removed_samples.size());
  return result;
}

// The genus of the largest component of the field's contour; the contour is kept in *mesh if given.
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
  result.outer_genus_before = genus_before >= 0 ? genus_before : contour_genus(field, level, threads, minimum_fraction, nullptr);
  if (result.outer_genus_before == 0) {
    if (final_contour) *final_contour = contour_isosurface(field, level, threads, minimum_fraction);
    return result;
  }
  // Interactions beyond those counted (a change that encloses a void or splits off a piece counts as a
  // handle removed) can leave handles after a round: the growths are then redone on the changed field.
  constexpr int kRounds = 4;
  for (int round = 0; round < kRounds; ++round) {
    HandleRepair more = repair_handles_impl(field, level, minimum_fraction, threads);
    const bool changed = !more.changes.empty();
    result.per_handle.samples_changed += more.samples_changed;
    result.per_handle.area_change += more.area_change;
    for (auto& change : more.changes) result.per_handle.changes.push_back(std::move(change));
    if (final_contour) *final_contour = Mesh{};  // the previous round's contour, freed before the next one
    if (contour_genus(field, level, threads, minimum_fraction, final_contour) == 0) {
      result.method = "per-handle";
      result.samples_changed = result.per_handle.samples_changed;
      result.rounds = round + 1;
      return result;
    }
    if (!changed) break;
  }
  undo_impl(field, result.per_handle);
  result.per_handle = {};
  result.global = cut_handles_impl(field, level, minimum_fraction, threads);
  result.method = result.global.filled ? "fill" : "cut";
  result.samples_changed = result.global.samples_removed;
  if (final_contour) *final_contour = contour_isosurface(field, level, threads, minimum_fraction);
  return result;
}

}  // namespace

HandleRepair repair_handles(Grid3<double>& field, double level, double minimum_fraction, int threads) {
  return repair_handles_impl(field, level, minimum_fraction, threads);
}
HandleRepair repair_handles(Grid3<float>& field, double level, double minimum_fraction, int threads) {
  return repair_handles_impl(field, level, minimum_fraction, threads);
}
void undo_handle_repair(Grid3<double>& field, const HandleRepair& repair) { undo_impl(field, repair); }
void undo_handle_repair(Grid3<float>& field, const HandleRepair& repair) { undo_impl(field, repair); }
HandleCut cut_handles(Grid3<double>& field, double level, double minimum_fraction, int threads) {
  return cut_handles_impl(field, level, minimum_fraction, threads);
}
HandleCut cut_handles(Grid3<float>& field, double level, double minimum_fraction, int threads) {
  return cut_handles_impl(field, level, minimum_fraction, threads);
}
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
