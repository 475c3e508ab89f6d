#include "spheremap/sphere/poles.hpp"

// Exact farthest pair by branch and bound on a k-d tree: O(n log n) in practice, even on meshes whose
// vertices all lie on a sphere (where the convex hull has every vertex).
#include <algorithm>
#include <numeric>
#include <optional>
#include <stdexcept>

#include "spheremap/geometry/vec.hpp"

namespace spheremap {
namespace {

struct Node {
  Vec3 lo, hi;
  std::int32_t begin, end;  // range in the permuted index array
  std::int32_t left = -1, right = -1;
};

constexpr std::int32_t kLeafSize = 8;

class KdTree {
 public:
  explicit KdTree(const std::vector<Vec3>& points) : points_(points), order_(points.size()) {
    std::iota(order_.begin(), order_.end(), 0);
    nodes_.reserve(2 * points.size() / kLeafSize + 2);
    build(0, static_cast<std::int32_t>(points.size()));
  }

  // The bound is evaluated with the same operations, in the same order, as the distance of any point
  // inside the box, and rounding is monotone: no point can beat the bound of its box.
  static double max_squared_distance(const Vec3& p, const Node& node) {
    double sum = 0;
    for (int a = 0; a < 3; ++a) {
      const double d = std::max(std::abs(p[a] - node.lo[a]), std::abs(p[a] - node.hi[a]));
      sum += d * d;
    }
    return sum;
  }
  static double squared(const Vec3& p, const Vec3& q) {
    double sum = 0;
    for (int a = 0; a < 3; ++a) {
      const double d = std::abs(p[a] - q[a]);
      sum += d * d;
    }
    return sum;
  }

  // Updates (best, pair) with every point j whose distance to point i beats or ties it (ties go to the
  // smaller index pair).
  void improve(std::int32_t i, double& best, std::pair<std::int32_t, std::int32_t>& pair) const {
    const Vec3& p = points_[i];
    std::int32_t stack[128];
    int top = 0;
    stack[top++] = 0;
    while (top > 0) {
      const Node& node = nodes_[stack[--top]];
      if (max_squared_distance(p, node) < best) continue;
      if (node.left < 0) {
        for (std::int32_t k = node.begin; k < node.end; ++k) {
          const std::int32_t j = order_[k];
          if (j == i) continue;
          const double d = squared(p, points_[j]);
          const std::pair<std::int32_t, std::int32_t> candidate{std::min(i, j), std::max(i, j)};
          if (d > best || (d == best && candidate < pair)) {
            best = d;
            pair = candidate;
          }
        }
        continue;
      }
      const double bound_left = max_squared_distance(p, nodes_[node.left]);
      const double bound_right = max_squared_distance(p, nodes_[node.right]);
      // Visit the more promising child first: push it last.
      if (bound_left > bound_right) {
        stack[top++] = node.right;
        stack[top++] = node.left;
      } else {
        stack[top++] = node.left;
        stack[top++] = node.right;
      }
    }
  }

 private:
  std::int32_t build(std::int32_t begin, std::int32_t end) {
    const auto id = static_cast<std::int32_t>(nodes_.size());
    nodes_.push_back({});
    Node node;
    node.begin = begin;
    node.end = end;
    node.lo = node.hi = points_[order_[begin]];
    for (std::int32_t k = begin; k < end; ++k) {
      for (int a = 0; a < 3; ++a) {
        node.lo[a] = std::min(node.lo[a], points_[order_[k]][a]);
        node.hi[a] = std::max(node.hi[a], points_[order_[k]][a]);
      }
    }
    if (end - begin > kLeafSize) {
      int axis = 0;
      for (int a = 1; a < 3; ++a)
        if (node.hi[a] - node.lo[a] > node.hi[axis] - node.lo[axis]) axis = a;
      const std::int32_t middle = begin + (end - begin) / 2;
      std::nth_element(order_.begin() + begin, order_.begin() + middle, order_.begin() + end,
                       [&](std::int32_t x, std::int32_t y) {
                         return points_[x][axis] != points_[y][axis] ? points_[x][axis] < points_[y][axis] : x < y;
                       });
      node.left = build(begin, middle);
      node.right = build(middle, end);
    }
    nodes_[id] = node;
    return id;
  }

  const std::vector<Vec3>& points_;
  std::vector<std::int32_t> order_;
  std::vector<Node> nodes_;
};

}  // namespace

std::pair<std::int32_t, std::int32_t> farthest_pair(const std::vector<Vec3>& positions) {
  const auto n = static_cast<std::int32_t>(positions.size());
  if (n < 2) throw std::invalid_argument("farthest_pair: needs at least 2 points");
  // A good first guess (repeatedly the farthest point from the last one) makes the pruning effective.
  std::int32_t a = 0;
  for (int round = 0; round < 4; ++round) {
    std::int32_t far = a;
    double far_d = -1;
    for (std::int32_t j = 0; j < n; ++j) {
      const double d = KdTree::squared(positions[a], positions[j]);
      if (d > far_d) {
        far_d = d;
        far = j;
      }
    }
    a = far;
  }
  double best = -1;
  std::pair<std::int32_t, std::int32_t> pair{0, 1};
  {
    double bd = -1;
    for (std::int32_t j = 0; j < n; ++j) bd = std::max(bd, KdTree::squared(positions[a], positions[j]));
    // Only a lower bound to prune with; the exact pair (and tie-breaking) comes from the full search.
    best = std::nextafter(bd, 0.0);
  }
  // Visit points from the outside in. A pair at distance D has |p - c| + |q - c| >= D, so once
  // |p - c| + max |q - c| is below the best distance no later point can be in a better pair with
  // another later point, and its pairs with earlier points were already examined from those.
  Vec3 centre{0, 0, 0};
  for (const auto& p : positions) centre = centre + (1.0 / n) * p;
  std::vector<double> radius(n);
  for (std::int32_t i = 0; i < n; ++i) radius[i] = norm(positions[i] - centre);
  const double largest_radius = *std::max_element(radius.begin(), radius.end());
  // The relative margin covers the rounding of the radii and of the square root.
  auto beyond_reach = [&](std::int32_t i) { return (radius[i] + largest_radius) * (1 + 1e-12) < std::sqrt(best); };
  // best only grows, so a point beyond reach now stays so: only the others are put in order (on a
  // cube, its corners only).
  std::vector<std::int32_t> outside_in;
  for (std::int32_t i = 0; i < n; ++i)
    if (!beyond_reach(i)) outside_in.push_back(i);
  std::sort(outside_in.begin(), outside_in.end(),
            [&](std::int32_t x, std::int32_t y) { return radius[x] != radius[y] ? radius[x] > radius[y] : x < y; });
  // Updates (best, pair) with every point j whose distance to point i beats or ties it (ties go to the
  // smaller index pair): by a scan of all points for the first few visited, through a k-d tree (built
  // then) for the rest. Either finds the same pairs.
  constexpr int kScannedPoints = 16;
  int visited = 0;
  std::optional<KdTree> tree;
  for (auto i : outside_in) {
    if (beyond_reach(i)) break;
    if (visited++ < kScannedPoints) {
      const Vec3& p = positions[i];
      for (std::int32_t j = 0; j < n; ++j) {
        if (j == i) continue;
        const double d = KdTree::squared(p, positions[j]);
        const std::pair<std::int32_t, std::int32_t> candidate{std::min(i, j), std::max(i, j)};
        if (d > best || (d == best && candidate < pair)) best = d, pair = candidate;
      }
      continue;
    }
    if (!tree) tree.emplace(positions);
    tree->improve(i, best, pair);
  }
  return pair;
}

}  // namespace spheremap
