#include "harmonic.hpp"

#include <cholmod.h>
#include <Eigen/CholmodSupport>
#include <Eigen/Sparse>
#include <Eigen/UmfPackSupport>

#include <algorithm>
#include <cmath>
#include <numeric>
#include <stdexcept>

#include "solver_section.hpp"
#include "spheremap/geometry/vec.hpp"

namespace spheremap::detail {

EdgeWeights compute_weights(const VertexRings& rings, const std::vector<Vec3>& positions, Weights kind) {
  EdgeWeights weights;
  weights.values.assign(rings.neighbors.size(), 1.0);
  weights.symmetric = kind != Weights::kMeanValue;
  if (kind == Weights::kUniform) return weights;
  const auto n = rings.vertex_count();
  for (std::int32_t v = 0; v < n; ++v) {
    const auto ring = rings.ring(v);
    const auto degree = static_cast<std::int64_t>(ring.size());
    const Vec3& p = positions[v];
    bool usable = true;
    for (std::int64_t k = 0; k < degree; ++k) {
      const Vec3& w = positions[ring[k]];
      const Vec3& next = positions[ring[(k + 1) % degree]];
      const Vec3& prev = positions[ring[(k + degree - 1) % degree]];
      double value;
      if (kind == Weights::kCotangent) {
        // Angles opposite the edge (v, w): at `next` in triangle (v, w, next), at `prev` in (v, prev, w).
        auto cotangent = [](const Vec3& apex, const Vec3& x, const Vec3& y) {
          const Vec3 a = x - apex, b = y - apex;
          return dot(a, b) / norm(cross(a, b));
        };
        value = 0.5 * (cotangent(next, p, w) + cotangent(prev, p, w));
      } else {
        // tan(δ/2) = |a × b| / (|a||b| + a·b), stable for every angle δ in (0, π).
        auto half_tangent = [](const Vec3& a, const Vec3& b) {
          return norm(cross(a, b)) / (norm(a) * norm(b) + dot(a, b));
        };
        const Vec3 e = w - p;
        value = (half_tangent(e, next - p) + half_tangent(prev - p, e)) / norm(e);
        if (!(value > 0)) usable = false;
      }
      if (!std::isfinite(value)) usable = false;
      weights.values[rings.offsets[v] + k] = value;
    }
    if (!usable) {
      // A degenerate corner (zero-length edge or zero angle): this row keeps uniform weights.
      for (std::int64_t k = 0; k < degree; ++k) weights.values[rings.offsets[v] + k] = 1.0;
      ++weights.fallback_rows;
      weights.symmetric = false;
    }
  }
  return weights;
}

namespace {

double neighbour_value(const HarmonicProblem& problem, const std::vector<double>& x, std::int64_t slot,
                       std::int32_t neighbour) {
  if (!problem.slot_value.empty() && !std::isnan(problem.slot_value[slot])) return problem.slot_value[slot];
  return x[neighbour];
}

SolveStats solve_gauss_seidel(const HarmonicProblem& problem, std::vector<double>& x, double tolerance,
                              std::int64_t max_sweeps) {
  const auto& rings = *problem.rings;
  const auto& w = problem.weights->values;
  const auto n = rings.vertex_count();
  SolveStats stats{LinearSolver::kGaussSeidel, 0, false};
  // The paper starts from 0.
  for (std::int32_t v = 0; v < n; ++v)
    if (!problem.fixed[v]) x[v] = 0;
  double scale = 0;
  for (std::int32_t v = 0; v < n; ++v)
    if (problem.fixed[v]) scale = std::max(scale, std::abs(x[v]));
  for (std::int64_t k = 0; k < static_cast<std::int64_t>(problem.slot_value.size()); ++k)
    if (!std::isnan(problem.slot_value[k])) scale = std::max(scale, std::abs(problem.slot_value[k]));
  const double threshold = tolerance * std::max(scale, 1.0);
  while (stats.sweeps < max_sweeps) {
    ++stats.sweeps;
    double largest_change = 0;
    for (std::int32_t v = 0; v < n; ++v) {
      if (problem.fixed[v]) continue;
      double sum = 0, total = 0;
      const auto ring = rings.ring(v);
      for (std::size_t k = 0; k < ring.size(); ++k) {
        const auto slot = rings.offsets[v] + static_cast<std::int64_t>(k);
        sum += w[slot] * neighbour_value(problem, x, slot, ring[k]);
        total += w[slot];
      }
      const double updated = sum / total;
      largest_change = std::max(largest_change, std::abs(updated - x[v]));
      x[v] = updated;
    }
    if (largest_change < threshold) {
      stats.converged = true;
      break;
    }
  }
  return stats;
}

// An unknown's position and number, side by side: the splits below compare and move these in place,
// which reads memory in order instead of looking each coordinate up by number.
struct OrderPoint {
  Vec3 position;
  std::int32_t unknown;
};

// Splits points[first, last) along `axis` near the median, in the widest gap between consecutive
// coordinates among the middle tenth (ties: the gap nearest the median), and returns where the upper part
// starts (both parts rearranged in place).
// Splitting exactly at the median cuts through the row of vertices that holds it: on a regular grid whose
// vertices are perturbed (or on any mesh whose vertices line up across the axis) that scatters the row
// over both halves, and the separator becomes a jagged band of one and a half rows or more, which costs
// the factorization several times the flops (3.8x on a subdivided cube perturbed by 5% of an edge). A wide
// gap passes between rows, where a plane cuts the fewest edges.
// Systems of fewer than kGapSplitVertices unknowns (meshes of about as many vertices) are split exactly
// at the median (ties by index), as before the gap split: their factorizations take milliseconds in any
// order, and a new order changes the last bits of their maps, which changed one of them by more than
// rounding (libigl_bumpy.off, 1,250 vertices: the plain map's smallest area ratio 0.0401 -> 0.0420,
// octant RMS 0.50% -> 0.88%).
// Which points end in each part depends only on the set in [first, last) (the comparison is a total
// order: coordinate, then number), not on their arrangement.
OrderPoint* widest_gap_split(OrderPoint* first, OrderPoint* last, int axis, bool in_gap) {
  auto less = [axis](const OrderPoint& x, const OrderPoint& y) {
    return x.position[axis] != y.position[axis] ? x.position[axis] < y.position[axis] : x.unknown < y.unknown;
  };
  const auto size = last - first;
  OrderPoint* const median = first + size / 2;
  if (!in_gap) {
    std::nth_element(first, median, last, less);
    return median;
  }
  OrderPoint* const low = first + size * 9 / 20;
  OrderPoint* const high = first + size * 11 / 20 + 1;
  std::nth_element(first, low, last, less);
  std::nth_element(low, high - 1, last, less);
  std::sort(low, high, less);
  OrderPoint* split = median;
  double widest = -1;
  for (OrderPoint* it = low + 1; it < high; ++it) {
    const double gap = it->position[axis] - (it - 1)->position[axis];
    if (gap > widest || (gap == widest && std::abs(it - median) < std::abs(split - median))) widest = gap, split = it;
  }
  return split;
}

// The neighbours of each unknown among the unknowns, as compressed columns: those of unknown k are
// index[start[k]] to index[start[k + 1] - 1] (an entry for k itself is allowed).
struct UnknownGraph {
  const int* start;
  const int* index;
};

// Order of the unknowns for a sparse Cholesky factorization: split the unknowns near the median of their
// longest bounding-box axis (widest_gap_split), take those of the lower half that touch the upper half as
// the separator, order both halves recursively and the separator last. On surface meshes the separators
// are curves of O(√n) vertices, which gives nested dissection's O(n^1.5) work instead of minimum degree's.
// Each block is a range of one array of points, split in place: the lower half is rearranged into the
// unknowns that stay in it and the separator, which keeps its range until both halves are ordered.
std::vector<std::int32_t> nested_dissection_order(const UnknownGraph& graph, const std::vector<Vec3>& positions) {
  const auto n = static_cast<std::int32_t>(positions.size());
  std::vector<std::int32_t> order;
  order.reserve(n);
  std::vector<OrderPoint> points(static_cast<std::size_t>(n));
  for (std::int32_t k = 0; k < n; ++k) points[k] = {positions[k], k};
  std::vector<std::int32_t> part(n, 0);  // part id of each unknown's upper half during the recursion
  constexpr std::ptrdiff_t kLeaf = 64;
  constexpr std::int32_t kGapSplitVertices = 5000;
  const bool in_gap = n >= kGapSplitVertices;
  std::int32_t next_part = 1;
  // Emits the unknowns of points[first, last) in increasing number.
  auto emit_sorted = [&](OrderPoint* first, OrderPoint* last) {
    const auto begin = order.size();
    for (OrderPoint* it = first; it != last; ++it) order.push_back(it->unknown);
    std::sort(order.begin() + static_cast<std::ptrdiff_t>(begin), order.end());
  };
  struct Task {
    OrderPoint* first;
    OrderPoint* last;
    bool emit_only;  // a separator, emitted once both halves are done
  };
  std::vector<Task> stack;
  if (n > 0) stack.push_back({points.data(), points.data() + n, false});
  while (!stack.empty()) {
    const Task task = stack.back();
    stack.pop_back();
    if (task.emit_only || task.last - task.first <= kLeaf) {
      emit_sorted(task.first, task.last);
      continue;
    }
    Vec3 lo = task.first->position, hi = lo;
    for (const OrderPoint* it = task.first; it != task.last; ++it)
      for (int a = 0; a < 3; ++a) lo[a] = std::min(lo[a], it->position[a]), hi[a] = std::max(hi[a], it->position[a]);
    int axis = 0;
    for (int a = 1; a < 3; ++a)
      if (hi[a] - lo[a] > hi[axis] - lo[axis]) axis = a;
    OrderPoint* const middle = widest_gap_split(task.first, task.last, axis, in_gap);
    if (middle == task.first) {  // cannot split further (all points coincide)
      emit_sorted(task.first, task.last);
      continue;
    }
    const std::int32_t upper_id = next_part++;
    for (const OrderPoint* it = middle; it != task.last; ++it) part[it->unknown] = upper_id;
    OrderPoint* const separator = std::partition(task.first, middle, [&](const OrderPoint& point) {
      for (int e = graph.start[point.unknown]; e < graph.start[point.unknown + 1]; ++e)
        if (part[graph.index[e]] == upper_id) return false;
      return true;
    });
    stack.push_back({separator, middle, true});
    stack.push_back({middle, task.last, false});
    stack.push_back({task.first, separator, false});
  }
  return order;
}

// The matrix of `problem` over its unknowns, both triangles (for the fill-reducing order and LU).
Eigen::SparseMatrix<double> problem_matrix(const HarmonicProblem& problem,
                                           const std::vector<std::int32_t>& unknown_index, std::int32_t unknowns) {
  const auto& rings = *problem.rings;
  const auto& w = problem.weights->values;
  std::vector<Eigen::Triplet<double>> entries;
  entries.reserve(rings.neighbors.size() + static_cast<std::size_t>(unknowns));
  for (std::int32_t v = 0; v < rings.vertex_count(); ++v) {
    if (problem.fixed[v]) continue;
    const auto row = unknown_index[v];
    double total = 0;
    const auto ring = rings.ring(v);
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const auto slot = rings.offsets[v] + static_cast<std::int64_t>(k);
      total += w[slot];
      if (!problem.fixed[ring[k]]) entries.emplace_back(row, unknown_index[ring[k]], -w[slot]);
    }
    entries.emplace_back(row, row, total);
  }
  Eigen::SparseMatrix<double> matrix(unknowns, unknowns);
  matrix.setFromTriplets(entries.begin(), entries.end());
  return matrix;
}

// CHOLMOD's workspace and one factor, freed on every path.
struct Cholmod {
  cholmod_common common{};
  cholmod_factor* factor = nullptr;
  Cholmod() {
    cholmod_start(&common);
    common.print = 0;
    common.nmethods = 1;
    common.method[0].ordering = CHOLMOD_NATURAL;  // the rows come in our nested-dissection order
  }
  ~Cholmod() {
    if (factor) cholmod_free_factor(&factor, &common);
    cholmod_finish(&common);
  }
  Cholmod(const Cholmod&) = delete;
  Cholmod& operator=(const Cholmod&) = delete;
};

bool solve_cholesky(const HarmonicProblem& problem, const std::vector<std::int32_t>& unknown_index,
                    std::int32_t unknowns, std::vector<double>& x) {
  const auto& rings = *problem.rings;
  const auto n = rings.vertex_count();
  std::vector<Vec3> unknown_positions(static_cast<std::size_t>(unknowns));
  for (std::int32_t v = 0; v < n; ++v)
    if (!problem.fixed[v]) unknown_positions[unknown_index[v]] = (*problem.positions)[v];
  const Eigen::SparseMatrix<double> matrix = problem_matrix(problem, unknown_index, unknowns);
  // Fill-reducing order of our own (geometric nested dissection): CHOLMOD's default search tries
  // several orderings (far slower than the factorization) and plain AMD fills more on smooth surface meshes (on
  // molecular surfaces it fills less: map_to_sphere chooses between the two through ReusableCholesky, which this
  // one-off solve does not). The lower triangle is written column by column in that order, directly in CHOLMOD's
  // format, and factorized in natural order.
  const auto order = nested_dissection_order({matrix.outerIndexPtr(), matrix.innerIndexPtr()},
                                             unknown_positions);  // order[k]: unknown at row k
  std::vector<std::int32_t> row_of(static_cast<std::size_t>(unknowns));
  for (std::int32_t k = 0; k < unknowns; ++k) row_of[order[k]] = k;
  Cholmod cholmod;
  cholmod_sparse* lower = cholmod_allocate_sparse(unknowns, unknowns, static_cast<std::size_t>(matrix.nonZeros()), 1, 1,
                                                  -1, CHOLMOD_REAL, &cholmod.common);
  if (!lower) throw std::bad_alloc();
  auto* column_start = static_cast<int*>(lower->p);
  auto* row_index = static_cast<int*>(lower->i);
  auto* value = static_cast<double*>(lower->x);
  std::int64_t next = 0;
  std::vector<std::pair<int, double>> column;
  for (std::int32_t k = 0; k < unknowns; ++k) {
    column_start[k] = static_cast<int>(next);
    column.clear();
    for (Eigen::SparseMatrix<double>::InnerIterator entry(matrix, order[k]); entry; ++entry) {
      const int row = row_of[entry.row()];
      if (row >= k) column.emplace_back(row, entry.value());
    }
    std::sort(column.begin(), column.end());
    for (const auto& [row, v] : column) row_index[next] = row, value[next] = v, ++next;
  }
  column_start[unknowns] = static_cast<int>(next);
  {
    const SolverSection section;
    cholmod.factor = cholmod_analyze(lower, &cholmod.common);
    if (cholmod.factor) cholmod_factorize(lower, cholmod.factor, &cholmod.common);
  }
  cholmod_free_sparse(&lower, &cholmod.common);
  // An indefinite matrix (cotangent weights) is expected: the caller falls back to LU.
  if (!cholmod.factor || cholmod.common.status != CHOLMOD_OK ||
      cholmod.factor->minor < static_cast<std::size_t>(unknowns))
    return false;
  cholmod_dense* rhs = cholmod_zeros(static_cast<std::size_t>(unknowns), 1, CHOLMOD_REAL, &cholmod.common);
  if (!rhs) throw std::bad_alloc();
  auto* b = static_cast<double*>(rhs->x);
  const auto& w = problem.weights->values;
  for (std::int32_t v = 0; v < n; ++v) {
    if (problem.fixed[v]) continue;
    const auto ring = rings.ring(v);
    double sum = 0;
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const auto slot = rings.offsets[v] + static_cast<std::int64_t>(k);
      if (problem.fixed[ring[k]]) sum += w[slot] * neighbour_value(problem, x, slot, ring[k]);
    }
    b[row_of[unknown_index[v]]] = sum;
  }
  cholmod_dense* solution = nullptr;
  {
    const SolverSection section;
    solution = cholmod_solve(CHOLMOD_A, cholmod.factor, rhs, &cholmod.common);
  }
  cholmod_free_dense(&rhs, &cholmod.common);
  if (!solution) throw std::runtime_error("the Cholesky solve failed");
  const auto* values = static_cast<const double*>(solution->x);
  for (std::int32_t v = 0; v < n; ++v)
    if (!problem.fixed[v]) x[v] = values[row_of[unknown_index[v]]];
  cholmod_free_dense(&solution, &cholmod.common);
  return true;
}

}  // namespace

struct ReusableCholesky::State {
  const VertexRings* rings;
  std::vector<std::int32_t> last;
  std::vector<std::int32_t> row_of_vertex;  // permuted row of each structural unknown, -1 if always fixed
  std::vector<std::int32_t> vertex_of_row;
  // Source of each stored entry of the lower triangle, column by column: a slot (row vertex's ring
  // index of the column vertex) for couplings, or -1 - v for the diagonal of vertex v.
  std::vector<std::int64_t> entry_source;
  Cholmod cholmod;
  cholmod_sparse* lower = nullptr;
  bool factorized = false;
  ~State() {
    if (lower) cholmod_free_sparse(&lower, &cholmod.common);
  }
};

namespace {

// The unknowns of a mesh's systems (vertices not in `apart`), numbered in vertex order.
struct Unknowns {
  std::vector<std::int32_t> index;   // per vertex: its unknown number, -1 if apart
  std::vector<std::int32_t> vertex;  // per unknown: its vertex
};

Unknowns number_unknowns(std::int32_t n, const std::vector<char>& apart) {
  Unknowns unknowns;
  unknowns.index.assign(n, -1);
  for (std::int32_t v = 0; v < n; ++v)
    if (!apart[v]) unknowns.index[v] = static_cast<std::int32_t>(unknowns.vertex.size()), unknowns.vertex.push_back(v);
  return unknowns;
}

// Geometric nested dissection of the vertices not in `apart`, as vertex numbers.
std::vector<std::int32_t> geometric_order_of(const VertexRings& rings, const std::vector<Vec3>& positions,
                                             const std::vector<char>& apart) {
  const auto unknowns = number_unknowns(rings.vertex_count(), apart);
  const auto count = static_cast<std::int32_t>(unknowns.vertex.size());
  std::vector<Vec3> unknown_positions(static_cast<std::size_t>(count));
  for (std::int32_t k = 0; k < count; ++k) unknown_positions[k] = positions[unknowns.vertex[k]];
  // Only the pattern matters for the order: the neighbours that are unknowns, read off the rings.
  std::vector<int> start(static_cast<std::size_t>(count) + 1, 0), index;
  index.reserve(rings.neighbors.size());
  for (std::int32_t k = 0; k < count; ++k) {
    for (const auto w : rings.ring(unknowns.vertex[k]))
      if (unknowns.index[w] >= 0) index.push_back(unknowns.index[w]);
    start[k + 1] = static_cast<int>(index.size());
  }
  const auto order = nested_dissection_order({start.data(), index.data()}, unknown_positions);
  std::vector<std::int32_t> vertices(static_cast<std::size_t>(count));
  for (std::int32_t k = 0; k < count; ++k) vertices[k] = unknowns.vertex[order[k]];
  return vertices;
}

}  // namespace

EliminationOrder geometric_elimination_order(const VertexRings& rings, const std::vector<Vec3>& positions,
                                             const std::vector<char>& always_fixed) {
  return {geometric_order_of(rings, positions, always_fixed), FillReducingOrder::kGeometric};
}

namespace {

// An order of the unknowns (vertices not in always_fixed) from one of CHOLMOD's orderings, which read the
// upper triangle's pattern (with the diagonal) of a symmetric matrix, column by column.
template <typename Ordering>
EliminationOrder cholmod_elimination_order(const VertexRings& rings, const std::vector<Vec3>& positions,
                                           const std::vector<char>& always_fixed, FillReducingOrder method,
                                           Ordering&& ordering) {
  const auto unknowns = number_unknowns(rings.vertex_count(), always_fixed);
  const auto count = static_cast<std::int32_t>(unknowns.vertex.size());
  if (count == 0) return {{}, method};
  Cholmod cholmod;
  std::size_t entries = static_cast<std::size_t>(count);
  for (const auto v : unknowns.vertex)
    for (const auto w : rings.ring(v)) entries += unknowns.index[w] >= 0 && unknowns.index[w] < unknowns.index[v];
  cholmod_sparse* upper = cholmod_allocate_sparse(count, count, entries, 1, 1, 1, CHOLMOD_PATTERN, &cholmod.common);
  if (!upper) throw std::bad_alloc();
  auto* column_start = static_cast<int*>(upper->p);
  auto* row_index = static_cast<int*>(upper->i);
  std::int64_t next = 0;
  std::vector<int> rows;
  for (std::int32_t k = 0; k < count; ++k) {
    column_start[k] = static_cast<int>(next);
    rows.assign(1, k);
    for (const auto w : rings.ring(unknowns.vertex[k]))
      if (unknowns.index[w] >= 0 && unknowns.index[w] < k) rows.push_back(unknowns.index[w]);
    std::sort(rows.begin(), rows.end());
    for (const int row : rows) row_index[next++] = row;
  }
  column_start[count] = static_cast<int>(next);
  std::vector<int> permutation(static_cast<std::size_t>(count));
  const int ok = ordering(upper, permutation.data(), &cholmod.common);
  cholmod_free_sparse(&upper, &cholmod.common);
  if (!ok || cholmod.common.status != CHOLMOD_OK) return geometric_elimination_order(rings, positions, always_fixed);
  EliminationOrder order{std::vector<std::int32_t>(static_cast<std::size_t>(count)), method,
                         method == FillReducingOrder::kAmd ? std::max(0.0, cholmod.common.fl) : 0.0};
  for (std::int32_t k = 0; k < count; ++k) order.vertices[k] = unknowns.vertex[permutation[k]];
  return order;
}

}  // namespace

EliminationOrder metis_elimination_order(const VertexRings& rings, const std::vector<Vec3>& positions,
                                         const std::vector<char>& always_fixed) {
  return cholmod_elimination_order(rings, positions, always_fixed, FillReducingOrder::kMetis,
                                   [](cholmod_sparse* upper, int* permutation, cholmod_common* common) {
                                     return cholmod_metis(upper, nullptr, 0, /*postorder=*/1, permutation, common);
                                   });
}

EliminationOrder amd_elimination_order(const VertexRings& rings, const std::vector<Vec3>& positions,
                                       const std::vector<char>& always_fixed) {
  return cholmod_elimination_order(rings, positions, always_fixed, FillReducingOrder::kAmd,
                                   [](cholmod_sparse* upper, int* permutation, cholmod_common* common) {
                                     return cholmod_amd(upper, nullptr, 0, permutation, common);
                                   });
}

ReusableCholesky::ReusableCholesky(const VertexRings& rings, const std::vector<Vec3>& positions,
                                   const std::vector<char>& always_fixed, const std::vector<std::int32_t>& last)
    : state_(std::make_unique<State>()) {
  // The fill-reducing order of the unknowns that are not in `last`, then `last` in its order.
  std::vector<char> ordered_apart = always_fixed;
  for (auto v : last) ordered_apart[v] = 1;
  auto rows = geometric_order_of(rings, positions, ordered_apart);
  rows.insert(rows.end(), last.begin(), last.end());
  analyse(rings, std::move(rows), last);
}

ReusableCholesky::ReusableCholesky(const VertexRings& rings, const EliminationOrder& order,
                                   const std::vector<std::int32_t>& last)
    : state_(std::make_unique<State>()) {
  std::vector<char> is_last(static_cast<std::size_t>(rings.vertex_count()), 0);
  for (auto v : last) is_last[v] = 1;
  std::vector<std::int32_t> rows;
  rows.reserve(order.vertices.size());
  for (auto v : order.vertices)
    if (!is_last[v]) rows.push_back(v);
  rows.insert(rows.end(), last.begin(), last.end());
  analyse(rings, std::move(rows), last);
}

void ReusableCholesky::analyse(const VertexRings& rings, std::vector<std::int32_t> vertex_of_row,
                               const std::vector<std::int32_t>& last) {
  auto& s = *state_;
  s.rings = &rings;
  s.last = last;
  const auto n = rings.vertex_count();
  s.vertex_of_row = std::move(vertex_of_row);
  s.row_of_vertex.assign(n, -1);
  const auto unknowns = static_cast<std::int32_t>(s.vertex_of_row.size());
  for (std::int32_t k = 0; k < unknowns; ++k) s.row_of_vertex[s.vertex_of_row[k]] = k;
  // The lower triangle in the permuted order: column k holds its diagonal and every neighbour whose
  // row is below k, with the slot that supplies the weight.
  std::size_t entries = 0;
  for (std::int32_t k = 0; k < unknowns; ++k) {
    ++entries;
    for (auto w : rings.ring(s.vertex_of_row[k])) entries += s.row_of_vertex[w] > k;
  }
  s.lower = cholmod_allocate_sparse(unknowns, unknowns, entries, 1, 1, -1, CHOLMOD_REAL, &s.cholmod.common);
  if (!s.lower) throw std::bad_alloc();
  auto* column_start = static_cast<int*>(s.lower->p);
  auto* row_index = static_cast<int*>(s.lower->i);
  s.entry_source.reserve(entries);
  std::vector<std::pair<int, std::int64_t>> column;
  std::int64_t next = 0;
  for (std::int32_t k = 0; k < unknowns; ++k) {
    column_start[k] = static_cast<int>(next);
    const auto v = s.vertex_of_row[k];
    column.clear();
    column.emplace_back(k, -1 - static_cast<std::int64_t>(v));
    for (auto w : rings.ring(v)) {
      const auto row = s.row_of_vertex[w];
      if (row <= k) continue;  // always fixed (-1), or in the upper triangle
      // The weight of (w, v) as row w reads it.
      const auto w_ring = rings.ring(w);
      std::size_t back = 0;
      while (w_ring[back] != v) ++back;
      column.emplace_back(row, rings.offsets[w] + static_cast<std::int64_t>(back));
    }
    std::sort(column.begin(), column.end());
    for (const auto& [row, source] : column) {
      row_index[next] = row;
      s.entry_source.push_back(source);
      ++next;
    }
  }
  column_start[unknowns] = static_cast<int>(next);
  // CHOLMOD postorders the elimination tree by default, which can move `last` away from the end (the
  // fill is the same either way). METIS's orders come postordered by cholmod_metis (without that, their
  // factorizations are much slower), AMD's by AMD itself (it ends with a postorder of its assembly tree);
  // the geometric one is left as it is (CHOLMOD's postorder does not help it on every mesh).
  s.cholmod.common.postorder = false;
  {
    const SolverSection section;
    s.cholmod.factor = cholmod_analyze(s.lower, &s.cholmod.common);
  }
  if (!s.cholmod.factor || s.cholmod.common.status != CHOLMOD_OK)
    throw std::runtime_error("CHOLMOD's symbolic analysis failed");
}

ReusableCholesky::~ReusableCholesky() = default;

const std::vector<std::int32_t>& ReusableCholesky::last() const { return state_->last; }

double ReusableCholesky::flops() const { return state_->cholmod.common.fl; }

bool ReusableCholesky::supernodal() const { return state_->cholmod.factor->is_super != 0; }

bool ReusableCholesky::factorize(const HarmonicProblem& problem) {
  auto& s = *state_;
  const auto& rings = *s.rings;
  const auto& w = problem.weights->values;
  const auto unknowns = static_cast<std::int32_t>(s.vertex_of_row.size());
  s.factorized = false;
  if (unknowns == 0) return s.factorized = true;
  auto* value = static_cast<double*>(s.lower->x);
  const auto* row_index = static_cast<const int*>(s.lower->i);
  for (std::size_t e = 0; e < s.entry_source.size(); ++e) {
    const auto source = s.entry_source[e];
    if (source < 0) {
      const auto v = static_cast<std::int32_t>(-1 - source);
      if (problem.fixed[v]) {
        value[e] = 1;  // decoupled row: x_v = b_v
        continue;
      }
      double total = 0;
      for (auto slot = rings.offsets[v]; slot < rings.offsets[v + 1]; ++slot) total += w[slot];
      value[e] = total;
    } else {
      // A slot of the row vertex's ring; a coupling to or from a fixed vertex is 0.
      const auto r = s.vertex_of_row[row_index[e]];
      value[e] = problem.fixed[r] || problem.fixed[rings.neighbors[source]] ? 0.0 : -w[source];
    }
  }
  {
    const SolverSection section;
    cholmod_factorize(s.lower, s.cholmod.factor, &s.cholmod.common);
  }
  s.factorized = s.cholmod.common.status == CHOLMOD_OK && s.cholmod.factor->minor >= static_cast<std::size_t>(unknowns);
  return s.factorized;
}

void ReusableCholesky::solve(const HarmonicProblem& problem, std::vector<double>& x, bool last_fixed) {
  auto& s = *state_;
  if (!s.factorized) throw std::logic_error("ReusableCholesky::solve before a successful factorize");
  const auto& rings = *s.rings;
  const auto& w = problem.weights->values;
  const auto unknowns = static_cast<std::int32_t>(s.vertex_of_row.size());
  if (unknowns == 0) return;
  const auto kept = unknowns - (last_fixed ? static_cast<std::int32_t>(s.last.size()) : 0);
  cholmod_dense* rhs = cholmod_zeros(static_cast<std::size_t>(unknowns), 1, CHOLMOD_REAL, &s.cholmod.common);
  if (!rhs) throw std::bad_alloc();
  auto* b = static_cast<double*>(rhs->x);
  for (std::int32_t k = 0; k < kept; ++k) {
    const auto v = s.vertex_of_row[k];
    if (problem.fixed[v]) {
      b[k] = x[v];
      continue;
    }
    const auto ring = rings.ring(v);
    double sum = 0;
    for (std::size_t j = 0; j < ring.size(); ++j) {
      const auto slot = rings.offsets[v] + static_cast<std::int64_t>(j);
      if (problem.fixed[ring[j]]) sum += w[slot] * neighbour_value(problem, x, slot, ring[j]);
    }
    b[k] = sum;
  }
  cholmod_dense* solution = nullptr;
  const SolverSection section;  // the solves below
  if (!last_fixed) {
    solution = cholmod_solve(CHOLMOD_A, s.cholmod.factor, rhs, &s.cholmod.common);
  } else {
    // With `last` ordered last, the leading blocks of L (and D) factor the system without them:
    // forward substitution through LD, then the trailing part of the intermediate set to zero (so the
    // trailing unknowns come out 0 and drop out of the leading rows), then back substitution through
    // L'. LD, not L: CHOLMOD factors as LDL' where it chooses a simplicial factorization (small or
    // well-ordered systems: fl/lnz below 40), and as LL' (D = I) where it chooses a supernodal one.
    cholmod_dense* forward = cholmod_solve(CHOLMOD_LD, s.cholmod.factor, rhs, &s.cholmod.common);
    if (forward) {
      auto* y = static_cast<double*>(forward->x);
      std::fill(y + kept, y + unknowns, 0.0);
      solution = cholmod_solve(CHOLMOD_Lt, s.cholmod.factor, forward, &s.cholmod.common);
      cholmod_free_dense(&forward, &s.cholmod.common);
    }
  }
  cholmod_free_dense(&rhs, &s.cholmod.common);
  if (!solution) throw std::runtime_error("the Cholesky solve failed");
  const auto* values = static_cast<const double*>(solution->x);
  for (std::int32_t k = 0; k < kept; ++k) {
    const auto v = s.vertex_of_row[k];
    if (!problem.fixed[v]) x[v] = values[k];
  }
  cholmod_free_dense(&solution, &s.cholmod.common);
}

SolveStats solve_harmonic(const HarmonicProblem& problem, std::vector<double>& x, Solver solver, double tolerance,
                          std::int64_t max_sweeps) {
  if (solver == Solver::kGaussSeidel) return solve_gauss_seidel(problem, x, tolerance, max_sweeps);
  SolveStats stats;
  const auto n = problem.rings->vertex_count();
  const auto numbered = number_unknowns(n, problem.fixed);
  const auto& unknown_index = numbered.index;
  const auto unknowns = static_cast<std::int32_t>(numbered.vertex.size());
  if (unknowns == 0) {
    stats.solver = LinearSolver::kNone;
    return stats;
  }
  if (problem.weights->symmetric && solve_cholesky(problem, unknown_index, unknowns, x)) {
    stats.solver = LinearSolver::kCholmodLlt;
    return stats;
  }
  // Non-symmetric weights (mean-value), or an indefinite matrix (cotangent weights).
  const Eigen::SparseMatrix<double> matrix = problem_matrix(problem, unknown_index, unknowns);
  Eigen::VectorXd rhs = Eigen::VectorXd::Zero(unknowns);
  const auto& rings = *problem.rings;
  for (std::int32_t v = 0; v < n; ++v) {
    if (problem.fixed[v]) continue;
    const auto ring = rings.ring(v);
    for (std::size_t k = 0; k < ring.size(); ++k) {
      const auto slot = rings.offsets[v] + static_cast<std::int64_t>(k);
      if (problem.fixed[ring[k]])
        rhs[unknown_index[v]] += problem.weights->values[slot] * neighbour_value(problem, x, slot, ring[k]);
    }
  }
  Eigen::UmfPackLU<Eigen::SparseMatrix<double>> lu;
  const SolverSection section;  // the factorization and the solve
  lu.compute(matrix);
  if (lu.info() != Eigen::Success) throw SingularSystem("the sparse LU factorization failed (singular system)");
  const Eigen::VectorXd solution = lu.solve(rhs);
  if (lu.info() != Eigen::Success) throw std::runtime_error("the sparse LU solve failed");
  stats.solver = LinearSolver::kUmfpackLu;
  for (std::int32_t v = 0; v < n; ++v)
    if (!problem.fixed[v]) x[v] = solution[unknown_index[v]];
  return stats;
}

}  // namespace spheremap::detail
