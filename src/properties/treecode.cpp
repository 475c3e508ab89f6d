// Sums Σ q K(|x - y|) for K = 1/r or 1/r²: exactly, and by a dual-tree treecode with Cartesian Taylor
// expansions (the fast multipole method's cell-to-cell form, as in Dehnen's falcON, with the derivative
// recurrence of Duan & Krasny's treecodes), derived for the kernel f = s^-a, s = r², so that 1/r² gets its
// own expansion and not the Coulomb one.
//
// With R = c_T - c_S between a target cell's centre and a source cell's centre, a target x = c_T + t and a
// source y = c_S + d: f(x - y) = Σ_n D_n (t - d)^n / n! over multi-indices n, D_n = D^n f(R). From
// s ∇f = -2a R f (dotted with the offset and matched term by term):
//   |n| s D_n = -(2|n| - 2 + 2a) Σ_i n_i R_i D_{n-e_i} - (|n| - 2 + 2a) Σ_i n_i (n_i - 1) D_{n-2e_i},
// D_0 = s^-a. Expanding (t - d)^n binomially, the source cell's moments M_k = Σ q (-d)^k (|k| <= P) give
// the target cell's local coefficients L_m = Σ_k D_{m+k} M_k / (m! k!) (|m| <= P), which children inherit
// by re-centring the polynomial (exact) and targets evaluate as Σ_m L_m t^m. A pair of cells is expanded
// when r_S + r_T < theta |R|; the truncation error then falls about as theta^(P + 1).
#include "treecode.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <stdexcept>

#include "../util/parallel.hpp"
#include "spheremap/geometry/vec.hpp"

namespace spheremap::detail {
namespace {

// ---------------------------------------------------------------------------------------------------------------
// Trees: boxes split at the median of their longest side, so both halves hold as many points (a balanced tree
// whatever the density), deterministic (ties broken by index).

struct Node {
  Vec3 centre{};
  double radius = 0;                   // largest distance from the centre to its points
  std::int32_t first = 0, last = 0;    // its points: order[first, last)
  std::int32_t left = -1, right = -1;  // children; -1 for a leaf
  [[nodiscard]] bool leaf() const { return left < 0; }
};

struct Tree {
  std::vector<Node> nodes;          // nodes[0] is the root
  std::vector<std::int32_t> order;  // tree position -> input index
};

std::int32_t build_node(const std::vector<Vec3>& points, Tree& tree, std::int32_t first, std::int32_t last,
                        int leaf_size) {
  Vec3 lo = points[tree.order[first]], hi = lo;
  for (std::int32_t i = first; i < last; ++i)
    for (int d = 0; d < 3; ++d) {
      lo[d] = std::min(lo[d], points[tree.order[i]][d]);
      hi[d] = std::max(hi[d], points[tree.order[i]][d]);
    }
  Node node;
  node.centre = 0.5 * (lo + hi);
  node.first = first;
  node.last = last;
  for (std::int32_t i = first; i < last; ++i)
    node.radius = std::max(node.radius, norm(points[tree.order[i]] - node.centre));
  const auto index = static_cast<std::int32_t>(tree.nodes.size());
  tree.nodes.push_back(node);
  if (last - first <= leaf_size) return index;
  const Vec3 extent = hi - lo;
  const int axis = extent[0] >= extent[1] && extent[0] >= extent[2] ? 0 : extent[1] >= extent[2] ? 1 : 2;
  const std::int32_t middle = first + (last - first) / 2;
  std::nth_element(tree.order.begin() + first, tree.order.begin() + middle, tree.order.begin() + last,
                   [&](std::int32_t a, std::int32_t b) {
                     const double pa = points[a][axis], pb = points[b][axis];
                     return pa < pb || (pa == pb && a < b);
                   });
  const std::int32_t left = build_node(points, tree, first, middle, leaf_size);
  const std::int32_t right = build_node(points, tree, middle, last, leaf_size);
  tree.nodes[index].left = left;
  tree.nodes[index].right = right;
  return index;
}

Tree build_tree(const std::vector<Vec3>& points, int leaf_size) {
  Tree tree;
  tree.order.resize(points.size());
  for (std::size_t i = 0; i < points.size(); ++i) tree.order[i] = static_cast<std::int32_t>(i);
  if (!points.empty()) build_node(points, tree, 0, static_cast<std::int32_t>(points.size()), leaf_size);
  return tree;
}

// ---------------------------------------------------------------------------------------------------------------
// Multi-indices (i, j, k), i.e. monomials x^i y^j z^k, numbered by degree, then by decreasing i, then j.

constexpr int monomial_count(int degree) { return (degree + 1) * (degree + 2) * (degree + 3) / 6; }

constexpr int monomial_index(int i, int j, int k) {
  const int n = i + j + k;
  return n * (n + 1) * (n + 2) / 6 + (n - i) * (n - i + 1) / 2 + (n - i - j);
}

// Index tables of order P: multi-indices of degree <= 2P (the derivatives an expansion pair needs), and the
// index pairs of the cell-to-cell contraction and of the parent-to-child shift. Expansions are kept scaled
// by factorials (moments M_k / k!, local coefficients m! L_m, derivatives D^n f = n! a_n), which turns
// every binomial coefficient into 1: L'_m = Σ_k D_{m+k} M'_k and L'_m(child) = Σ_j L'_j δ^(j-m) / (j-m)!.
template <int P>
struct Tables {
  static constexpr int kTerms = monomial_count(P);       // moments and local coefficients
  static constexpr int kTaylor = monomial_count(2 * P);  // derivatives D_n
  // Σ over m of the number of j >= m with |j| <= P.
  static constexpr int kShifts = [] {
    int count = 0;
    for (int n = 0; n <= P; ++n) count += (n + 1) * (n + 2) / 2 * monomial_count(P - n);
    return count;
  }();
  std::array<std::array<int, 3>, kTaylor> exponent{};
  std::array<int, kTaylor> degree{};
  // The recurrence's terms: index of n - e_i and n - 2e_i (kTaylor, a zero slot, when absent) and their
  // weights n_i and n_i (n_i - 1).
  std::array<std::array<int, 3>, kTaylor> minus_one{}, minus_two{};
  std::array<std::array<double, 3>, kTaylor> weight_one{}, weight_two{};
  std::array<int, kTerms> parent{}, axis{};           // monomial = monomial[parent] * coordinate[axis] (degree >= 1)
  std::array<double, kTerms> inverse_factorial{};     // 1 / (i! j! k!)
  std::array<int, kTerms * kTerms> m2l_derivative{};  // index of m + k for the pair (m, k)
  std::array<int, kShifts> shift_target{}, shift_source{}, shift_monomial{};  // m, j, j - m

  constexpr Tables() {
    for (int n = 0; n <= 2 * P; ++n)
      for (int i = n; i >= 0; --i)
        for (int j = n - i; j >= 0; --j) {
          const int k = n - i - j, q = monomial_index(i, j, k);
          exponent[q] = {i, j, k};
          degree[q] = n;
          for (int d = 0; d < 3; ++d) {
            std::array<int, 3> e = {i, j, k};
            const int nd = e[d];
            e[d] -= 1;
            minus_one[q][d] = nd >= 1 ? monomial_index(e[0], e[1], e[2]) : kTaylor;
            weight_one[q][d] = nd;
            e[d] -= 1;
            minus_two[q][d] = nd >= 2 ? monomial_index(e[0], e[1], e[2]) : kTaylor;
            weight_two[q][d] = nd * (nd - 1);
          }
          if (n <= P) {
            inverse_factorial[q] = 1.0 / (factorial(i) * factorial(j) * factorial(k));
            if (n >= 1) {
              axis[q] = i > 0 ? 0 : j > 0 ? 1 : 2;
              parent[q] = minus_one[q][axis[q]];
            }
          }
        }
    int shift = 0;
    for (int m = 0; m < kTerms; ++m) {
      const auto& em = exponent[m];
      for (int k = 0; k < kTerms; ++k) {
        const auto& ek = exponent[k];
        m2l_derivative[m * kTerms + k] = monomial_index(em[0] + ek[0], em[1] + ek[1], em[2] + ek[2]);
      }
      for (int j = 0; j < kTerms; ++j) {
        const auto& ej = exponent[j];
        if (ej[0] < em[0] || ej[1] < em[1] || ej[2] < em[2]) continue;
        shift_target[shift] = m;
        shift_source[shift] = j;
        shift_monomial[shift] = monomial_index(ej[0] - em[0], ej[1] - em[1], ej[2] - em[2]);
        ++shift;
      }
    }
  }

 private:
  static constexpr double factorial(int n) { return n <= 1 ? 1.0 : n * factorial(n - 1); }
};

template <int P>
inline constexpr Tables<P> kTables{};

template <int P>
using Expansion = std::array<double, Tables<P>::kTerms>;

// Scaled monomials r^k / k! up to degree P.
template <int P>
void fill_scaled_monomials(const Vec3& r, double* mono) {
  mono[0] = 1;
  for (int q = 1; q < Tables<P>::kTerms; ++q) mono[q] = mono[kTables<P>.parent[q]] * r[kTables<P>.axis[q]];
  for (int q = 1; q < Tables<P>::kTerms; ++q) mono[q] *= kTables<P>.inverse_factorial[q];
}

// ---------------------------------------------------------------------------------------------------------------
// The expansion operators.

// M'_k = Σ q (c - y)^k / k! over the node's own sources (every node from its sources, not from its children's
// moments: a few more flops, one code path).
template <int P>
std::vector<Expansion<P>> node_moments(const Tree& tree, const std::vector<Vec3>& positions,
                                       const std::vector<double>& charges, int threads) {
  std::vector<Expansion<P>> moments(tree.nodes.size(), Expansion<P>{});
  parallel_ranges(static_cast<std::int64_t>(tree.nodes.size()), 64, threads, [&](std::int64_t begin, std::int64_t end) {
    Expansion<P> mono{};
    for (std::int64_t n = begin; n < end; ++n) {
      const Node& node = tree.nodes[n];
      for (std::int32_t i = node.first; i < node.last; ++i) {
        const std::int32_t source = tree.order[i];
        fill_scaled_monomials<P>(node.centre - positions[source], mono.data());
        for (int k = 0; k < Tables<P>::kTerms; ++k) moments[n][k] += charges[source] * mono[k];
      }
    }
  });
  return moments;
}

// The recurrence's factors of the kernel s^-a: D_n = -(first[n] Σ_i n_i R_i D_{n-e_i} + second[n] Σ_i
// n_i (n_i - 1) D_{n-2e_i}) / s, first = (2|n| - 2 + 2a) / |n|, second = (|n| - 2 + 2a) / |n|.
template <int P>
struct Recurrence {
  std::array<double, Tables<P>::kTaylor> first{}, second{};
  explicit Recurrence(double a) {
    for (int n = 1; n < Tables<P>::kTaylor; ++n) {
      const int degree = kTables<P>.degree[n];
      first[n] = (2 * degree - 2 + 2 * a) / degree;
      second[n] = (degree - 2 + 2 * a) / degree;
    }
  }
};

// Adds to `local` (about the target centre) the field of the source moments, r = target centre - source
// centre: the derivatives of s^-a at r, then the contraction.
template <int P>
void add_multipole_to_local(const Vec3& r, bool inverse_square, const Recurrence<P>& recurrence,
                            const Expansion<P>& moments, Expansion<P>& local) {
  constexpr auto& t = kTables<P>;
  std::array<double, Tables<P>::kTaylor + 1> derivative{};  // the last one stays 0 (absent terms)
  const double inverse_s = 1.0 / dot(r, r);
  derivative[0] = inverse_square ? inverse_s : std::sqrt(inverse_s);
  for (int n = 1; n < Tables<P>::kTaylor; ++n) {
    const auto &one = t.minus_one[n], &two = t.minus_two[n];
    const auto &w1 = t.weight_one[n], &w2 = t.weight_two[n];
    const double along =
        w1[0] * r[0] * derivative[one[0]] + w1[1] * r[1] * derivative[one[1]] + w1[2] * r[2] * derivative[one[2]];
    const double across = w2[0] * derivative[two[0]] + w2[1] * derivative[two[1]] + w2[2] * derivative[two[2]];
    derivative[n] = -(recurrence.first[n] * along + recurrence.second[n] * across) * inverse_s;
  }
  for (int m = 0; m < Tables<P>::kTerms; ++m) {
    double sum = 0;
    for (int k = 0; k < Tables<P>::kTerms; ++k)
      sum += derivative[t.m2l_derivative[m * Tables<P>::kTerms + k]] * moments[k];
    local[m] += sum;
  }
}

// The local expansion about a child's centre, `offset` = child centre - parent centre.
template <int P>
Expansion<P> shift_local(const Expansion<P>& local, const Vec3& offset) {
  constexpr auto& t = kTables<P>;
  Expansion<P> mono{}, shifted{};
  fill_scaled_monomials<P>(offset, mono.data());
  for (int e = 0; e < Tables<P>::kShifts; ++e)
    shifted[t.shift_target[e]] += local[t.shift_source[e]] * mono[t.shift_monomial[e]];
  return shifted;
}

// Sources in tree order, as arrays for the inner loops.
struct Sources {
  std::vector<double> x, y, z, q;
};

// Targets of one leaf, with their sums.
struct TargetBlock {
  std::vector<double> x, y, z, phi;
  [[nodiscard]] std::size_t size() const { return x.size(); }
};

template <PowerKernel kKernel>
void add_direct(const Sources& s, std::int32_t first, std::int32_t last, TargetBlock& b) {
  const std::size_t n = b.size();
  double* phi = b.phi.data();
  const double *tx = b.x.data(), *ty = b.y.data(), *tz = b.z.data();
  for (std::int32_t i = first; i < last; ++i) {
    const double sx = s.x[i], sy = s.y[i], sz = s.z[i], q = s.q[i];
    for (std::size_t t = 0; t < n; ++t) {
      const double dx = tx[t] - sx, dy = ty[t] - sy, dz = tz[t] - sz;
      const double r2 = dx * dx + dy * dy + dz * dz;
      if constexpr (kKernel == PowerKernel::kInverseSquare)
        phi[t] += q / r2;
      else
        phi[t] += q / std::sqrt(r2);
    }
  }
}

Sources sources_in_order(const std::vector<Vec3>& positions, const std::vector<double>& charges,
                         const std::vector<std::int32_t>& order) {
  Sources s;
  for (const std::int32_t i : order) {
    s.x.push_back(positions[i][0]);
    s.y.push_back(positions[i][1]);
    s.z.push_back(positions[i][2]);
    s.q.push_back(charges[i]);
  }
  return s;
}

// ---------------------------------------------------------------------------------------------------------------
// The dual-tree walk, driven by the target tree: each target node receives the source nodes its parent could
// not take (`candidates`), expands those far enough into its local expansion, splits the larger of the two
// when they are too close, and passes the rest to its children; a target leaf sums its near source leaves
// exactly. Every target's terms are added in an order fixed by the trees alone, so the result does not depend
// on which thread walks which subtree.

template <int P, PowerKernel kKernel>
class DualTreeWalk {
 public:
  DualTreeWalk(const std::vector<Vec3>& positions, const std::vector<double>& charges, const std::vector<Vec3>& points,
               const TreecodeParameters& parameters)
      : points_(points),
        theta_(parameters.theta),
        threads_(surface_threads(parameters.threads)),
        sources_tree_(build_tree(positions, parameters.source_leaf_size)),
        targets_tree_(build_tree(points, parameters.target_leaf_size)),
        moments_(node_moments<P>(sources_tree_, positions, charges, threads_)),
        sources_(sources_in_order(positions, charges, sources_tree_.order)),
        recurrence_(kInverseSquare ? 1.0 : 0.5),
        result_(points.size(), 0.0) {}

  std::vector<double> run() {
    // The walk is split into independent tasks at a fixed depth of the target tree (deep enough for a few
    // tasks per thread); the tasks' order of work is the same as a single walk's.
    std::vector<Task> tasks;
    walk(0, Expansion<P>{}, {0}, 0, &tasks);
    parallel_chunks(static_cast<std::int64_t>(tasks.size()), threads_, [&](std::int64_t chunk, int) {
      walk(tasks[chunk].target, tasks[chunk].local, tasks[chunk].candidates, kTaskDepth, nullptr);
    });
    return std::move(result_);
  }

 private:
  static constexpr int kTaskDepth = 8;
  static constexpr bool kInverseSquare = kKernel == PowerKernel::kInverseSquare;

  struct Task {
    std::int32_t target;
    Expansion<P> local;
    std::vector<std::int32_t> candidates;
  };

  void walk(std::int32_t target, Expansion<P> local, const std::vector<std::int32_t>& candidates, int depth,
            std::vector<Task>* tasks) {
    const Node& t = targets_tree_.nodes[target];
    if (tasks != nullptr && depth == kTaskDepth && !t.leaf()) {
      tasks->push_back({target, local, candidates});
      return;
    }
    std::vector<std::int32_t> deferred, near;
    std::vector<std::int32_t> stack(candidates.rbegin(), candidates.rend());
    while (!stack.empty()) {
      const std::int32_t index = stack.back();
      stack.pop_back();
      const Node& s = sources_tree_.nodes[index];
      if (s.radius + t.radius < theta_ * norm(t.centre - s.centre)) {
        add_multipole_to_local<P>(t.centre - s.centre, kInverseSquare, recurrence_, moments_[index], local);
      } else if (t.leaf() ? s.leaf() : (s.leaf() || s.radius <= t.radius)) {
        (t.leaf() ? near : deferred).push_back(index);
      } else {
        stack.push_back(s.right);
        stack.push_back(s.left);
      }
    }
    if (t.leaf()) {
      evaluate_leaf(t, local, near);
      return;
    }
    for (const std::int32_t child : {t.left, t.right})
      walk(child, shift_local<P>(local, targets_tree_.nodes[child].centre - t.centre), deferred, depth + 1, tasks);
  }

  void evaluate_leaf(const Node& t, const Expansion<P>& local, const std::vector<std::int32_t>& near) {
    TargetBlock block;
    Expansion<P> mono{};
    for (std::int32_t i = t.first; i < t.last; ++i) {
      const Vec3& p = points_[targets_tree_.order[i]];
      block.x.push_back(p[0]);
      block.y.push_back(p[1]);
      block.z.push_back(p[2]);
      fill_scaled_monomials<P>(p - t.centre, mono.data());
      double far = 0;
      for (int m = 0; m < Tables<P>::kTerms; ++m) far += local[m] * mono[m];
      block.phi.push_back(far);
    }
    for (const std::int32_t index : near) {
      const Node& s = sources_tree_.nodes[index];
      add_direct<kKernel>(sources_, s.first, s.last, block);
    }
    for (std::int32_t i = t.first; i < t.last; ++i) result_[targets_tree_.order[i]] = block.phi[i - t.first];
  }

  const std::vector<Vec3>& points_;
  double theta_;
  int threads_;
  Tree sources_tree_, targets_tree_;
  std::vector<Expansion<P>> moments_;
  Sources sources_;
  Recurrence<P> recurrence_;
  std::vector<double> result_;
};

template <int P>
std::vector<double> treecode_of_order(const std::vector<Vec3>& positions, const std::vector<double>& charges,
                                      const std::vector<Vec3>& points, PowerKernel kernel,
                                      const TreecodeParameters& parameters) {
  if (kernel == PowerKernel::kInverseSquare)
    return DualTreeWalk<P, PowerKernel::kInverseSquare>(positions, charges, points, parameters).run();
  return DualTreeWalk<P, PowerKernel::kInverseDistance>(positions, charges, points, parameters).run();
}

void check_sizes(const std::vector<Vec3>& positions, const std::vector<double>& charges) {
  if (positions.size() != charges.size())
    throw std::invalid_argument("power sum: as many charges as positions are needed");
}

}  // namespace

std::vector<double> direct_power_sum(const std::vector<Vec3>& positions, const std::vector<double>& charges,
                                     const std::vector<Vec3>& points, PowerKernel kernel, int threads) {
  check_sizes(positions, charges);
  std::vector<std::int32_t> order(positions.size());
  for (std::size_t i = 0; i < order.size(); ++i) order[i] = static_cast<std::int32_t>(i);
  const Sources sources = sources_in_order(positions, charges, order);
  std::vector<double> result(points.size(), 0.0);
  const auto count = static_cast<std::int32_t>(positions.size());
  parallel_ranges(static_cast<std::int64_t>(points.size()), 64, surface_threads(threads),
                  [&](std::int64_t begin, std::int64_t end) {
                    TargetBlock block;
                    for (std::int64_t i = begin; i < end; ++i) {
                      block.x.push_back(points[i][0]);
                      block.y.push_back(points[i][1]);
                      block.z.push_back(points[i][2]);
                    }
                    block.phi.assign(block.size(), 0.0);
                    if (kernel == PowerKernel::kInverseSquare)
                      add_direct<PowerKernel::kInverseSquare>(sources, 0, count, block);
                    else
                      add_direct<PowerKernel::kInverseDistance>(sources, 0, count, block);
                    std::copy(block.phi.begin(), block.phi.end(), result.begin() + begin);
                  });
  return result;
}

std::vector<double> treecode_power_sum(const std::vector<Vec3>& positions, const std::vector<double>& charges,
                                       const std::vector<Vec3>& points, PowerKernel kernel,
                                       const TreecodeParameters& parameters) {
  check_sizes(positions, charges);
  if (!(parameters.theta > 0 && parameters.theta < 1) || parameters.order < 0 || parameters.order > kMaxTreecodeOrder ||
      parameters.source_leaf_size < 1 || parameters.target_leaf_size < 1)
    throw std::invalid_argument("treecode: theta in (0, 1), order in [0, 6] and leaf sizes >= 1 are needed");
  if (positions.empty() || points.empty()) return std::vector<double>(points.size(), 0.0);
  switch (parameters.order) {
    case 0: return treecode_of_order<0>(positions, charges, points, kernel, parameters);
    case 1: return treecode_of_order<1>(positions, charges, points, kernel, parameters);
    case 2: return treecode_of_order<2>(positions, charges, points, kernel, parameters);
    case 3: return treecode_of_order<3>(positions, charges, points, kernel, parameters);
    case 4: return treecode_of_order<4>(positions, charges, points, kernel, parameters);
    case 5: return treecode_of_order<5>(positions, charges, points, kernel, parameters);
    default: return treecode_of_order<6>(positions, charges, points, kernel, parameters);
  }
}

}  // namespace spheremap::detail
