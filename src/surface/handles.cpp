#include "spheremap/surface/handles.hpp"

#include <algorithm>
#include <array>
#include <atomic>
#include <cmath>
#include <cstring>
#include <exception>
#include <limits>
#include <memory>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <thread>
#include <utility>

#include "handles_tuning.hpp"
#include "../util/parallel.hpp"
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

// The two growths run at once on two threads (grow_both). Each writes only the state bytes of its own
// side's samples (the solid's growth the inside ones, the outside's the outside ones), and reads the other
// side's bytes only for bits that never change there (kInside) or that only its own side ever has (its
// member bit): each decision is the one it would be with the growths one after the other. The bytes are
// still shared, so they are read and written as relaxed atomics (plain moves on x86-64); a byte has one
// writer, so a load then a store is a safe update.
inline std::uint8_t load_state(const std::uint8_t* state, std::int64_t s) {
  return std::atomic_ref<std::uint8_t>(const_cast<std::uint8_t&>(state[s])).load(std::memory_order_relaxed);
}
inline void store_state(std::uint8_t* state, std::int64_t s, std::uint8_t value) {
  std::atomic_ref<std::uint8_t>(state[s]).store(value, std::memory_order_relaxed);
}

// Grows the solid by simple samples only, deepest first (by field value, in buckets of spacing/256),
// from the deepest sample of its largest piece, and marks the members kInSolid: the set stays a ball.
// Touches the kQueued and kInSolid bits of inside samples only.
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
      const std::uint8_t b = load_state(state, start);
      if ((b & (kInside | kQueued)) != kInside) continue;
      std::int64_t size = 0, deepest = start;
      store_state(state, start, b | kQueued);
      stack.push_back(static_cast<Index>(start));
      while (!stack.empty()) {
        const auto v = static_cast<std::int64_t>(stack.back());
        stack.pop_back();
        ++size;
        if (values[v] > values[deepest] || (values[v] == values[deepest] && v < deepest)) deepest = v;
        for (int n = 0; n < 14; ++n) {
          const std::int64_t t = v + offset[n];
          const std::uint8_t bt = load_state(state, t);
          if ((bt & (kInside | kQueued)) == kInside) store_state(state, t, bt | kQueued), stack.push_back(static_cast<Index>(t));
        }
      }
      if (size > seed_piece_size) seed_piece_size = size, seed = deepest;
    }
    for (std::int64_t s = 0; s < total; ++s) {
      const std::uint8_t b = load_state(state, s);
      if ((b & (kInside | kQueued)) == (kInside | kQueued)) store_state(state, s, b & static_cast<std::uint8_t>(~kQueued));
    }
  }
  if (seed < 0) throw std::invalid_argument("cut_handles: nothing is inside");
  const double quantum = field.spacing / 256;
  BucketQueue<Index> frontier(static_cast<std::size_t>((top_value - level) / quantum) + 2);
  // Smaller key = deeper (further below the top value).
  auto offer_neighbours = [&](std::int64_t s) {
    for (int n = 0; n < 14; ++n) {
      const std::int64_t t = s + offset[n];
      const std::uint8_t b = load_state(state, t);
      if ((b & (kInside | kInSolid | kQueued)) != kInside) continue;
      store_state(state, t, b | kQueued);
      const double v = static_cast<double>(values[t]);
      frontier.push(std::isfinite(v) ? static_cast<std::size_t>((top_value - v) / quantum) : 0, static_cast<Index>(t));
    }
  };
  store_state(state, seed, load_state(state, seed) | kInSolid);
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
    const std::uint8_t b = load_state(state, s) & static_cast<std::uint8_t>(~kQueued);
    unsigned mask = 0;
    for (int n = 0; n < 14; ++n) mask |= static_cast<unsigned>(load_state(state, s + offset[n]) & kInSolid) << n;
    if (simple[mask]) {
      store_state(state, s, b | kInSolid);
      offer_neighbours(s);
    } else {
      store_state(state, s, b);
    }
  }
}

// Grows the outside the same way from the whole grid border (everything beyond the grid counted in), by
// decreasing distance to the solid (`depth`, outside_depth), and marks the members kInOutside: the set
// stays a shell and what it encloses a ball. Touches the kQueued and kInOutside bits of outside samples only.
template <typename Index>
void grow_outside(const Lattice& lattice, const std::array<std::int64_t, 3>& size, const std::vector<std::uint16_t>& depth,
                  std::uint8_t* state) {
  const auto& simple = simple_table();
  std::array<std::int64_t, 14> offset{};
  for (int n = 0; n < 14; ++n) offset[n] = lattice.offset(n);
  BucketQueue<Index> frontier(std::size_t{kDepthCap} + 1);
  // Smaller key = farther from the solid.
  auto offer = [&](std::int64_t t) {
    const std::uint8_t b = load_state(state, t);
    if (b & (kInside | kInOutside | kQueued)) return;
    store_state(state, t, b | kQueued);
    const std::uint32_t d = depth[static_cast<std::size_t>(t)];
    frontier.push(d >= kDepthCap ? 0 : kDepthCap - d, static_cast<Index>(t));
  };
  lattice.border([&](std::int64_t s) { store_state(state, s, load_state(state, s) | kInOutside); });
  lattice.border([&](std::int64_t s) {
    lattice.neighbours(s, [&](int, std::int64_t t) {
      if (t >= 0) offer(t);
    });
  });
  // Border samples are members from the start, so every sample popped is off the border: plain offsets.
  const Prefetch prefetch(size);
  while (!frontier.empty()) {
    const auto s = static_cast<std::int64_t>(frontier.pop());
    if (const Index* later = frontier.peek(kPrefetchAhead)) {
      prefetch.neighbourhood(state, static_cast<std::int64_t>(*later));
      prefetch.neighbourhood(depth.data(), static_cast<std::int64_t>(*later));
    }
    const std::uint8_t b = load_state(state, s) & static_cast<std::uint8_t>(~kQueued);
    unsigned mask = 0;
    for (int n = 0; n < 14; ++n) mask |= static_cast<unsigned>((load_state(state, s + offset[n]) & kInOutside) >> 1) << n;
    if (simple[mask]) {
      store_state(state, s, b | kInOutside);
      for (int n = 0; n < 14; ++n) offer(s + offset[n]);
    } else {
      store_state(state, s, b);
    }
  }
}

// Both growths, marked in one state byte per sample (plus, while they run, two bytes of distance per
// sample). With more than one thread the two growths run at once (see load_state).
template <typename T, typename Index>
void grow_both_with(const Grid3<T>& field, double level, const Lattice& lattice, std::uint8_t* state, int threads) {
  const std::vector<std::uint16_t> depth = outside_depth(field, level, threads);
  std::optional<std::thread> solid_thread;
  std::exception_ptr solid_error;
  if (detail::surface_threads(threads) > 1) {
    try {
      solid_thread.emplace([&] {
        try {
          grow_solid<T, Index>(field, level, lattice, state);
        } catch (...) {
          solid_error = std::current_exception();
        }
      });
    } catch (const std::system_error&) {
      // No second thread (solid_thread stays empty): one growth after the other.
    }
  }
  if (!solid_thread) grow_solid<T, Index>(field, level, lattice, state);
  try {
    grow_outside<Index>(lattice, field.size, depth, state);
  } catch (...) {
    if (solid_thread) solid_thread->join();
    throw;
  }
  if (solid_thread) solid_thread->join();
  if (solid_error) std::rethrow_exception(solid_error);
}

// `threads`: 0 for one per hardware thread, as the public functions take it.
template <typename T>
std::vector<std::uint8_t> grow_both(const Grid3<T>& field, double level, int threads) {
  threads = detail::surface_threads(threads);  // parallel_chunks takes a count: 0 would run one thread
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
  if (field.count() <= static_cast<std::int64_t>(std::numeric_limits<std::uint32_t>::max()))
    grow_both_with<T, std::uint32_t>(field, level, lattice, state.data(), threads);
  else
    grow_both_with<T, std::int64_t>(field, level, lattice, state.data(), threads);
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

// Puts back the field values a change replaced (its samples' original_values).
template <typename T>
void restore_change(T* values, const TopologyChange& change) {
  for (std::size_t k = 0; k < change.samples.size(); ++k) values[change.samples[k]] = static_cast<T>(change.original_values[k]);
}

// Whether a change just applied (its samples already on their new side) split the side they left around
// it (a piece cut off the solid, or a pocket of the outside closed off), or left its samples apart from
// their new side (a floating piece, an enclosed void). Either raises the Euler characteristic as a removed
// handle does, but removes none. The side left is searched breadth first from every sample next to the
// change, one label per start, labels joined where their searches meet (union-find); a label all of whose
// samples are searched while other labels remain is a piece apart. Everything beyond the grid belongs to
// the outside. After `budget` samples searched (or twice as many found) besides those next to the change,
// the search stops and the change counts as harmless: a larger piece is left to the next round of
// repair_outer_genus, as before this check.
template <typename T>
bool splits_its_side(const Lattice& lattice, const T* values, double level, const std::vector<std::int64_t>& moved,
                     bool left_inside, std::int64_t budget) {
  const bool new_inside = !left_inside;
  auto on_side = [&](std::int64_t t, bool inside) { return t >= 0 && (values[t] > level) == inside; };
  auto is_moved = [&](std::int64_t t) { return std::binary_search(moved.begin(), moved.end(), t); };
  bool joins_new_side = false;
  for (const auto s : moved) {
    lattice.neighbours(s, [&](int, std::int64_t t) {
      joins_new_side = joins_new_side || (t < 0 ? !new_inside : on_side(t, new_inside) && !is_moved(t));
    });
    if (joins_new_side) break;
  }
  if (!joins_new_side) return true;
  constexpr std::int64_t kEndless = std::numeric_limits<std::int64_t>::max() / 2;
  std::vector<int> parent;
  std::vector<std::int64_t> pending;  // per root: samples of its label queued and not yet searched
  int roots = 0;
  auto make_label = [&](std::int64_t queued) {
    parent.push_back(static_cast<int>(parent.size()));
    pending.push_back(queued);
    ++roots;
    return parent.back();
  };
  auto find = [&](int a) {
    while (parent[static_cast<std::size_t>(a)] != a) a = parent[static_cast<std::size_t>(a)] = parent[static_cast<std::size_t>(parent[static_cast<std::size_t>(a)])];
    return a;
  };
  auto unite = [&](int a, int b) {
    a = find(a), b = find(b);
    if (a == b) return;
    if (b < a) std::swap(a, b);
    parent[static_cast<std::size_t>(b)] = a;
    pending[static_cast<std::size_t>(a)] += pending[static_cast<std::size_t>(b)];
    --roots;
  };
  const int beyond = left_inside ? -1 : make_label(kEndless);  // the outside beyond the grid never runs out
  // Sample -> label, open addressing: the searches are small and many (one per change applied).
  std::size_t capacity = 1024;
  while (capacity < 4 * static_cast<std::size_t>(budget) + 64 * moved.size()) capacity *= 2;
  std::vector<std::int64_t> keys(capacity, -1);
  std::vector<int> values_of(capacity);
  std::size_t stored = 0;
  // The slot of t: its label (existing), or where to store it (keys[slot] == -1).
  auto slot_of = [&](std::int64_t t) {
    auto slot = static_cast<std::size_t>((static_cast<std::uint64_t>(t) * 0x9E3779B97F4A7C15ull) >> 20) & (capacity - 1);
    while (keys[slot] != -1 && keys[slot] != t) slot = (slot + 1) & (capacity - 1);
    return slot;
  };
  std::vector<std::pair<std::int64_t, int>> queue;
  for (const auto s : moved)
    lattice.neighbours(s, [&](int, std::int64_t t) {
      if (t < 0 || !on_side(t, left_inside)) return;
      const auto slot = slot_of(t);
      if (keys[slot] != -1) return;
      keys[slot] = t;
      values_of[slot] = make_label(1);
      ++stored;
      queue.emplace_back(t, values_of[slot]);
    });
  budget += static_cast<std::int64_t>(queue.size());
  for (std::size_t head = 0; head < queue.size() && roots > 1; ++head) {
    if (static_cast<std::int64_t>(head) >= budget || 2 * stored > capacity) return false;
    const auto [u, label] = queue[head];
    lattice.neighbours(u, [&](int, std::int64_t t) {
      if (t < 0) {
        if (beyond >= 0) unite(label, beyond);
        return;
      }
      if (!on_side(t, left_inside)) return;
      const auto slot = slot_of(t);
      if (keys[slot] != -1) {
        unite(label, values_of[slot]);
        return;
      }
      keys[slot] = t;
      values_of[slot] = label;
      ++stored;
      queue.emplace_back(t, label);
      ++pending[static_cast<std::size_t>(find(label))];
    });
    const int root = find(label);
    if (--pending[static_cast<std::size_t>(root)] == 0 && roots > 1) return true;
  }
  return false;
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

// The values a repair gives the samples it moves inside (filled) and outside (cut): half a grid step
// past the level, as if the surface ran along the faces of their voxels. Just past the level (the
// smallest change of sign), the contour runs through the moved samples themselves, and a membrane one
// sample thick became two faces a hair apart: a needless sliver, and 10–25% more area added per
// closure (measured on the ten structures whose repair added more than 1% at a 1 Å grid).
template <typename T>
std::pair<T, T> moved_sample_values(double level, double spacing) {
  const T just_below = std::nextafter(static_cast<T>(level), -std::numeric_limits<T>::max());
  const T just_above = std::nextafter(static_cast<T>(level), std::numeric_limits<T>::max());
  return {std::min(just_below, static_cast<T>(level - 0.5 * spacing)), std::max(just_above, static_cast<T>(level + 0.5 * spacing))};
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


// Moving a membrane to the thinnest section of its handle or tunnel nearby. The growths put a membrane
// where their two fronts meet: where the handle is thinnest or the tunnel narrowest by the depth that
// orders them (an inscribed radius), which is not where its cross-section is smallest (a slit is narrow
// but wide). Within `reach` lattice steps of the membrane, the sides of the handle (or tunnel) are
// labelled by a breadth-first race from the membrane's faces (the connected groups of grown samples next
// to it) through the grown set; a minimum vertex cut (max-flow, unit capacity per sample) then
// separates the far ends of the sides (where the race stopped, or where two sides met again around the
// handle) through the sides and the membrane: the smallest cross-section within reach, in samples. A
// cluster where several membranes meet (more than two faces) gets the union of the cuts isolating each
// face from the others, all but the largest (the classic approximation of a multiway cut). The caller
// checks what the new membrane changes (Euler characteristic, area) before using it.
class MembraneMover {
 public:
  MembraneMover(const Lattice& lattice, const std::array<std::int64_t, 3>& size, std::uint8_t* state, int reach)
      : lattice_(lattice), size_(size), state_(state), reach_(reach) {}

  // Completes a new membrane (every sample within the box of the last move, all on the side `inside`)
  // with what changing it would enclose or split off: the samples of its side next to it, connected
  // through that side within the box, that do not reach the box's outer layer (a handle's or a tunnel's
  // sides lead out of the box; a crevice at the rim of a fill, closed by it, does not). Changed too, they
  // leave no void (or piece) that the Euler characteristic would count as a handle removed. Returns false
  // if the membrane is a cut that does not touch the outside. `is_inside(s)`: whether sample s is inside.
  template <typename Inside>
  bool complete(std::vector<std::int64_t>& membrane, bool inside, Inside&& is_inside) {
    seen_.assign(static_cast<std::size_t>(count_), 0);
    for (const auto s : membrane) seen_[static_cast<std::size_t>(local(s))] = 1;
    bool touches_outside = false;
    std::vector<std::int64_t> enclosed, group, stack;
    const std::size_t size = membrane.size();
    for (std::size_t k = 0; k < size; ++k) {
      const std::int64_t b = local(membrane[k]);
      for (int n = 0; n < 14; ++n) {
        const std::int64_t start = b + offset_[n];
        const bool side = is_inside(global(start));
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
            if (seen_[static_cast<std::size_t>(t)] || is_inside(global(t)) != inside) continue;
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

  // The new membrane (sorted sample indices) if one with fewer samples than `membrane` exists, else empty.
  // `member_bit`: kInSolid for a cut (the membrane's samples are inside), kInOutside for a fill.
  std::vector<std::int64_t> move(const std::vector<std::int64_t>& membrane, std::uint8_t member_bit) {
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

 private:
  // Labels: 0 none, sides 1 to kMaxFaces, then the membrane and samples waiting for their side.
  static constexpr std::uint8_t kNone = 0, kMaxFaces = 8, kFace = 254, kPending = 255;
  static constexpr std::int8_t kNoArc = -1, kTerminal = 14;
  static constexpr std::int64_t kSink = -2, kMaxBoxSamples = std::int64_t{1} << 22;
  // Search trees of the maximum flow, and a node's parent when it has none (orphan or free) or is a root.
  static constexpr std::uint8_t kFree = 0, kSourceTree = 1, kSinkTree = 2;
  static constexpr std::int32_t kNoParent = -1, kRootParent = -2;
  [[nodiscard]] static bool is_side(std::uint8_t label) { return label != kNone && label <= kMaxFaces; }

  bool set_box(const std::vector<std::int64_t>& membrane) {
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
    for (int n = 0; n < 14; ++n) offset_[n] = kNeighbour[n][0] + extent_[0] * (kNeighbour[n][1] + extent_[1] * kNeighbour[n][2]);
    return true;
  }
  [[nodiscard]] std::int64_t local(std::int64_t s) const {
    const auto c = lattice_.coordinates(s);
    return (c[0] - low_[0]) + extent_[0] * ((c[1] - low_[1]) + extent_[1] * (c[2] - low_[2]));
  }
  [[nodiscard]] std::int64_t global(std::int64_t b) const {
    const std::int64_t a = b % extent_[0], c = (b / extent_[0]) % extent_[1], d = b / (extent_[0] * extent_[1]);
    return (low_[0] + a) + size_[0] * ((low_[1] + c) + size_[1] * (low_[2] + d));
  }
  // Off the box's outer layer: the box's margin (reach + 1) keeps every labelled sample there, and where
  // the box is clipped by the grid this also keeps the grid's border out of any membrane.
  [[nodiscard]] bool interior(std::int64_t b) const {
    const std::int64_t a = b % extent_[0], c = (b / extent_[0]) % extent_[1], d = b / (extent_[0] * extent_[1]);
    return a > 0 && c > 0 && d > 0 && a + 1 < extent_[0] && c + 1 < extent_[1] && d + 1 < extent_[2];
  }

  // Labels the grown samples next to the membrane by face (connected groups), then the grown samples
  // within reach by the face they are reached from first; finds the terminals (labelled by side).
  // Returns the number of faces (0 if more than kMaxFaces, or if some face has no terminal).
  int label_sides(const std::vector<std::int64_t>& membrane, std::uint8_t member_bit) {
    auto member = [&](std::int64_t b) { return interior(b) && (state_[global(b)] & member_bit) != 0; };
    std::vector<std::int64_t> next_to;
    for (const auto s : membrane) {
      const std::int64_t b = local(s);
      for (int n = 0; n < 14; ++n) {
        const std::int64_t t = b + offset_[n];
        if (label_[static_cast<std::size_t>(t)] == kNone && member(t)) label_[static_cast<std::size_t>(t)] = kPending, next_to.push_back(t);
      }
    }
    int faces = 0;
    std::vector<std::int64_t> stack;
    for (const auto start : next_to) {
      if (label_[static_cast<std::size_t>(start)] != kPending) continue;
      if (++faces > kMaxFaces) return 0;
      label_[static_cast<std::size_t>(start)] = static_cast<std::uint8_t>(faces);
      stack.push_back(start);
      while (!stack.empty()) {
        const auto b = stack.back();
        stack.pop_back();
        for (int n = 0; n < 14; ++n) {
          const std::int64_t t = b + offset_[n];
          if (label_[static_cast<std::size_t>(t)] == kPending) label_[static_cast<std::size_t>(t)] = static_cast<std::uint8_t>(faces), stack.push_back(t);
        }
      }
    }
    if (faces < 2) return 0;
    region_ = next_to;
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

  // Residual arcs of the split graph (node 2b: into sample b, 2b + 1: out of it): into b -> out of b
  // (capacity 1, if unused), into b -> out of its predecessor (cancelling that flow), out of b -> the
  // sink (if b is a sink terminal), out of b -> into b (cancelling b's flow), out of b -> into each
  // labelled neighbour (unbounded) except across the two sides.
  [[nodiscard]] int arcs(std::int64_t x) const { return (x & 1) ? 16 : 2; }
  [[nodiscard]] std::int64_t target(std::int64_t x, int slot) const {
    const std::int64_t b = x >> 1;
    const auto ub = static_cast<std::size_t>(b);
    if ((x & 1) == 0) {
      if (slot == 0) return used_[ub] ? -1 : x + 1;
      const auto p = previous_[ub];
      return (p >= 0 && p < kTerminal) ? 2 * (b + offset_[p]) + 1 : -1;
    }
    if (slot == 0) return (terminal_[ub] != 0 && terminal_[ub] != source_side_) ? kSink : -1;
    if (slot == 1) return used_[ub] ? x - 1 : -1;
    const std::int64_t t = b + offset_[slot - 2];
    return joined(label_[ub], label_[static_cast<std::size_t>(t)]) ? 2 * t : -1;
  }

  // Whether out of a labelled sample (label `from`) leads into its neighbour (label `to`): the neighbour
  // is labelled too, and the two are not on different sides.
  [[nodiscard]] static bool joined(std::uint8_t from, std::uint8_t to) {
    return to != kNone && to != kPending && !(is_side(from) && is_side(to) && from != to);
  }

  // Calls visit(y, slot) for every node y with a residual arc from node x (y = target(x, slot); the sink
  // left out).
  template <typename Visit>
  void residual_from(std::int64_t x, Visit&& visit) const {
    for (int slot = 0; slot < arcs(x); ++slot)
      if (const std::int64_t y = target(x, slot); y >= 0) visit(y, slot);
  }

  // Calls visit(q, slot) for every node q with a residual arc into node x (target(q, slot) == x).
  template <typename Visit>
  void residual_into(std::int64_t x, Visit&& visit) const {
    const std::int64_t b = x >> 1;
    const auto ub = static_cast<std::size_t>(b);
    if ((x & 1) == 0) {
      if (used_[ub]) visit(x + 1, 1);  // out of b -> into b (cancelling b's flow)
      const auto lb = label_[ub];
      for (int n = 0; n < 14; ++n) {  // out of each labelled neighbour -> into b (unbounded)
        const std::int64_t t = b + offset_[n];
        if (joined(lb, label_[static_cast<std::size_t>(t)])) visit(2 * t + 1, 2 + (n ^ 1));
      }
      return;
    }
    if (!used_[ub]) visit(x - 1, 0);  // into b -> out of b
    const auto n = next_[ub];
    if (n >= 0 && n < kTerminal) visit(2 * (b + offset_[n]), 1);  // into t -> out of b (cancelling b's flow to t)
  }

  // The depth of node x in its search tree (a root is 1) if its parents still lead to a terminal, else
  // -1 (an orphan on the way). The nodes walked are stamped with `time` and their depths.
  std::int32_t rooted_depth(std::int64_t x, std::int32_t time) {
    std::int32_t depth = 0;
    for (std::int64_t u = x;; u = parent_[static_cast<std::size_t>(u)]) {
      const auto uu = static_cast<std::size_t>(u);
      if (stamp_[uu] == time) {
        depth += depth_[uu];
        break;
      }
      if (parent_[uu] == kNoParent) return -1;
      ++depth;
      if (parent_[uu] == kRootParent) break;
    }
    std::int32_t at = depth;
    for (std::int64_t u = x; stamp_[static_cast<std::size_t>(u)] != time; u = parent_[static_cast<std::size_t>(u)]) {
      stamp_[static_cast<std::size_t>(u)] = time;
      depth_[static_cast<std::size_t>(u)] = at--;
      if (parent_[static_cast<std::size_t>(u)] == kRootParent) break;
    }
    return depth;
  }

  // Adds to the flow already in used_, next_ and previous_ (shortest_path_phases') until the flow from
  // the terminals of source_side_ to those of the other sides is maximal, and returns the units added,
  // or `limit` as soon as it has added that many; the flow is left in used_, next_ and previous_.
  // Boykov & Kolmogorov's algorithm (2004): a search tree grows from the sources and one from the
  // sinks; where they touch, one unit goes through; the nodes cut off by the saturated arcs (orphans)
  // find new parents in their tree or are freed. The trees are kept from one path to the next, where
  // Dinic's phases search the whole region afresh (82 phases over 90k samples for one membrane of 5hr7
  // at 0.25 Å). Any maximum flow leaves the same samples reachable from the sources, so the cut does not
  // depend on the algorithm.
  std::int64_t maximum_flow(std::int64_t limit) {
    const auto nodes = static_cast<std::size_t>(2 * count_);
    tree_.assign(nodes, kFree);
    parent_.assign(nodes, kNoParent);
    parent_slot_.assign(nodes, 0);
    stamp_.assign(nodes, 0);
    depth_.assign(nodes, 0);
    is_active_.assign(nodes, 0);
    active_.clear();
    std::size_t head = 0;
    auto activate = [&](std::int64_t x) {
      if (is_active_[static_cast<std::size_t>(x)]) return;
      is_active_[static_cast<std::size_t>(x)] = 1;
      active_.push_back(x);
    };
    auto join = [&](std::int64_t x, std::uint8_t tree, std::int64_t parent, int slot) {
      const auto ux = static_cast<std::size_t>(x);
      tree_[ux] = tree;
      parent_[ux] = static_cast<std::int32_t>(parent);
      parent_slot_[ux] = static_cast<std::uint8_t>(slot);
      if (parent >= 0) stamp_[ux] = stamp_[static_cast<std::size_t>(parent)], depth_[ux] = depth_[static_cast<std::size_t>(parent)] + 1;
      else depth_[ux] = 1;
      activate(x);
    };
    for (const auto b : region_) {
      const auto side = terminal_[static_cast<std::size_t>(b)];
      if (side == source_side_) join(2 * b, kSourceTree, kRootParent, 0);
      else if (side != 0) join(2 * b + 1, kSinkTree, kRootParent, 0);
    }
    std::int64_t flow = 0;
    std::int32_t time = 0;
    for (;;) {
      // Grow the trees until they touch: target(from, via) == to, from in the source tree, to in the sink tree.
      std::int64_t from = -1, to = -1;
      int via = 0;
      while (head < active_.size() && from < 0) {
        const std::int64_t x = active_[head];
        const auto tree = tree_[static_cast<std::size_t>(x)];
        if (tree == kSourceTree) {
          // (The sink is left out: the nodes with an arc to it root the sink tree for good.)
          residual_from(x, [&](std::int64_t y, int slot) {
            if (from >= 0) return;
            const auto other = tree_[static_cast<std::size_t>(y)];
            if (other == kFree) join(y, kSourceTree, x, slot);
            else if (other == kSinkTree) from = x, via = slot, to = y;
          });
        } else if (tree == kSinkTree) {
          residual_into(x, [&](std::int64_t q, int slot) {
            if (from >= 0) return;
            const auto other = tree_[static_cast<std::size_t>(q)];
            if (other == kFree) join(q, kSinkTree, x, slot);
            else if (other == kSourceTree) from = q, via = slot, to = x;
          });
        }
        if (from < 0) is_active_[static_cast<std::size_t>(x)] = 0, ++head;  // done with x (it stays first if it touched)
      }
      if (from < 0) return flow;
      if (head > 4096 && head * 2 > active_.size()) active_.erase(active_.begin(), active_.begin() + static_cast<std::ptrdiff_t>(head)), head = 0;
      // The path: the source tree's branch to `from`, the arc, the sink tree's branch from `to`, the sink.
      path_.clear();
      slots_.clear();
      for (std::int64_t x = from;; x = parent_[static_cast<std::size_t>(x)]) {
        path_.push_back(x);
        if (parent_[static_cast<std::size_t>(x)] == kRootParent) break;
        slots_.push_back(parent_slot_[static_cast<std::size_t>(x)]);
      }
      std::reverse(path_.begin(), path_.end());
      std::reverse(slots_.begin(), slots_.end());
      slots_.push_back(via);
      for (std::int64_t x = to;; x = parent_[static_cast<std::size_t>(x)]) {
        path_.push_back(x);
        slots_.push_back(parent_[static_cast<std::size_t>(x)] == kRootParent ? 0 : parent_slot_[static_cast<std::size_t>(x)]);
        if (parent_[static_cast<std::size_t>(x)] == kRootParent) break;
      }
      path_.push_back(kSink);
      augment();
      if (++flow >= limit) return flow;
      // Every unit arc of the path is now saturated (the unbounded ones never are): the child across each
      // one in either tree becomes an orphan.
      ++time;
      orphans_.clear();
      for (std::size_t k = 0; k + 2 < path_.size(); ++k) {
        const std::int64_t x = path_[k], y = path_[k + 1];
        if ((x & 1) == 1 && slots_[k] != 1) continue;  // out of a sample into a neighbour (unbounded)
        const auto ux = static_cast<std::size_t>(x), uy = static_cast<std::size_t>(y);
        if (tree_[ux] == kSourceTree && tree_[uy] == kSourceTree && parent_[uy] == x) parent_[uy] = kNoParent, orphans_.push_back(y);
        else if (tree_[ux] == kSinkTree && tree_[uy] == kSinkTree && parent_[ux] == y) parent_[ux] = kNoParent, orphans_.push_back(x);
      }
      while (!orphans_.empty()) {
        const std::int64_t o = orphans_.back();
        orphans_.pop_back();
        const auto uo = static_cast<std::size_t>(o);
        std::int64_t best = -1;
        int best_slot = 0;
        std::int32_t best_depth = std::numeric_limits<std::int32_t>::max();
        auto consider = [&](std::int64_t q, int slot) {
          if (tree_[static_cast<std::size_t>(q)] != tree_[uo]) return;
          const std::int32_t d = rooted_depth(q, time);
          if (d >= 0 && d < best_depth) best = q, best_slot = slot, best_depth = d;
        };
        if (tree_[uo] == kSourceTree) residual_into(o, consider);
        else residual_from(o, consider);
        if (best >= 0) {
          parent_[uo] = static_cast<std::int32_t>(best);
          parent_slot_[uo] = static_cast<std::uint8_t>(best_slot);
          stamp_[uo] = time;
          depth_[uo] = best_depth + 1;
          continue;
        }
        // No parent: o leaves its tree; its neighbours in the tree, on either side of an arc, are searched
        // again (those that could reach it), and its children (among them) are orphans too.
        const auto tree = tree_[uo];
        tree_[uo] = kFree;
        auto requeue = [&](std::int64_t q, int) {
          const auto uq = static_cast<std::size_t>(q);
          if (tree_[uq] != tree) return;
          activate(q);
          if (parent_[uq] == o) parent_[uq] = kNoParent, orphans_.push_back(q);
        };
        residual_into(o, requeue);
        residual_from(o, requeue);
      }
    }
  }

  // Pushes one unit along the path: flags first cleared (cancelled flow), then set (new flow), so that a
  // sample's predecessor replaced on this path ends as the new one.
  void augment() {
    for (std::size_t k = 0; k + 1 < path_.size(); ++k) {
      const auto x = path_[k], y = path_[k + 1];
      if (y == kSink) continue;
      const std::int64_t b = x >> 1, c = y >> 1;
      if ((x & 1) == 0 && b != c) next_[static_cast<std::size_t>(c)] = kNoArc, previous_[static_cast<std::size_t>(b)] = kNoArc;
      if ((x & 1) == 1 && b == c) used_[static_cast<std::size_t>(b)] = 0;
    }
    previous_[static_cast<std::size_t>(path_.front() >> 1)] = kTerminal;
    for (std::size_t k = 0; k + 1 < path_.size(); ++k) {
      const auto x = path_[k], y = path_[k + 1];
      const std::int64_t b = x >> 1;
      if (y == kSink) {
        next_[static_cast<std::size_t>(b)] = kTerminal;
        continue;
      }
      const std::int64_t c = y >> 1;
      if ((x & 1) == 0 && b == c) used_[static_cast<std::size_t>(b)] = 1;
      if ((x & 1) == 1 && b != c) {
        const auto n = static_cast<std::int8_t>(slots_[k] - 2);
        next_[static_cast<std::size_t>(b)] = n;
        previous_[static_cast<std::size_t>(c)] = static_cast<std::int8_t>(n ^ 1);
      }
    }
  }

  // Dinic's phases: a breadth-first layering of the residual graph from the sources, then a blocking
  // flow of shortest paths in it (depth-first, with a current arc per node). Returns the flow added.
  // minimum_cut runs a few of them before Boykov & Kolmogorov's algorithm finishes the flow, for
  // membranes of detail::membrane_shortest_paths_from() samples or more (1,000): the first phases find
  // most of the flow along short paths for a breadth-first search each, where the search trees pay for
  // every path. Measured on GroEL at 0.25 Å, whose largest membranes carry 8-10k units of flow, the
  // membrane searches took 57 s with the trees alone, 84.8 s with Dinic's phases alone, 44.7 s after 4
  // phases, 39.1-39.4 s after 10-15 and 45.3 s after 30 (for every membrane), 35.9 s after 12 for
  // membranes of 1,000 samples or more; at 0.5 Å (smaller membranes) 2.25 s, 2.44-2.48 s after 12 for
  // every membrane, 2.20-2.23 s for those of 1,000 samples or more.
  std::int64_t shortest_path_phases(std::int64_t limit, int phases) {
    const auto nodes = static_cast<std::size_t>(2 * count_);
    std::int64_t flow = 0;
    // level_ is -1 and arc_ 0 everywhere between phases: only the nodes a phase reached are reset after it.
    level_.resize(nodes, -1);
    arc_.resize(nodes, 0);
    auto reset = [&] {
      for (const auto x : queue_) level_[static_cast<std::size_t>(x)] = -1, arc_[static_cast<std::size_t>(x)] = 0;
    };
    for (int phase = 0; phase < phases && flow < limit; ++phase) {
      queue_.clear();
      for (const auto b : sources_) level_[static_cast<std::size_t>(2 * b)] = 0, queue_.push_back(2 * b);
      std::int32_t last = -1;  // the level of the nodes next to the sink
      for (std::size_t head = 0; head < queue_.size(); ++head) {
        const std::int64_t x = queue_[head];
        const std::int32_t lx = level_[static_cast<std::size_t>(x)];
        if (last >= 0 && lx >= last) break;
        if ((x & 1) && target(x, 0) == kSink) {
          last = lx;
          continue;
        }
        residual_from(x, [&](std::int64_t y, int) {
          if (level_[static_cast<std::size_t>(y)] < 0) level_[static_cast<std::size_t>(y)] = lx + 1, queue_.push_back(y);
        });
      }
      if (last < 0) {
        reset();
        break;
      }
      const std::int64_t before = flow;
      for (const auto b : sources_) {
        while (flow < limit) {
          path_.assign(1, 2 * b);
          slots_.clear();
          bool found = false;
          while (!path_.empty()) {
            const std::int64_t x = path_.back();
            const auto ux = static_cast<std::size_t>(x);
            if (level_[ux] == last && (x & 1) && target(x, 0) == kSink) {
              found = true;
              break;
            }
            std::int64_t y = -1;
            if (level_[ux] < last)
              for (; arc_[ux] < arcs(x); ++arc_[ux]) {
                y = target(x, arc_[ux]);
                if (y >= 0 && level_[static_cast<std::size_t>(y)] == level_[ux] + 1) break;
                y = -1;
              }
            if (y >= 0) {
              slots_.push_back(arc_[ux]);
              path_.push_back(y);
              continue;
            }
            level_[ux] = -2;  // a dead end for the rest of the phase
            path_.pop_back();
            if (!slots_.empty()) slots_.pop_back(), ++arc_[static_cast<std::size_t>(path_.back())];
          }
          if (!found) break;
          slots_.push_back(0);
          path_.push_back(kSink);
          augment();
          ++flow;
        }
      }
      reset();
      if (flow == before) break;
    }
    return flow;
  }

  static constexpr int kShortestPathPhases = 12;

  // The minimum vertex cut between the terminals of `side` and those of the other sides, unless it
  // has `limit` samples or more. Returns the cut's samples (sorted global indices), else empty.
  std::vector<std::int64_t> minimum_cut(int side, std::int64_t limit) {
    source_side_ = static_cast<std::uint8_t>(side);
    sources_.clear();
    for (const auto b : region_)
      if (terminal_[static_cast<std::size_t>(b)] == source_side_) sources_.push_back(b);
    const auto n = static_cast<std::size_t>(count_);
    used_.assign(n, 0);
    next_.assign(n, kNoArc);
    previous_.assign(n, kNoArc);
    const std::int64_t first = limit >= detail::membrane_shortest_paths_from() ? shortest_path_phases(limit, kShortestPathPhases) : 0;
    const std::int64_t flow = first >= limit ? first : first + maximum_flow(limit - first);
    if (flow >= limit) return {};
    // The cut: samples whose "into" node the source still reaches in the residual graph, but not their "out of".
    std::vector<std::uint8_t> reached(2 * n, 0);
    queue_.clear();
    for (const auto b : sources_) reached[static_cast<std::size_t>(2 * b)] = 1, queue_.push_back(2 * b);
    for (std::size_t head = 0; head < queue_.size(); ++head)
      residual_from(queue_[head], [&](std::int64_t y, int) {
        if (reached[static_cast<std::size_t>(y)]) return;
        reached[static_cast<std::size_t>(y)] = 1;
        queue_.push_back(y);
      });
    std::vector<std::int64_t> cut;
    for (const auto b : region_)
      if (reached[static_cast<std::size_t>(2 * b)] && !reached[static_cast<std::size_t>(2 * b + 1)]) cut.push_back(global(b));
    std::sort(cut.begin(), cut.end());
    if (static_cast<std::int64_t>(cut.size()) != flow) return {};  // cannot happen with exact max-flow; be safe
    return cut;
  }

  const Lattice& lattice_;
  std::array<std::int64_t, 3> size_;
  std::uint8_t* state_;
  int reach_;
  std::array<std::int64_t, 3> low_{}, extent_{};
  std::array<std::int64_t, 14> offset_{};
  std::int64_t count_ = 0;
  std::vector<std::uint8_t> label_, terminal_, used_, seen_;
  std::uint8_t source_side_ = 1;
  std::vector<std::uint16_t> distance_;
  std::vector<std::int8_t> next_, previous_;
  std::vector<std::uint8_t> tree_, parent_slot_, is_active_;
  std::vector<std::int32_t> parent_, stamp_, depth_, level_;  // nodes number fewer than 2^23 (kMaxBoxSamples)
  std::vector<std::uint8_t> arc_;
  std::vector<std::int64_t> region_, sources_, queue_, path_, active_, orphans_;
  std::vector<int> slots_;
};


// How far (Å) from where the growths put a membrane its handle or tunnel is searched for a thinner
// section (MembraneMover). 4 Å: most of the gain of 15 Å on 4hhb, 2src and 1igy for a tenth of the time.
constexpr double kMembraneReach = 4.0;

// How far (Å³ of samples) the check for a change that splits off a piece (splits_its_side) searches
// before it gives up: the piece GroEL's first round split off at 0.5 Å measured 16.7 Å³. The check costs
// 9 ms of 5hr7's 0.67 s repair at 0.5 Å and 0.12 s of GroEL's; 20,000 Å³ found one more piece in GroEL
// at 0.25 Å, but the repair then took 308 s instead of about 120 s, and still two rounds.
constexpr double kSplitSearchVolume = 500.0;
// ... and at most this many samples (500 Å³ at grids of 0.08 Å and coarser): the search's table and queue,
// about 80 bytes per sample of the budget, stay near 80 MB at the finest grids the command line accepts.
constexpr std::int64_t kSplitSearchMostSamples = std::int64_t{1} << 20;

// The best set of clusters when each has a value (weight, possibly negative) and some pairs of a cut
// and a fill lose value when both are chosen (penalty >= 0): maximise the chosen weights minus the
// penalties of chosen pairs. With the fills' choice flipped this is a submodular minimisation, i.e. a
// minimum cut (chosen cuts on the source side, chosen fills on the sink side; a pair's penalty is an arc
// from the cut to the fill). Edmonds-Karp: the graph has one node per cluster.
struct Interaction {
  int cut = 0, fill = 0;
  std::int64_t penalty = 0;
};

std::vector<bool> best_selection(const std::vector<bool>& is_fill, const std::vector<std::int64_t>& weight,
                                 const std::vector<Interaction>& interactions) {
  const int n = static_cast<int>(weight.size());
  const int source = n, sink = n + 1;
  struct Arc {
    int to;
    std::int64_t capacity;
  };
  std::vector<Arc> arcs;
  std::vector<std::vector<int>> out(static_cast<std::size_t>(n) + 2);
  auto add = [&](int a, int b, std::int64_t capacity) {
    if (capacity <= 0) return;
    out[static_cast<std::size_t>(a)].push_back(static_cast<int>(arcs.size()));
    arcs.push_back({b, capacity});
    out[static_cast<std::size_t>(b)].push_back(static_cast<int>(arcs.size()));
    arcs.push_back({a, 0});
  };
  // Not choosing a cluster of positive weight loses it; choosing one of negative weight costs it.
  for (int v = 0; v < n; ++v) {
    const auto w = weight[static_cast<std::size_t>(v)];
    if (is_fill[static_cast<std::size_t>(v)]) w >= 0 ? add(v, sink, w) : add(source, v, -w);
    else w >= 0 ? add(source, v, w) : add(v, sink, -w);
  }
  for (const auto& i : interactions) add(i.cut, i.fill, i.penalty);
  std::vector<int> arrived_by(static_cast<std::size_t>(n) + 2);
  auto reachable = [&] {
    std::fill(arrived_by.begin(), arrived_by.end(), -1);
    std::vector<int> queue{source};
    arrived_by[static_cast<std::size_t>(source)] = -2;
    for (std::size_t head = 0; head < queue.size(); ++head)
      for (const int a : out[static_cast<std::size_t>(queue[head])]) {
        const int to = arcs[static_cast<std::size_t>(a)].to;
        if (arcs[static_cast<std::size_t>(a)].capacity > 0 && arrived_by[static_cast<std::size_t>(to)] == -1)
          arrived_by[static_cast<std::size_t>(to)] = a, queue.push_back(to);
      }
    return arrived_by[static_cast<std::size_t>(sink)] != -1;
  };
  while (reachable()) {
    std::int64_t bottleneck = std::numeric_limits<std::int64_t>::max();
    for (int v = sink; v != source; v = arcs[static_cast<std::size_t>(arrived_by[static_cast<std::size_t>(v)] ^ 1)].to)
      bottleneck = std::min(bottleneck, arcs[static_cast<std::size_t>(arrived_by[static_cast<std::size_t>(v)])].capacity);
    for (int v = sink; v != source; v = arcs[static_cast<std::size_t>(arrived_by[static_cast<std::size_t>(v)] ^ 1)].to) {
      arcs[static_cast<std::size_t>(arrived_by[static_cast<std::size_t>(v)])].capacity -= bottleneck;
      arcs[static_cast<std::size_t>(arrived_by[static_cast<std::size_t>(v)] ^ 1)].capacity += bottleneck;
    }
  }
  // Chosen: the cuts still reached from the source, and the fills not reached.
  std::vector<bool> chosen(static_cast<std::size_t>(n));
  for (int v = 0; v < n; ++v) {
    const bool reached = arrived_by[static_cast<std::size_t>(v)] != -1;
    chosen[static_cast<std::size_t>(v)] = is_fill[static_cast<std::size_t>(v)] ? !reached : reached;
  }
  return chosen;
}

// A cluster of left-out samples and what moving it would do, alone, to the field of this round.
struct Candidate {
  TopologyChange change;
  int euler = 0;           // Euler change of the solid (handles removed when positive)
  double area = 0;         // Å², change of the contour's area
  std::int64_t cost = 0;   // |area| in thousandths of Å²: what the selection minimises
};

template <typename T>
HandleRepair repair_handles_impl(Grid3<T>& field, double level, double minimum_fraction, int threads, int handles_to_remove) {
  threads = detail::surface_threads(threads);
  auto state = grow_both(field, level, threads);
  const Lattice lattice(field.size);
  const auto total = lattice.count();
  T* values = field.values.data();
  auto left_out = [&](std::int64_t s) {
    return values[s] > level ? !(state[s] & kInSolid) : !(state[s] & kInOutside);
  };
  // Clusters of left-out samples (connected through samples on the same side that are also left out).
  std::vector<Candidate> candidates;
  {
    std::vector<std::int64_t> stack;
    for (std::int64_t s = 0; s < total; ++s) {
      if ((state[s] & kClustered) || !left_out(s)) continue;
      const bool inside = values[s] > level;
      Candidate candidate;
      candidate.change.filled = !inside;
      stack.push_back(s);
      state[s] |= kClustered;
      while (!stack.empty()) {
        const auto v = stack.back();
        stack.pop_back();
        candidate.change.samples.push_back(v);
        lattice.neighbours(v, [&](int, std::int64_t t) {
          if (t < 0 || (state[t] & kClustered) || (values[t] > level) != inside || !left_out(t)) return;
          state[t] |= kClustered;
          stack.push_back(t);
        });
      }
      std::sort(candidate.change.samples.begin(), candidate.change.samples.end());
      candidates.push_back(std::move(candidate));
    }
  }
  const auto [below, above] = moved_sample_values<T>(level, field.spacing);
  auto new_value = [&](const TopologyChange& change) { return change.filled ? above : below; };
  // Only clusters that touch the solid's main piece (the one grown, and the cut clusters on it) change
  // the outer surface: a whole detached piece, or a membrane across a tunnel through one, is left as it
  // is (deleting a piece of genus 2 or more would also raise the Euler characteristic).
  auto touches = [&](const Candidate& c, std::uint8_t bits) {
    for (const auto s : c.change.samples) {
      bool found = false;
      lattice.neighbours(s, [&](int, std::int64_t t) { found = found || (t >= 0 && (state[t] & bits)); });
      if (found) return true;
    }
    return false;
  };
  std::vector<bool> on_main(candidates.size(), false);
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    if (candidates[c].change.filled || !touches(candidates[c], kInSolid)) continue;
    on_main[c] = true;
    for (const auto s : candidates[c].change.samples) state[s] |= kMark;
  }
  for (std::size_t c = 0; c < candidates.size(); ++c)
    if (candidates[c].change.filled) on_main[c] = touches(candidates[c], kInSolid | kMark);
  for (std::size_t c = 0; c < candidates.size(); ++c) {
    if (!candidates[c].change.filled)
      for (const auto s : candidates[c].change.samples) state[s] &= static_cast<std::uint8_t>(~kMark);
    auto& candidate = candidates[c];
    candidate.euler = on_main[c] ? euler_change(field, level, candidate.change.samples, candidate.change.filled, state.data()) : 0;
  }
  // Each membrane moves to the thinnest section nearby when that changes less area, removes at least as
  // many handles and stays apart from the other clusters of its side. The search for each one's thinner
  // section reads only what stays fixed until the changes are applied (the grown sets, the field), so the
  // searches run in parallel, one mover per thread; the checks that follow depend on the membranes moved
  // before (which samples are clustered) and run in order, as they would one after another.
  const int reach = std::max(2, static_cast<int>(std::lround(kMembraneReach / field.spacing)));
  std::vector<std::vector<std::int64_t>> moved_of(candidates.size());
  {
    std::vector<std::unique_ptr<MembraneMover>> movers(static_cast<std::size_t>(threads));
    detail::parallel_chunks(static_cast<std::int64_t>(candidates.size()), threads, [&](std::int64_t k, int worker) {
      const auto& c = candidates[static_cast<std::size_t>(k)];
      if (c.euler <= 0) return;
      auto& mover = movers[static_cast<std::size_t>(worker)];
      if (!mover) mover = std::make_unique<MembraneMover>(lattice, field.size, state.data(), reach);
      auto moved = mover->move(c.change.samples, c.change.filled ? kInOutside : kInSolid);
      if (moved.empty() || !mover->complete(moved, !c.change.filled, [&](std::int64_t t) { return values[t] > level; })) return;
      moved_of[static_cast<std::size_t>(k)] = std::move(moved);
    });
  }
  for (std::size_t k = 0; k < candidates.size(); ++k) {
    auto& c = candidates[k];
    if (c.euler <= 0) continue;
    c.area = area_change(field, level, minimum_fraction, c.change.samples, new_value(c.change));
    auto moved = std::move(moved_of[k]);
    const bool inside = !c.change.filled;
    if (moved.empty()) continue;
    for (const auto s : c.change.samples) state[s] |= kMark;
    bool apart = true;
    for (const auto s : moved) {
      lattice.neighbours(s, [&](int, std::int64_t t) {
        if (t >= 0 && (state[t] & (kClustered | kMark)) == kClustered && (values[t] > level) == inside) apart = false;
      });
    }
    for (const auto s : c.change.samples) state[s] &= static_cast<std::uint8_t>(~kMark);
    if (!apart) continue;
    // A section through a junction of tunnels (or handles) may remove more at once than the membrane it
    // replaces (it encloses no pocket and splits off no piece, so its Euler change counts handles only):
    // the selection below weighs it as such; one that removes fewer is not taken.
    const int moved_euler = euler_change(field, level, moved, c.change.filled, state.data());
    if (moved_euler < c.euler) continue;
    const double moved_area = area_change(field, level, minimum_fraction, moved, new_value(c.change));
    if (std::abs(moved_area) >= std::abs(c.area)) continue;
    for (const auto s : c.change.samples) state[s] &= static_cast<std::uint8_t>(~kClustered);
    for (const auto s : moved) state[s] |= kClustered;
    c.change.samples = std::move(moved);
    c.euler = moved_euler;
    c.area = moved_area;
  }
  // The clusters that remove handles, and the pairs whose changes interact (adjacent cut and fill: the
  // fill's membrane ends on the cut's, so after one the other may no longer remove its handle). Clusters
  // of one side never touch, so every simplex of the lattice meets at most one cut and one fill, and the
  // Euler change of any set of clusters is exactly the sum of their own plus these pairwise interactions.
  std::vector<int> handle_of;  // candidate index of each handle-removing cluster
  for (int c = 0; c < static_cast<int>(candidates.size()); ++c)
    if (candidates[static_cast<std::size_t>(c)].euler > 0) handle_of.push_back(c);
  const int handles = static_cast<int>(handle_of.size());
  HandleRepair repair;
  if (handles == 0) return repair;
  std::vector<std::pair<std::int64_t, int>> owner;  // (sample, handle number), sorted
  for (int h = 0; h < handles; ++h)
    for (const auto s : candidates[static_cast<std::size_t>(handle_of[static_cast<std::size_t>(h)])].change.samples) owner.emplace_back(s, h);
  std::sort(owner.begin(), owner.end());
  std::vector<Interaction> interactions;  // (cut, fill) handle numbers, and the Euler change lost by choosing both
  for (int h = 0; h < handles; ++h) {
    const auto& change = candidates[static_cast<std::size_t>(handle_of[static_cast<std::size_t>(h)])].change;
    std::vector<int> touching;
    for (const auto s : change.samples)
      lattice.neighbours(s, [&](int, std::int64_t t) {
        if (t < 0 || !(state[t] & kClustered)) return;
        const auto found = std::lower_bound(owner.begin(), owner.end(), std::make_pair(t, -1));
        if (found != owner.end() && found->first == t && found->second > h) touching.push_back(found->second);
      });
    std::sort(touching.begin(), touching.end());
    touching.erase(std::unique(touching.begin(), touching.end()), touching.end());
    for (const int other : touching) {
      auto& first = candidates[static_cast<std::size_t>(handle_of[static_cast<std::size_t>(h)])];
      auto& second = candidates[static_cast<std::size_t>(handle_of[static_cast<std::size_t>(other)])];
      std::vector<T> original;
      original.reserve(first.change.samples.size());
      for (const auto s : first.change.samples) original.push_back(values[s]), values[s] = new_value(first.change);
      const int together = euler_change(field, level, second.change.samples, second.change.filled, state.data());
      for (std::size_t k = 0; k < original.size(); ++k) values[first.change.samples[k]] = original[k];
      // A gain when both are chosen (not seen in practice) is ignored: the penalties must not be negative.
      if (together < second.euler)
        interactions.push_back({first.change.filled ? other : h, first.change.filled ? h : other, second.euler - together});
    }
  }
  // The set that removes the handles at the least cost. Each cluster is worth handles x price - cost, and
  // a chosen pair loses its lost handles x price; for a given price the best set is a min-cut. The price
  // is the smallest for which that set removes every handle left (binary search: the count grows with
  // the price), so that no expensive change is bought for a handle count beyond the genus, which only
  // enclosed voids or split-off pieces can make up. If no price reaches it, the most handles.
  std::vector<bool> is_fill(static_cast<std::size_t>(handles));
  std::int64_t most_cost = 1;
  for (int h = 0; h < handles; ++h) {
    auto& c = candidates[static_cast<std::size_t>(handle_of[static_cast<std::size_t>(h)])];
    c.cost = std::llround(std::abs(c.area) * 1000);
    most_cost += c.cost;
    is_fill[static_cast<std::size_t>(h)] = c.change.filled;
  }
  auto select = [&](std::int64_t price, int& removes) {
    std::vector<std::int64_t> weight(static_cast<std::size_t>(handles));
    for (int h = 0; h < handles; ++h) {
      const auto& c = candidates[static_cast<std::size_t>(handle_of[static_cast<std::size_t>(h)])];
      weight[static_cast<std::size_t>(h)] = c.euler * price - c.cost;
    }
    auto priced = interactions;
    for (auto& i : priced) i.penalty *= price;
    auto chosen = best_selection(is_fill, weight, priced);
    removes = 0;
    for (int h = 0; h < handles; ++h)
      if (chosen[static_cast<std::size_t>(h)]) removes += candidates[static_cast<std::size_t>(handle_of[static_cast<std::size_t>(h)])].euler;
    for (const auto& i : interactions)
      if (chosen[static_cast<std::size_t>(i.cut)] && chosen[static_cast<std::size_t>(i.fill)]) removes -= static_cast<int>(i.penalty);
    return chosen;
  };
  int removes = 0;
  std::vector<bool> chosen = select(most_cost, removes);
  if (handles_to_remove >= 0 && removes > handles_to_remove) {
    std::int64_t low = 0, high = most_cost;  // select(high) removes enough; select(low) does not
    while (high - low > 1) {
      const std::int64_t middle = low + (high - low) / 2;
      int middle_removes = 0;
      select(middle, middle_removes);
      (middle_removes >= handles_to_remove ? high : low) = middle;
    }
    chosen = select(high, removes);
  }
  // Applied cheapest first, each only if it still removes a handle on the field as it then is; if some
  // chosen cluster no longer does, the others complete the count, cheapest first.
  std::vector<int> order(static_cast<std::size_t>(handles));
  for (int h = 0; h < handles; ++h) order[static_cast<std::size_t>(h)] = h;
  auto cheaper = [&](int a, int b) {
    const auto& ca = candidates[static_cast<std::size_t>(handle_of[static_cast<std::size_t>(a)])];
    const auto& cb = candidates[static_cast<std::size_t>(handle_of[static_cast<std::size_t>(b)])];
    if (ca.cost != cb.cost) return ca.cost < cb.cost;
    return ca.change.samples.front() < cb.change.samples.front();
  };
  std::sort(order.begin(), order.end(), [&](int a, int b) {
    if (chosen[static_cast<std::size_t>(a)] != chosen[static_cast<std::size_t>(b)]) return static_cast<bool>(chosen[static_cast<std::size_t>(a)]);
    return cheaper(a, b);
  });
  // No more than `handles_to_remove`: a larger count can only come from changes that enclose voids or
  // split off pieces (a connected solid without voids has an Euler characteristic of at most 1).
  int goal = removes, removed = 0;
  if (handles_to_remove >= 0) goal = std::min(goal, handles_to_remove);
  const auto split_search_budget = std::min<std::int64_t>(
      static_cast<std::int64_t>(std::ceil(kSplitSearchVolume / std::pow(field.spacing, 3))), kSplitSearchMostSamples);
  for (const int h : order) {
    if (removed >= goal) break;
    auto& c = candidates[static_cast<std::size_t>(handle_of[static_cast<std::size_t>(h)])];
    auto& change = c.change;
    change.euler_change = euler_change(field, level, change.samples, change.filled, state.data());
    if (change.euler_change <= 0) continue;
    change.area_change = area_change(field, level, minimum_fraction, change.samples, new_value(change));
    change.original_values.reserve(change.samples.size());
    for (const auto v : change.samples) {
      change.original_values.push_back(static_cast<double>(values[v]));
      values[v] = new_value(change);
    }
    // A change can raise the Euler characteristic by splitting off a piece of the solid, or closing a
    // pocket of the outside into a void, instead of removing a handle: the second of two cuts across one
    // ring, the second of two fills across one pipe. It is not applied: it would drop the piece or the
    // pocket's lining from the outer surface and leave the handle it was counted for, which the clusters
    // not chosen then remove if they can (else the next round). Among the 88 structures: GroEL at 0.5 Å
    // (a cut; it needed a second round of growths before), 3o21 at 0.25 Å (a cut) and 1vln at 1 Å (a fill).
    if (splits_its_side(lattice, values, level, change.samples, !change.filled, split_search_budget)) {
      restore_change(values, change);
      change.original_values.clear();
      continue;
    }
    removed += change.euler_change;
    repair.samples_changed += static_cast<std::int64_t>(change.samples.size());
    repair.area_change += change.area_change;
    repair.changes.push_back(std::move(change));
  }
  return repair;
}

template <typename T>
void undo_impl(Grid3<T>& field, const HandleRepair& repair) {
  for (auto change = repair.changes.rbegin(); change != repair.changes.rend(); ++change) restore_change(field.values.data(), *change);
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
  const auto [below, above] = moved_sample_values<T>(level, field.spacing);
  auto& chosen = result.filled ? fills : cuts;
  result.area_change = area_change(field, level, minimum_fraction, chosen, result.filled ? above : below);
  for (auto s : chosen) field.values[s] = result.filled ? above : below;
  result.removed_samples = std::move(chosen);
  result.samples_removed = static_cast<std::int64_t>(result.removed_samples.size());
  return result;
}

// The genus of the largest component of the field's contour; the contour is kept in *mesh if given, with
// its components in *kept_components when its genus is 0.
template <typename T>
int contour_genus(const Grid3<T>& field, double level, int threads, double minimum_fraction, Mesh* mesh,
                  std::optional<std::vector<MeshComponent>>* kept_components = nullptr) {
  Mesh contour = contour_isosurface(field, level, threads, minimum_fraction);
  auto components = mesh_components(contour);
  if (mesh) *mesh = std::move(contour);
  const int genus = components.empty() ? 0 : components.front().genus;
  if (kept_components && genus == 0) *kept_components = std::move(components);
  return genus;
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
  // Interactions beyond those counted can leave handles after a round (a change that splits off a piece
  // of more than the 500 Å³ splits_its_side searches counts as a handle removed; the clusters left out
  // may not complete the count): the growths are then redone on the changed field.
  constexpr int kRounds = 4;
  int genus = result.outer_genus_before;
  for (int round = 0; round < kRounds; ++round) {
    // The previous round's contour, freed before this round's growths: at 0.25 Å it is a gigabyte.
    if (final_contour) *final_contour = Mesh{};
    HandleRepair more = repair_handles_impl(field, level, minimum_fraction, threads, genus);
    const bool changed = !more.changes.empty();
    result.per_handle.samples_changed += more.samples_changed;
    result.per_handle.area_change += more.area_change;
    for (auto& change : more.changes) result.per_handle.changes.push_back(std::move(change));
    genus = contour_genus(field, level, threads, minimum_fraction, final_contour,
                          final_contour ? &result.final_components : nullptr);
    if (genus == 0) {
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

namespace detail {
bool change_splits_its_side(const Grid3<double>& field, double level, const std::vector<std::int64_t>& samples, bool filled,
                            std::int64_t budget) {
  return splits_its_side(Lattice(field.size), field.values.data(), level, samples, !filled, budget);
}
}  // namespace detail

HandleRepair repair_handles(Grid3<double>& field, double level, double minimum_fraction, int threads, int handles_to_remove) {
  return repair_handles_impl(field, level, minimum_fraction, threads, handles_to_remove);
}
HandleRepair repair_handles(Grid3<float>& field, double level, double minimum_fraction, int threads, int handles_to_remove) {
  return repair_handles_impl(field, level, minimum_fraction, threads, handles_to_remove);
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
