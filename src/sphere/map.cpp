#include "spheremap/sphere/map.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <numbers>
#include <stdexcept>
#include <unordered_set>

#include <fmt/format.h>

#include "harmonic.hpp"
#include "spheremap/error.hpp"
#include "spheremap/geometry/predicates.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/shapes.hpp"
#include "untangle.hpp"

namespace spheremap {

const char* to_string(Weights weights) {
  switch (weights) {
    case Weights::kUniform: return "uniform";
    case Weights::kCotangent: return "cotan";
    case Weights::kMeanValue: return "mean-value";
  }
  return "?";
}
const char* to_string(Solver solver) { return solver == Solver::kDirect ? "direct" : "gauss-seidel"; }

namespace {

using Clock = std::chrono::steady_clock;
constexpr double kPi = std::numbers::pi;
constexpr double kRingZ = 1.0;  // Z: the circumpolar rings sit at z = ±Z
// Re-weighting against collapse, damped: Yoshizawa's full step (exponent 1/2, unbounded) overshoots and
// oscillates on limbs (measured on libigl_arm.obj: 9 rounds, 345 folds left); a quarter power with at
// most a 4x change per round per edge converges in 6–27 rounds on every mesh of ../shared/data/meshes.
constexpr double kReweightingExponent = 0.25;
constexpr double kReweightingStep = 4.0;
constexpr int kReweightingPatience = 8;  // rounds without a better map before giving up

class StageTimer {
 public:
  explicit StageTimer(std::vector<StageTime>& out) : out_(out), start_(Clock::now()) {}
  void lap(const std::string& stage) {
    const auto now = Clock::now();
    out_.push_back({stage, std::chrono::duration<double>(now - start_).count()});
    start_ = now;
  }

 private:
  std::vector<StageTime>& out_;
  Clock::time_point start_;
};

// The mesh the planar problem is solved on: the input plus one midpoint per split dividing edge.
struct WorkingMesh {
  std::vector<Vec3> positions;
  std::vector<Triangle> triangles;
  VertexRings rings;
};

// Splits every edge joining two non-consecutive vertices of the ring around `pole` (a separating
// triangle through the pole): such an edge would pin everything on its pole side to z = ±Z.
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

struct PlanarCoordinates {
  std::vector<double> z, phi;
  std::vector<std::int32_t> meridian;
  bool meridian_by_descent = true;
  detail::SolveStats z_stats, phi_stats;
};

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

PlanarCoordinates solve_planar(const WorkingMesh& work, std::int32_t north, std::int32_t south,
                               const detail::EdgeWeights& weights, const MapOptions& options) {
  const auto& rings = work.rings;
  const auto n = rings.vertex_count();
  const auto north_ring = rings.ring(north);
  const auto south_ring = rings.ring(south);
  std::vector<char> on_north_ring(n, 0), on_south_ring(n, 0);
  for (auto v : north_ring) on_north_ring[v] = 1;
  for (auto v : south_ring) on_south_ring[v] = 1;

  PlanarCoordinates planar;
  // z: harmonic between the rings.
  detail::HarmonicProblem z_problem{&rings, &weights, &work.positions, std::vector<char>(n, 0), {}};
  planar.z.assign(n, 0.0);
  z_problem.fixed[north] = z_problem.fixed[south] = 1;
  planar.z[north] = kRingZ;
  planar.z[south] = -kRingZ;
  for (auto v : north_ring) z_problem.fixed[v] = 1, planar.z[v] = kRingZ;
  for (auto v : south_ring) z_problem.fixed[v] = 1, planar.z[v] = -kRingZ;
  planar.z_stats = detail::solve_harmonic(z_problem, planar.z, options.solver, options.gauss_seidel_tolerance,
                                          options.gauss_seidel_max_sweeps);

  // Boundary meridian: steepest descent in the strict total order (z, index), so that ties cannot stall
  // or loop and no edge can join two non-consecutive meridian vertices.
  auto lower = [&](std::int32_t a, std::int32_t b) {
    return planar.z[a] != planar.z[b] ? planar.z[a] < planar.z[b] : a < b;
  };
  auto lowest_neighbour = [&](std::int32_t v) {
    std::int32_t best = -1;
    for (auto w : rings.ring(v)) {
      if (w == north || w == south || on_north_ring[w]) continue;
      if (best < 0 || lower(w, best)) best = w;
    }
    return best;
  };
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
      if (next < 0 || !lower(next, current)) stalled = true;
      else current = next;
    }
    if (!stalled) {
      planar.meridian = std::move(path);
      break;
    }
  }
  if (planar.meridian.empty()) {
    // Only with weights that can be negative (cotangent) can z have interior minima where every descent
    // stalls. A shortest path from ring to ring has no chord either (a chord would shorten it); the
    // certificate judges the map it leads to.
    planar.meridian_by_descent = false;
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
    if (reached < 0) throw std::logic_error("no path between the circumpolar rings");
    for (auto v = reached;; v = previous[v]) {
      planar.meridian.push_back(v);
      if (previous[v] == v) break;
    }
    std::reverse(planar.meridian.begin(), planar.meridian.end());
  }

  // φ: rings uniformly spaced, meridian at 0 (seen from the east) and 2π (from the west).
  detail::HarmonicProblem phi_problem{&rings, &weights, &work.positions, std::vector<char>(n, 0),
                                      std::vector<double>(rings.neighbors.size(), std::nan(""))};
  planar.phi.assign(n, 0.0);
  phi_problem.fixed[north] = phi_problem.fixed[south] = 1;
  const auto& meridian = planar.meridian;
  {
    const auto size = static_cast<std::int64_t>(north_ring.size());
    std::int64_t first = 0;
    while (north_ring[first] != meridian.front()) ++first;
    for (std::int64_t k = 0; k < size; ++k) {
      const auto v = north_ring[(first + k) % size];
      phi_problem.fixed[v] = 1;
      planar.phi[v] = 2 * kPi * static_cast<double>(k) / static_cast<double>(size);
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
      planar.phi[v] = k == 0 ? 0.0 : 2 * kPi * static_cast<double>(size - k) / static_cast<double>(size);
    }
  }
  for (std::size_t m = 0; m < meridian.size(); ++m) {
    const auto b = meridian[m];
    phi_problem.fixed[b] = 1;
    planar.phi[b] = 0;
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
            is_west_of(rings, b, up, down, i) ? 2 * kPi : 0.0;
      }
    }
  }
  planar.phi_stats = detail::solve_harmonic(phi_problem, planar.phi, options.solver, options.gauss_seidel_tolerance,
                                            options.gauss_seidel_max_sweeps);
  return planar;
}

Vec3 unit_from_angles(double theta, double phi) {
  return {std::sin(theta) * std::cos(phi), std::sin(theta) * std::sin(phi), std::cos(theta)};
}

// The sphere points of the first `count` working vertices (the input's), by the Mercator scaling.
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

// Per-vertex normalized area ratio of the map on the working mesh (used to re-weight against collapse).
std::vector<double> vertex_area_ratios(const WorkingMesh& work, const std::vector<Vec3>& sphere_all) {
  const auto n = static_cast<std::int64_t>(work.positions.size());
  std::vector<double> sphere_area(n, 0), surface_area(n, 0);
  double total_surface = 0;
  for (const auto& t : work.triangles) {
    const double a = triangle_area(work.positions[t[0]], work.positions[t[1]], work.positions[t[2]]);
    const double s = std::abs(signed_solid_angle(sphere_all[t[0]], sphere_all[t[1]], sphere_all[t[2]]));
    total_surface += a;
    for (auto v : t) surface_area[v] += a, sphere_area[v] += s;
  }
  std::vector<double> ratio(n, 1.0);
  for (std::int64_t v = 0; v < n; ++v) {
    if (surface_area[v] > 0) ratio[v] = (sphere_area[v] / (4 * kPi)) / (surface_area[v] / total_surface);
  }
  return ratio;
}

std::vector<Vec3> all_sphere_points(const PlanarCoordinates& planar, std::int32_t north, std::int32_t south,
                                    double c) {
  return to_sphere(planar, north, south, c, static_cast<std::int32_t>(planar.z.size()));
}

}  // namespace

SphereMap map_to_sphere(const Mesh& mesh, const MapOptions& options) {
  SphereMap result;
  StageTimer timer(result.timings);
  const auto n = static_cast<std::int32_t>(mesh.positions.size());
  if (n < 4) throw MeshRefused("the mesh has fewer than 4 vertices; a closed triangle mesh needs at least 4");

  WorkingMesh work{mesh.positions, mesh.triangles, build_vertex_rings(n, mesh.triangles)};
  if (options.poles) {
    const auto [a, b] = *options.poles;
    if (a < 0 || b < 0 || a >= n || b >= n || a == b)
      throw InputError(fmt::format("poles {},{} must be two different vertices in [0, {})", a, b, n));
    result.north = a;
    result.south = b;
    result.poles_from_options = true;
  } else {
    std::tie(result.north, result.south) = farthest_pair(mesh.positions);
  }
  const auto north = result.north, south = result.south;
  result.pole_graph_distance = graph_distances(work.rings, north)[south];
  if (result.poles_from_options && result.pole_graph_distance < 2)
    throw InputError(fmt::format("poles {},{} are joined by an edge, which cannot join two antipodal points; choose "
                                 "poles at least 2 edges apart (or leave --poles out)",
                                 north, south));
  timer.lap("poles");

  std::vector<Vec3> sphere;
  PlanarCoordinates planar;
  detail::EdgeWeights weights;
  if (result.pole_graph_distance < 4) {
    // Too few edges between the poles: below 3 the rings are not disjoint (tetrahedron, octahedron,
    // bipyramids); at 3 an edge can join the two rings and land on antipodal points. Map a midpoint
    // subdivision instead, whose original vertices keep their indices, and keep only those. The input's
    // triangles are then checked and repaired like any other map.
    result.method = "refined-poles-and-rings";
    Mesh refined = mesh;
    // Adjacent poles (every pair of a tetrahedron is an edge) would put an edge between antipodal
    // points: the inner south pole is then the refined vertex farthest from N (in edges, then in space)
    // that is not N nor an original neighbour of N.
    std::vector<char> excluded(n, 0);
    excluded[north] = 1;
    if (result.pole_graph_distance < 2)
      for (auto w : work.rings.ring(north)) excluded[w] = 1;
    std::int32_t inner_south = south;
    std::int32_t inner_distance = 0;
    do {
      refined = subdivide_midpoint(refined, 1);
      ++result.refinement_levels;
      const auto count = static_cast<std::int32_t>(refined.positions.size());
      const auto distance = graph_distances(build_vertex_rings(count, refined.triangles), north);
      if (result.pole_graph_distance < 2) {
        inner_south = -1;
        for (std::int32_t v = 0; v < count; ++v) {
          if (v < n && excluded[v]) continue;
          if (inner_south < 0 || distance[v] > distance[inner_south] ||
              (distance[v] == distance[inner_south] && squared_distance(refined.positions[v], refined.positions[north]) >
                                                           squared_distance(refined.positions[inner_south], refined.positions[north])))
            inner_south = v;
        }
      }
      inner_distance = distance[inner_south];
    } while (inner_distance < 4);
    MapOptions inner = options;
    inner.poles = std::make_pair(north, inner_south);
    const SphereMap refined_map = map_to_sphere(refined, inner);
    // Back to the inner map's pole-aligned frame: θ, φ and the superposition below are taken from there.
    const auto& r = refined_map.superposition.rotation;
    const std::array<double, 9> undo{r[0], r[3], r[6], r[1], r[4], r[7], r[2], r[5], r[8]};
    sphere.resize(n);
    for (std::int32_t v = 0; v < n; ++v) sphere[v] = rotate(undo, refined_map.sphere[v]);
    result.solver_used = refined_map.solver_used;
    result.theta0 = refined_map.theta0;
    result.mercator_c = refined_map.mercator_c;
    timer.lap("solve");
  } else {
    result.method = "poles-and-rings";
    split_dividing_edges(work, north, 'N', result.split_edges);
    split_dividing_edges(work, south, 'S', result.split_edges);
    if (!result.split_edges.empty())
      work.rings = build_vertex_rings(static_cast<std::int32_t>(work.positions.size()), work.triangles);
    result.north_ring_size = work.rings.degree(north);
    result.south_ring_size = work.rings.degree(south);
    result.theta0 = kPi / result.pole_graph_distance;
    result.ring_z = kRingZ;
    result.mercator_c = kRingZ / std::log((1 + std::cos(result.theta0)) / std::sin(result.theta0));
    weights = detail::compute_weights(work.rings, work.positions, options.weights);
    result.weight_fallback_rows = weights.fallback_rows;
    timer.lap("rings");
    planar = solve_planar(work, north, south, weights, options);
    result.solver_used = planar.z_stats.solver;
    result.gauss_seidel_sweeps = planar.z_stats.sweeps + planar.phi_stats.sweeps;
    result.gauss_seidel_converged = planar.z_stats.converged && planar.phi_stats.converged;
    sphere = to_sphere(planar, north, south, result.mercator_c, n);
    timer.lap("solve");
  }
  result.plain_certificate = certify_sphere_map(mesh, sphere, options.collapse_floor);
  timer.lap("certify-plain");

  if (options.repair && result.method == "poles-and-rings" && result.plain_certificate.collapsed > 0) {
    // Collapse: harmonic z and φ decay exponentially along limbs that lead to neither pole. Re-weighting
    // each edge by the area ratio at its far end (Yoshizawa, Belyaev & Seidel 2004, in (z, φ)) pulls
    // every vertex towards its less collapsed neighbours, which spreads the limb; the weights stay
    // positive, so the planar map stays one-to-one (Floater 2003).
    auto best_sphere = sphere;
    auto best_planar = planar;
    auto best_certificate = result.plain_certificate;
    int rounds_without_progress = 0;
    // Each vertex j gets a gain g_j and the weight of edge (i, j) becomes base_ij * g_j. Multiplying
    // row i by g_i gives the same solution with base_ij * g_i * g_j, which is symmetric whenever the base
    // weights are: the re-weighted systems stay on the Cholesky path.
    const detail::EdgeWeights base = weights;
    std::vector<double> gain(work.positions.size(), 1.0);
    for (int round = 1; round <= options.max_reweighting_rounds; ++round) {
      const auto ratio = vertex_area_ratios(work, all_sphere_points(planar, north, south, result.mercator_c));
      double log_mean = 0;
      for (std::size_t v = 0; v < gain.size(); ++v) {
        gain[v] *= std::clamp(std::pow(ratio[v], kReweightingExponent), 1 / kReweightingStep, kReweightingStep);
        log_mean += std::log(gain[v]) / static_cast<double>(gain.size());
      }
      // Only ratios of gains matter: keep them centred on 1 so that no weight over- or underflows.
      for (auto& g : gain) g /= std::exp(log_mean);
      for (std::int32_t v = 0; v < work.rings.vertex_count(); ++v) {
        const auto ring = work.rings.ring(v);
        for (std::size_t k = 0; k < ring.size(); ++k) {
          const auto slot = work.rings.offsets[v] + static_cast<std::int64_t>(k);
          weights.values[slot] = base.values[slot] * gain[ring[k]] * (base.symmetric ? gain[v] : 1.0);
        }
      }
      planar = solve_planar(work, north, south, weights, options);
      sphere = to_sphere(planar, north, south, result.mercator_c, n);
      const auto certificate = certify_sphere_map(mesh, sphere, options.collapse_floor);
      result.reweighting_rounds = round;
      const bool better = certificate.collapsed + certificate.folded < best_certificate.collapsed + best_certificate.folded ||
                          (certificate.collapsed + certificate.folded == best_certificate.collapsed + best_certificate.folded &&
                           certificate.min_area_ratio > best_certificate.min_area_ratio);
      if (better) {
        best_sphere = sphere;
        best_planar = planar;
        best_certificate = certificate;
        rounds_without_progress = 0;
      } else if (++rounds_without_progress >= kReweightingPatience) {
        break;
      }
      if (certificate.collapsed == 0) break;
    }
    sphere = std::move(best_sphere);
    planar = std::move(best_planar);
    result.solver_used = planar.z_stats.solver;
    timer.lap("reweight");
  }

  // Superposition first, so that the certificate is of the very numbers that are written.
  result.superposition = superpose_sphere_on_surface(mesh.positions, sphere);
  for (auto& p : sphere) p = rotate(result.superposition.rotation, p);
  timer.lap("superpose");

  auto certificate = certify_sphere_map(mesh, sphere, options.collapse_floor);
  // Local moves can remove folds and collapse but cannot change how often the image covers the sphere.
  if (options.repair && !certificate.certified() && std::abs(certificate.coverage - 1) < 1e-9) {
    result.untangling_moves =
        detail::untangle_on_sphere(mesh, work.rings.vertex_count() == n ? work.rings : build_vertex_rings(n, mesh.triangles),
                                   sphere, options.collapse_floor, options.max_untangling_sweeps);
    timer.lap("untangle");
    certificate = certify_sphere_map(mesh, sphere, options.collapse_floor);
  }
  result.certificate = std::move(certificate);
  timer.lap("certify");

  result.theta.resize(n);
  result.phi.resize(n);
  const auto& r = result.superposition.rotation;
  const std::array<double, 9> inverse{r[0], r[3], r[6], r[1], r[4], r[7], r[2], r[5], r[8]};
  for (std::int32_t v = 0; v < n; ++v) {
    const Vec3 u = rotate(inverse, sphere[v]);
    result.theta[v] = std::acos(std::clamp(u[2], -1.0, 1.0));
    double phi = std::atan2(u[1], u[0]);
    if (phi < 0) phi += 2 * kPi;
    if (phi >= 2 * kPi) phi = 0;  // -0 and tiny negatives round up to 2π
    result.phi[v] = phi;
  }
  if (result.method == "poles-and-rings") {
    result.meridian = planar.meridian;
    result.meridian_method = planar.meridian_by_descent ? "steepest-descent" : "shortest-path";
  }
  result.sphere = std::move(sphere);
  return result;
}

}  // namespace spheremap
