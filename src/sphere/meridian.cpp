#include "meridian.hpp"

#include <algorithm>
#include <stdexcept>

namespace spheremap::detail {

Meridian boundary_meridian(const VertexRings& rings, const std::vector<double>& z, std::int32_t north,
                           std::int32_t south, const std::vector<std::int32_t>* kept) {
  const auto n = rings.vertex_count();
  const auto north_ring = rings.ring(north);
  const auto south_ring = rings.ring(south);
  std::vector<char> on_north_ring(n, 0), on_south_ring(n, 0);
  for (auto v : north_ring) on_north_ring[v] = 1;
  for (auto v : south_ring) on_south_ring[v] = 1;
  auto lower = [&](std::int32_t a, std::int32_t b) { return z[a] != z[b] ? z[a] < z[b] : a < b; };
  auto lowest_neighbour = [&](std::int32_t v) {
    std::int32_t best = -1;
    for (auto w : rings.ring(v)) {
      if (w == north || w == south || on_north_ring[w]) continue;
      if (best < 0 || lower(w, best)) best = w;
    }
    return best;
  };

  Meridian meridian;
  // A kept path is still chord-free from ring to ring (a property of the graph); if z strictly decreases
  // along it, the boundary of the (z, φ) rectangle is again traversed monotonically and Floater's theorem
  // applies as for a fresh steepest descent.
  if (kept) {
    bool descends = kept->size() >= 2;
    for (std::size_t m = 0; descends && m + 1 < kept->size(); ++m) descends = lower((*kept)[m + 1], (*kept)[m]);
    if (descends) {
      meridian.path = *kept;
      meridian.kept = true;
      return meridian;
    }
  }

  std::vector<std::int32_t> starts(north_ring.begin(), north_ring.end());
  // Start where the descent is steepest; the rest are fallbacks should a descent stall numerically.
  std::sort(starts.begin(), starts.end(), [&](std::int32_t a, std::int32_t b) {
    const auto la = lowest_neighbour(a), lb = lowest_neighbour(b);
    if (la < 0 || lb < 0) return la >= 0 && lb < 0;
    return la != lb ? lower(la, lb) : a < b;
  });
  for (auto start : starts) {
    std::vector<std::int32_t> path{start};
    auto current = lowest_neighbour(start);
    bool stalled = current < 0;
    while (!stalled) {
      path.push_back(current);
      if (on_south_ring[current]) break;
      const auto next = lowest_neighbour(current);
      if (next < 0 || !lower(next, current))
        stalled = true;
      else
        current = next;
    }
    if (!stalled) {
      meridian.path = std::move(path);
      return meridian;
    }
  }

  meridian.by_descent = false;
  std::vector<std::int32_t> previous(n, -1);
  std::vector<std::int32_t> queue;
  std::vector<std::int32_t> sources(north_ring.begin(), north_ring.end());
  std::sort(sources.begin(), sources.end());
  for (auto v : sources) previous[v] = v, queue.push_back(v);
  std::int32_t reached = -1;
  for (std::size_t head = 0; head < queue.size() && reached < 0; ++head) {
    const auto v = queue[head];
    for (auto w : rings.ring(v)) {
      if (w == north || w == south || previous[w] >= 0) continue;
      previous[w] = v;
      if (on_south_ring[w]) {
        reached = w;
        break;
      }
      queue.push_back(w);
    }
  }
  if (reached < 0) throw std::logic_error("boundary_meridian: no path between the circumpolar rings");
  for (auto v = reached;; v = previous[v]) {
    meridian.path.push_back(v);
    if (previous[v] == v) break;
  }
  std::reverse(meridian.path.begin(), meridian.path.end());
  return meridian;
}

}  // namespace spheremap::detail
