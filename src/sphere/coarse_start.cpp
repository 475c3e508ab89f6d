#include "coarse_start.hpp"

#include <algorithm>
#include <cmath>
#include <limits>
#include <stdexcept>

#include "spheremap/geometry/predicates.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/sphere/certify.hpp"
#include "spheremap/topology/connectivity.hpp"
#include "spheremap/topology/simplify.hpp"
#include "untangle.hpp"

namespace spheremap::detail {
namespace {

// Each level has about this many times fewer vertices than the one above.
constexpr double kCoarsening = 10;
constexpr double kCoarseMinAngleDegrees = 5;
// Sweeps of the untangler over the triangles the prolongation folds (a few hundred of 86k on armadillo,
// thousands on GroEL's surface, where 20 sweeps did not reach every one).
constexpr int kUntanglingSweeps = 200;

double mean_edge_length(const Mesh& mesh) {
  double sum = 0;
  for (const auto& t : mesh.triangles)
    for (int k = 0; k < 3; ++k) sum += norm(mesh.positions[t[(k + 1) % 3]] - mesh.positions[t[k]]);
  return sum / static_cast<double>(3 * std::max<std::size_t>(mesh.triangles.size(), 1));
}

// The vertices in breadth-first order from `first`: consecutive ones lie close together, so each walk
// below starts next to its point.
std::vector<std::int32_t> breadth_first_order(const VertexRings& rings, std::int32_t first) {
  std::vector<std::int32_t> order{first};
  std::vector<char> seen(static_cast<std::size_t>(rings.vertex_count()), 0);
  seen[first] = 1;
  for (std::size_t i = 0; i < order.size(); ++i)
    for (const auto w : rings.ring(order[i]))
      if (!seen[w]) seen[w] = 1, order.push_back(w);
  return order;
}

// Locates points in a valid spherical triangulation by walking across the edges that separate the
// current triangle from the point (exact predicates, so the two sides of an edge agree). Where several
// edges do, the choice is pseudo-random but fixed by the point (a remembering stochastic walk, which
// cannot cycle for ever the way a deterministic walk can on a triangulation that is not Delaunay).
class Walker {
 public:
  Walker(const std::vector<Triangle>& triangles, const std::vector<Vec3>& points)
      : triangles_(triangles), points_(points), opposite_(opposite_half_edges(points.size(), triangles, 1)) {}

  // The triangle that holds p (on its boundary counts), starting from `start`; -1 after as many steps
  // as there are triangles.
  std::int64_t locate(const Vec3& p, std::int64_t start, std::uint64_t seed) const {
    std::int64_t t = start, previous = -1;
    std::uint64_t state = seed;
    for (std::size_t step = 0; step <= triangles_.size(); ++step) {
      const auto& tri = triangles_[static_cast<std::size_t>(t)];
      const Vec3 &a = points_[tri[0]], &b = points_[tri[1]], &c = points_[tri[2]];
      // Side k: the edge opposite corner k, half-edge 3t + (k + 1) % 3.
      const int sign[3] = {orientation_sign(p, b, c), orientation_sign(a, p, c), orientation_sign(a, b, p)};
      int choices[3], count = 0;
      for (int k = 0; k < 3; ++k)
        if (sign[k] < 0 && across(t, k) != previous) choices[count++] = k;
      if (count == 0)
        for (int k = 0; k < 3; ++k)
          if (sign[k] < 0) choices[count++] = k;
      if (count == 0) return t;
      state = state * 6364136223846793005ULL + 1442695040888963407ULL;
      previous = t;
      t = across(t, choices[(state >> 33) % static_cast<std::uint64_t>(count)]);
    }
    return -1;
  }

 private:
  std::int64_t across(std::int64_t t, int k) const {
    return opposite_[static_cast<std::size_t>(3 * t + (k + 1) % 3)] / 3;
  }

  const std::vector<Triangle>& triangles_;
  const std::vector<Vec3>& points_;
  std::vector<std::int32_t> opposite_;
};

// p, inside the triangle (a, b, c) of `before`, carried to the same barycentric coordinates of the central
// projection in (a', b', c') of `after`.
Vec3 carry(const Vec3& p, const Triangle& t, const std::vector<Vec3>& before, const std::vector<Vec3>& after) {
  const Vec3 &a = before[t[0]], &b = before[t[1]], &c = before[t[2]];
  double weight[3] = {dot(p, cross(b, c)), dot(a, cross(p, c)), dot(a, cross(b, p))};
  // Rounding may make a weight of a point on an edge slightly negative.
  for (double& w : weight) w = std::max(w, 0.0);
  if (!(weight[0] + weight[1] + weight[2] > 0)) weight[0] = weight[1] = weight[2] = 1;
  return normalized(weight[0] * after[t[0]] + weight[1] * after[t[1]] + weight[2] * after[t[2]]);
}

}  // namespace

bool coarse_start(const Mesh& mesh, std::vector<Vec3>& sphere, std::int32_t north, std::int32_t south,
                  const SphereOptimizeOptions& options, CoarseStart& report) {
  const auto vertices = static_cast<std::int64_t>(mesh.vertex_count());
  // A start that is not valid (rounding can flip a certified, nearly flat triangle when the map is
  // turned back to the construction's frame) gets no coarse start; the optimization refuses it anyway.
  if (vertices < kCoarseStartMinVertices || !positively_oriented(mesh.triangles, sphere)) return false;
  SimplifyOptions simplify;
  simplify.target_edge_length = mean_edge_length(mesh) * std::sqrt(kCoarsening);
  simplify.max_error = std::numeric_limits<double>::max();  // only the map's validity matters here
  // The coarse triangles' shapes matter little (the rest triangles of the optimization guard against
  // needles): at the default 20°, molecular surfaces lost only two thirds of their vertices.
  simplify.min_angle_degrees = kCoarseMinAngleDegrees;
  simplify.measure_distance = false;
  simplify.threads = options.threads;
  simplify.kept_vertices = {north, south};
  simplify.oriented_on = sphere;
  SimplifyReport simplified;
  const Mesh coarse = simplify_surface(mesh, simplify, &simplified);
  if (4 * coarse.vertex_count() > mesh.vertex_count()) return false;
  // The kept vertices' points: a valid map of the coarse mesh (simplify kept every triangle positive).
  std::vector<std::int32_t> coarse_of(mesh.vertex_count(), -1);
  std::vector<Vec3> before(coarse.vertex_count());
  for (std::size_t i = 0; i < before.size(); ++i) {
    coarse_of[simplified.kept_vertex[i]] = static_cast<std::int32_t>(i);
    before[i] = sphere[simplified.kept_vertex[i]];
  }
  const std::int32_t coarse_north = coarse_of[north], coarse_south = coarse_of[south];
  CoarseStart nested;  // stays empty when the coarse mesh gets no coarse start of its own
  std::vector<Vec3> after = before;
  coarse_start(coarse, after, coarse_north, coarse_south, options, nested);
  std::vector<char> fixed(coarse.vertex_count(), 0);
  fixed[coarse_north] = fixed[coarse_south] = 1;
  SphereOptimizeReport run;
  try {
    run = optimize_on_sphere(coarse.positions, coarse.triangles, after, fixed, options);
  } catch (const std::invalid_argument&) {
    return false;  // not expected (the start is valid), but a failed coarse start only costs its time
  }
  // Every vertex carried along with its coarse triangle (a kept one is that triangle's corner anyway).
  const Walker walker(coarse.triangles, before);
  std::vector<Vec3> carried(sphere.size());
  std::int64_t hint = 0;
  const VertexRings rings = build_vertex_rings(static_cast<std::int32_t>(vertices), mesh.triangles);
  for (const auto v : breadth_first_order(rings, north)) {
    if (coarse_of[v] >= 0) {
      carried[v] = after[coarse_of[v]];
      continue;
    }
    const auto t = walker.locate(sphere[v], hint, static_cast<std::uint64_t>(v));
    if (t < 0) return false;
    carried[v] = carry(sphere[v], coarse.triangles[static_cast<std::size_t>(t)], before, after);
    hint = t;
  }
  std::int64_t moves = 0;
  if (!positively_oriented(mesh.triangles, carried)) {
    std::vector<char> poles(sphere.size(), 0);
    poles[north] = poles[south] = 1;
    moves = untangle_on_sphere(mesh, rings, untangling_frame(mesh, rings), carried, kDefaultCollapseFloor,
                               kUntanglingSweeps, poles);
    if (!positively_oriented(mesh.triangles, carried)) return false;
  }
  // The coarse optimization and the untangler keep the poles; the optimization to come needs them exact.
  if (!(carried[north] == sphere[north]) || !(carried[south] == sphere[south])) return false;
  sphere.swap(carried);
  report.coarse_vertices = static_cast<std::int64_t>(coarse.vertex_count());
  report.levels = nested.levels + 1;
  report.iterations = nested.iterations + run.iterations;
  report.untangling_moves = nested.untangling_moves + moves;
  return true;
}

}  // namespace spheremap::detail
