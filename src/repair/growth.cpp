#include "growth.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <exception>
#include <limits>
#include <optional>
#include <stdexcept>
#include <system_error>
#include <thread>

#include "../util/parallel.hpp"
#include "bucket_queue.hpp"
#include "lattice.hpp"
#include "outside_depth.hpp"
#include "sample_state.hpp"

namespace spheremap::detail {
namespace {

// How many visits ahead the growths fetch a sample's neighbourhood.
constexpr std::size_t kPrefetchAhead = 8;

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

std::array<std::int64_t, 14> offsets(const Lattice& lattice) {
  std::array<std::int64_t, 14> offset{};
  for (int n = 0; n < 14; ++n) offset[n] = lattice.offset(n);
  return offset;
}

// The deepest sample of the largest connected inside piece (by samples), or -1 if nothing is inside: the
// solid's growth starts there, so that the piece kept whole is the main body even when a small detached
// piece is thicker. Pieces are labelled with the queued bit, cleared afterwards. Inside samples are never
// on the border: plain offsets.
template <typename T, typename Index>
std::int64_t deepest_sample_of_largest_piece(const Grid3<T>& field, const Lattice& lattice, std::uint8_t* state) {
  const T* values = field.values.data();
  const auto total = lattice.count();
  const auto offset = offsets(lattice);
  std::int64_t seed = -1, seed_piece_size = 0;
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
        if ((bt & (kInside | kQueued)) == kInside)
          store_state(state, t, bt | kQueued), stack.push_back(static_cast<Index>(t));
      }
    }
    if (size > seed_piece_size) seed_piece_size = size, seed = deepest;
  }
  for (std::int64_t s = 0; s < total; ++s) {
    const std::uint8_t b = load_state(state, s);
    if ((b & (kInside | kQueued)) == (kInside | kQueued))
      store_state(state, s, b & static_cast<std::uint8_t>(~kQueued));
  }
  return seed;
}

// Grows the solid by simple samples only, deepest first (by field value, in buckets of spacing/256),
// from its seed, and marks the members kInSolid: the set stays a ball. Touches the kQueued and kInSolid
// bits of inside samples only.
template <typename T, typename Index>
void grow_solid(const Grid3<T>& field, double level, const Lattice& lattice, std::uint8_t* state) {
  const auto& simple = simple_table();
  const T* values = field.values.data();
  const auto total = lattice.count();
  const auto offset = offsets(lattice);
  double top_value = level;
  for (std::int64_t s = 0; s < total; ++s)
    if (std::isfinite(values[s])) top_value = std::max(top_value, static_cast<double>(values[s]));
  const std::int64_t seed = deepest_sample_of_largest_piece<T, Index>(field, lattice, state);
  if (seed < 0) throw std::invalid_argument("handle repair: nothing is inside");
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
void grow_outside(const Lattice& lattice, const std::array<std::int64_t, 3>& size,
                  const std::vector<std::uint16_t>& depth, std::uint8_t* state) {
  const auto& simple = simple_table();
  const auto offset = offsets(lattice);
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
    for (int n = 0; n < 14; ++n)
      mask |= static_cast<unsigned>((load_state(state, s + offset[n]) & kInOutside) >> 1) << n;
    if (simple[mask]) {
      store_state(state, s, b | kInOutside);
      for (int n = 0; n < 14; ++n) offer(s + offset[n]);
    } else {
      store_state(state, s, b);
    }
  }
}

// Both growths, with more than one thread at once (see load_state), plus, while they run, two bytes of
// distance per sample.
template <typename T, typename Index>
void grow_both_with(const Grid3<T>& field, double level, const Lattice& lattice, std::uint8_t* state, int threads) {
  const std::vector<std::uint16_t> depth = outside_depth(field, level, threads);
  std::optional<std::thread> solid_thread;
  std::exception_ptr solid_error;
  if (surface_threads(threads) > 1) {
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

}  // namespace

template <typename T>
std::vector<std::uint8_t> grow_both(const Grid3<T>& field, double level, int threads) {
  threads = surface_threads(threads);  // parallel_chunks takes a count: 0 would run one thread
  const Lattice lattice(field.size);
  std::vector<std::uint8_t> state(static_cast<std::size_t>(field.count()), 0);
  bool any_inside = false;
  for (std::size_t s = 0; s < state.size(); ++s) {
    const bool inside = field.values[s] > level;
    state[s] = inside ? kInside : 0;
    any_inside = any_inside || inside;
  }
  if (!any_inside) throw std::invalid_argument("handle repair: nothing is inside");
  lattice.border([&](std::int64_t s) {
    if (state[static_cast<std::size_t>(s)] & kInside)
      throw std::invalid_argument("handle repair: the solid reaches the border of the grid");
  });
  if (field.count() <= static_cast<std::int64_t>(std::numeric_limits<std::uint32_t>::max()))
    grow_both_with<T, std::uint32_t>(field, level, lattice, state.data(), threads);
  else
    grow_both_with<T, std::int64_t>(field, level, lattice, state.data(), threads);
  return state;
}

template std::vector<std::uint8_t> grow_both(const Grid3<double>&, double, int);
template std::vector<std::uint8_t> grow_both(const Grid3<float>&, double, int);

}  // namespace spheremap::detail
