#include "planar.hpp"

#include <algorithm>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <unordered_set>
#include <utility>

#include "meridian.hpp"
#include "spheremap/geometry/vec.hpp"

namespace spheremap::detail {
namespace {

// Fill-reducing orders (harmonic.hpp). The geometric nested dissection is cheap and the best on smooth,
// convex-ish shapes (a subdivided cube, perturbed or not), but a plane cuts a molecular surface, or a
// body with limbs (armadillo), along long curves, where AMD's order needs 2-10x fewer flops. The flops of
// the geometric order per n^1.5 do not tell the two kinds apart (armadillo's 29 and a cube's 34), so on
// a mesh of kTryAmdVertices or more AMD's order is always computed (about as cheap as the geometric one,
// and it counts its own flops), analysed only if it needs fewer, and the one with fewer flops serves
// every factorization of the map. Fewer flops has meant less time on every mesh measured
// (BENCHMARKS.md). Below that size a factorization takes milliseconds in any order.
constexpr std::size_t kTryAmdVertices = 5000;

// Side of neighbour `i` of meridian vertex `b` whose meridian neighbours are `up` (towards N) and `down`:
// counter-clockwise from `up` one meets the west side first (north is up, seen from outside).
bool is_west_of(const VertexRings& rings, std::int32_t b, std::int32_t up, std::int32_t down, std::int32_t i) {
  const auto ring = rings.ring(b);
  const auto size = ring.size();
  std::size_t start = 0;
  while (start < size && ring[start] != up) ++start;
  for (std::size_t k = 1; k < size; ++k) {
    const auto w = ring[(start + k) % size];
    if (w == i) return true;
    if (w == down) return false;
  }
  return false;
}

// z: harmonic between the rings (+Z on the north ring, -Z on the south ring). Returns whether `factor`
// factorized z's system (then φ may reuse the factorization).
bool solve_z(const WorkingMesh& work, std::int32_t north, std::int32_t south, const EdgeWeights& weights,
             const MapOptions& options, ReusableCholesky* factor, PlanarCoordinates& planar) {
  const auto& rings = work.rings;
  const auto n = rings.vertex_count();
  HarmonicProblem z_problem{&rings, &weights, &work.positions, std::vector<char>(n, 0), {}};
  planar.z.assign(n, 0.0);
  z_problem.fixed[north] = z_problem.fixed[south] = 1;
  planar.z[north] = kRingZ;
  planar.z[south] = -kRingZ;
  for (auto v : rings.ring(north)) z_problem.fixed[v] = 1, planar.z[v] = kRingZ;
  for (auto v : rings.ring(south)) z_problem.fixed[v] = 1, planar.z[v] = -kRingZ;
  const bool factorized = factor && factor->factorize(z_problem);
  if (factorized) {
    factor->solve(z_problem, planar.z);
    planar.z_stats = {LinearSolver::kCholmodLlt, 0, true};
  } else {
    planar.z_stats = solve_harmonic(z_problem, planar.z, options.solver, options.gauss_seidel_tolerance,
                                    options.gauss_seidel_max_sweeps);
  }
  return factorized;
}

// φ's Dirichlet problem: rings uniformly spaced, meridian at 0 (seen from the east) and 2π (from the
// west). Sets the fixed values in `phi`.
HarmonicProblem phi_problem_for(const WorkingMesh& work, std::int32_t north, std::int32_t south,
                                const EdgeWeights& weights, const std::vector<std::int32_t>& meridian,
                                std::vector<double>& phi) {
  const auto& rings = work.rings;
  const auto n = rings.vertex_count();
  const auto north_ring = rings.ring(north);
  const auto south_ring = rings.ring(south);
  HarmonicProblem phi_problem{&rings, &weights, &work.positions, std::vector<char>(n, 0),
                              std::vector<double>(rings.neighbors.size(), std::nan(""))};
  phi.assign(n, 0.0);
  phi_problem.fixed[north] = phi_problem.fixed[south] = 1;
  {
    const auto size = static_cast<std::int64_t>(north_ring.size());
    std::int64_t first = 0;
    while (north_ring[first] != meridian.front()) ++first;
    for (std::int64_t k = 0; k < size; ++k) {
      const auto v = north_ring[(first + k) % size];
      phi_problem.fixed[v] = 1;
      phi[v] = 2 * std::numbers::pi * static_cast<double>(k) / static_cast<double>(size);
    }
  }
  {
    // Counter-clockwise around S seen from outside is clockwise seen from +z: φ decreases.
    const auto size = static_cast<std::int64_t>(south_ring.size());
    std::int64_t first = 0;
    while (south_ring[first] != meridian.back()) ++first;
    for (std::int64_t k = 0; k < size; ++k) {
      const auto v = south_ring[(first + k) % size];
      phi_problem.fixed[v] = 1;
      phi[v] = k == 0 ? 0.0 : 2 * std::numbers::pi * static_cast<double>(size - k) / static_cast<double>(size);
    }
  }
  for (std::size_t m = 0; m < meridian.size(); ++m) {
    const auto b = meridian[m];
    phi_problem.fixed[b] = 1;
    phi[b] = 0;
  }
  for (std::size_t m = 0; m < meridian.size(); ++m) {
    const auto b = meridian[m];
    const auto up = m == 0 ? north : meridian[m - 1];
    const auto down = m + 1 == meridian.size() ? south : meridian[m + 1];
    for (auto i : rings.ring(b)) {
      if (phi_problem.fixed[i]) continue;
      const auto ring_i = rings.ring(i);
      for (std::size_t k = 0; k < ring_i.size(); ++k) {
        if (ring_i[k] != b) continue;
        phi_problem.slot_value[rings.offsets[i] + static_cast<std::int64_t>(k)] =
            is_west_of(rings, b, up, down, i) ? 2 * std::numbers::pi : 0.0;
      }
    }
  }
  return phi_problem;
}

Vec3 unit_from_angles(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

}  // namespace

void split_dividing_edges(WorkingMesh& work, std::int32_t pole, char tag, std::vector<SplitEdge>& splits) {
  const auto ring_span = work.rings.ring(pole);
  const std::vector<std::int32_t> ring(ring_span.begin(), ring_span.end());
  const auto size = static_cast<std::int64_t>(ring.size());
  std::vector<std::int64_t> position(work.positions.size(), -1);
  for (std::int64_t k = 0; k < size; ++k) position[ring[k]] = k;
  std::vector<std::pair<std::int32_t, std::int32_t>> chords;
  for (auto a : ring) {
    for (auto b : work.rings.ring(a)) {
      if (b >= static_cast<std::int32_t>(position.size()) || position[b] < 0 || b < a) continue;
      const auto gap = std::abs(position[a] - position[b]);
      if (gap != 1 && gap != size - 1) chords.emplace_back(a, b);
    }
  }
  if (chords.empty()) return;
  std::sort(chords.begin(), chords.end());
  std::unordered_set<std::int32_t> on_ring(ring.begin(), ring.end());
  std::vector<std::int32_t> candidates;  // triangles touching the ring: the only ones a chord can be in
  for (std::int32_t t = 0; t < static_cast<std::int32_t>(work.triangles.size()); ++t) {
    const auto& tri = work.triangles[t];
    if (on_ring.count(tri[0]) || on_ring.count(tri[1]) || on_ring.count(tri[2])) candidates.push_back(t);
  }
  for (const auto& [a, b] : chords) {
    const auto midpoint = static_cast<std::int32_t>(work.positions.size());
    work.positions.push_back(0.5 * (work.positions[a] + work.positions[b]));
    int replaced = 0;
    for (std::size_t c = 0, count = candidates.size(); c < count; ++c) {
      auto& tri = work.triangles[candidates[c]];
      for (int s = 0; s < 3; ++s) {
        const auto u = tri[s], v = tri[(s + 1) % 3], opposite = tri[(s + 2) % 3];
        if (!((u == a && v == b) || (u == b && v == a))) continue;
        tri = {u, midpoint, opposite};
        work.triangles.push_back({midpoint, v, opposite});
        candidates.push_back(static_cast<std::int32_t>(work.triangles.size()) - 1);
        ++replaced;
        break;
      }
    }
    if (replaced != 2) throw std::logic_error("split_dividing_edges: a dividing edge is not shared by two triangles");
    splits.push_back({a, b, tag});
  }
}

PlanarCoordinates solve_planar(const WorkingMesh& work, std::int32_t north, std::int32_t south,
                               const EdgeWeights& weights, const MapOptions& options, ReusableCholesky* factor,
                               const PlanarCoordinates* kept, int round) {
  PlanarCoordinates planar;
  const bool factorized = solve_z(work, north, south, weights, options, factor, planar);

  // Boundary meridian (meridian.hpp): the best round's if z still strictly decreases along it.
  auto found = boundary_meridian(work.rings, planar.z, north, south, kept ? &kept->meridian : nullptr);
  planar.meridian = std::move(found.path);
  planar.meridian_by_descent = found.kept ? kept->meridian_by_descent : found.by_descent;
  planar.meridian_round = found.kept ? kept->meridian_round : round;

  // φ: from z's factorization when the meridian interior was ordered last in it.
  const auto& meridian = planar.meridian;
  HarmonicProblem phi_problem = phi_problem_for(work, north, south, weights, meridian, planar.phi);
  const std::vector<std::int32_t> meridian_interior(meridian.begin() + 1, meridian.end() - 1);
  if (factorized && factor->last() == meridian_interior) {
    factor->solve(phi_problem, planar.phi, true);
    planar.phi_stats = {LinearSolver::kCholmodLlt, 0, true};
  } else if (factor && factor->factorize(phi_problem)) {
    factor->solve(phi_problem, planar.phi);
    planar.phi_stats = {LinearSolver::kCholmodLlt, 0, true};
  } else {
    planar.phi_stats = solve_harmonic(phi_problem, planar.phi, options.solver, options.gauss_seidel_tolerance,
                                      options.gauss_seidel_max_sweeps);
  }
  return planar;
}

std::unique_ptr<ReusableCholesky> make_factor(const WorkingMesh& work, const OrderChoice& order,
                                              const std::vector<std::int32_t>& last) {
  if (order.chosen) return std::make_unique<ReusableCholesky>(work.rings, *order.chosen, last);
  return std::make_unique<ReusableCholesky>(work.rings, work.positions, order.always_fixed, last);
}

std::unique_ptr<ReusableCholesky> plain_map_factor(const WorkingMesh& work, OrderChoice& order) {
  auto factor = make_factor(work, order);
  if (work.positions.size() >= kTryAmdVertices) {
    auto amd = amd_elimination_order(work.rings, work.positions, order.always_fixed);
    if (amd.method == FillReducingOrder::kAmd && amd.flops < factor->flops()) {
      auto amd_factor = std::make_unique<ReusableCholesky>(work.rings, amd);
      if (amd_factor->flops() < factor->flops()) order.chosen = std::move(amd), factor = std::move(amd_factor);
    }
  }
  return factor;
}

std::vector<Vec3> to_sphere(const PlanarCoordinates& planar, std::int32_t north, std::int32_t south, double c,
                            std::int32_t count) {
  std::vector<Vec3> sphere(count);
  for (std::int32_t v = 0; v < count; ++v) {
    const double theta = 2 * std::atan(std::exp(-planar.z[v] / c));
    sphere[v] = unit_from_angles(theta, planar.phi[v]);
  }
  sphere[north] = {0, 0, 1};
  sphere[south] = {0, 0, -1};
  return sphere;
}

}  // namespace spheremap::detail
