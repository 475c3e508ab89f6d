#include "spheremap/sphere/map.hpp"

#include <algorithm>
#include <chrono>
#include <cmath>
#include <memory>
#include <numbers>
#include <optional>
#include <stdexcept>
#include <unordered_set>

#include <fmt/format.h>

#include "harmonic.hpp"
#include "meridian.hpp"
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
// Re-weighting against collapse (reweight_against_collapse; the README's "The map" explains the choices).
// Each vertex whose normalized area ratio r (over its star) is below kReweightingTarget gets a step
// ln g += kReweightingExponent · ln(r / target), averaged twice over the 1-ring and at most
// kReweightingMaxStep per round; a round is kept only if it improves the map, else the step limit is
// quartered (patience kReweightingPatience). Measured on ../shared/data/meshes, the molecular surfaces of
// BENCHMARKS.md and generated cups: a full step (exponent 1) or equalizing every ratio towards 1 (the
// target 1) fold tens to thousands of triangles; exponent 0.75 with a 1e-2 target needs 1-5 rounds.
constexpr double kReweightingExponent = 0.75;
constexpr double kReweightingTarget = 1e-2;
constexpr int kReweightingSmoothing = 2;
constexpr double kReweightingMaxStep = 13.815510557964274;  // ln 1e6
constexpr int kReweightingPatience = 3;
// Requiring the smallest ratio never to drop stalled GroEL at 0.5 Å: 1,081 bad triangles at a smallest
// ratio 3.9e-8, then a round with 270 at 2.1e-8 was refused and the step limit shrank to 1e-3 in ten
// rejected rounds; with this allowance that round is kept and untangling certifies it (957 moves).
constexpr double kReweightingDip = 4;
// With at most this many folded and collapsed triangles, untangling is tried before another round.
constexpr std::int64_t kUntanglingAttempt = 100;
// Equalizing after certification: the rounds above stop as soon as nothing is collapsed, which leaves
// limbs small on the sphere. Further rounds move every vertex's gain by r^kEqualizingExponent (at most
// kEqualizingStep-fold per round, both ways) and are kept only if the map stays certified without
// untangling and its mean area distortion drops. Measured on ../shared/data/meshes: the earlier
// two-sided re-weighting with these constants gave 47-61% area distortion on the limb meshes.
constexpr double kEqualizingExponent = 0.25;
constexpr double kEqualizingStep = 4.0;
constexpr int kEqualizingPatience = 2;
// Equalizing stops once a kept round lowers the mean area distortion by less than this fraction: the
// first rounds give most of the gain (ajc_horse: 1.83, 1.04, 0.90, 0.59, 0.50), later ones cost a
// factorization each for a few percent.
constexpr double kEqualizingMinGain = 0.02;
constexpr int kEqualizingMinRounds = 3;  // before that, a small gain may precede large ones (ajc_beast)

// Fill-reducing orders (harmonic.hpp). The geometric nested dissection is nearly free and the best on
// smooth, convex-ish shapes (a subdivided cube), but a plane cuts a molecular surface along long curves.
// Judged by fl / n^1.5 of its factor (a good nested dissection of a surface mesh needs O(n^1.5) flops):
// measured 27-44 on most of ../shared/data/meshes and 35 on the cube, 57-96 on bumpy and many-limbed
// ones, 40-96 on molecular surfaces. CHOLMOD's AMD costs about as little to compute (0.05 s at 78k
// vertices) and gives 2-12x fewer flops than the geometric order wherever that ratio exceeds 38 (on the
// cube 1.7x more; METIS's nested dissection, 5-10x dearer to compute, saved no time over AMD on any
// molecular surface measured: BENCHMARKS.md). So where the ratio exceeds kTryAmd on a mesh of
// kTryAmdVertices or more, AMD's order is analysed too and the one with fewer flops serves every
// factorization of the map; below that size a factorization takes milliseconds in any order.
constexpr double kTryAmd = 38;
constexpr std::size_t kTryAmdVertices = 5000;

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
  int meridian_round = 0;  // the round whose z the meridian was found for (0: the plain map)
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

// z, the meridian and φ. The re-weighting rounds pass `factor` (analysed once, with the meridian
// interior ordered last) and the meridian of the best round so far, which is kept while z still
// strictly decreases along it: then z and φ come from one numeric factorization (ReusableCholesky).
PlanarCoordinates solve_planar(const WorkingMesh& work, std::int32_t north, std::int32_t south,
                               const detail::EdgeWeights& weights, const MapOptions& options,
                               detail::ReusableCholesky* factor = nullptr, const PlanarCoordinates* kept = nullptr,
                               int round = 0) {
  const auto& rings = work.rings;
  const auto n = rings.vertex_count();
  const auto north_ring = rings.ring(north);
  const auto south_ring = rings.ring(south);

  PlanarCoordinates planar;
  // z: harmonic between the rings.
  detail::HarmonicProblem z_problem{&rings, &weights, &work.positions, std::vector<char>(n, 0), {}};
  planar.z.assign(n, 0.0);
  z_problem.fixed[north] = z_problem.fixed[south] = 1;
  planar.z[north] = kRingZ;
  planar.z[south] = -kRingZ;
  for (auto v : north_ring) z_problem.fixed[v] = 1, planar.z[v] = kRingZ;
  for (auto v : south_ring) z_problem.fixed[v] = 1, planar.z[v] = -kRingZ;
  const bool factorized = factor && factor->factorize(z_problem);
  if (factorized) {
    factor->solve(z_problem, planar.z);
    planar.z_stats = {"cholmod-llt", 0, true};
  } else {
    planar.z_stats = detail::solve_harmonic(z_problem, planar.z, options.solver, options.gauss_seidel_tolerance,
                                            options.gauss_seidel_max_sweeps);
  }

  // Boundary meridian (meridian.hpp): the best round's if z still strictly decreases along it.
  auto found = detail::boundary_meridian(rings, planar.z, north, south, kept ? &kept->meridian : nullptr);
  planar.meridian = std::move(found.path);
  planar.meridian_by_descent = found.kept ? kept->meridian_by_descent : found.by_descent;
  planar.meridian_round = found.kept ? kept->meridian_round : round;

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
  const std::vector<std::int32_t> meridian_interior(meridian.begin() + 1, meridian.end() - 1);
  if (factorized && factor->last() == meridian_interior) {
    factor->solve(phi_problem, planar.phi, true);
    planar.phi_stats = {"cholmod-llt", 0, true};
  } else if (factor && factor->factorize(phi_problem)) {
    factor->solve(phi_problem, planar.phi);
    planar.phi_stats = {"cholmod-llt", 0, true};
  } else {
    planar.phi_stats = detail::solve_harmonic(phi_problem, planar.phi, options.solver, options.gauss_seidel_tolerance,
                                              options.gauss_seidel_max_sweeps);
  }
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

// Triangle areas of a mesh, which every round's area ratios divide by: computed once per map.
struct TriangleAreas {
  std::vector<double> area;
  double total = 0;  // summed in triangle order
};

TriangleAreas triangle_areas(const std::vector<Vec3>& positions, const std::vector<Triangle>& triangles) {
  TriangleAreas areas;
  areas.area.reserve(triangles.size());
  for (const auto& t : triangles) {
    areas.area.push_back(triangle_area(positions[t[0]], positions[t[1]], positions[t[2]]));
    areas.total += areas.area.back();
  }
  return areas;
}

// Per-vertex normalized area ratio of the map on the working mesh (used to re-weight against collapse),
// from the signed solid angles of its triangles.
std::vector<double> vertex_area_ratios(const WorkingMesh& work, const TriangleAreas& areas, const std::vector<double>& solid_angles) {
  const auto n = static_cast<std::int64_t>(work.positions.size());
  std::vector<double> sphere_area(n, 0), surface_area(n, 0);
  for (std::size_t k = 0; k < work.triangles.size(); ++k) {
    const double a = areas.area[k], s = std::abs(solid_angles[k]);
    for (auto v : work.triangles[k]) surface_area[v] += a, sphere_area[v] += s;
  }
  std::vector<double> ratio(n, 1.0);
  for (std::int64_t v = 0; v < n; ++v) {
    if (surface_area[v] > 0) ratio[v] = (sphere_area[v] / (4 * kPi)) / (surface_area[v] / areas.total);
  }
  return ratio;
}

std::vector<Vec3> all_sphere_points(const PlanarCoordinates& planar, std::int32_t north, std::int32_t south,
                                    double c) {
  return to_sphere(planar, north, south, c, static_cast<std::int32_t>(planar.z.size()));
}

// Mean over the input's triangles of |r - 1|, r = (solid angle / 4π) / (area / total area): the
// report's area distortion (metrics), computed here to judge equalizing rounds.
double mean_area_distortion(const TriangleAreas& areas, const std::vector<double>& solid_angles) {
  if (!(areas.total > 0) || areas.area.empty()) return 0;
  double sum = 0;
  for (std::size_t k = 0; k < areas.area.size(); ++k) {
    const double share = areas.area[k] / areas.total;
    const double solid = std::abs(solid_angles[k]) / (4 * kPi);
    sum += share > 0 ? std::abs(solid / share - 1) : 0;
  }
  return sum / static_cast<double>(areas.area.size());
}

struct Candidate {
  PlanarCoordinates planar;
  std::vector<Vec3> sphere;  // of the input's vertices, before the superposition
  Certificate certificate;
  std::vector<double> solid_angles;  // of the input's triangles on `sphere`, from the certificate
};

// The last steps of every map: superposition (first, so that the certificate is of the very numbers
// that are written), certificate, and untangling on the sphere when the map is not certified but covers
// the sphere once (local moves can remove folds and collapse, not change how often the image covers it).
struct Finished {
  std::vector<Vec3> sphere;
  Superposition superposition;
  Certificate certificate;
  std::vector<double> solid_angles;  // of the input's triangles on `sphere`, from the certificate
  std::int64_t untangling_moves = 0;
  bool untangled = false;  // untangling ran
};

// The input's rings (the untangling works on the input's triangles, not the split working mesh), and what
// the untangling needs of the input, built at its first call and shared by the others (5hr7's default map
// untangles 10 candidates, one per equalizing round; building it took 9 ms of each call's 15).
class InputStars {
 public:
  explicit InputStars(const Mesh& mesh, const VertexRings& rings) : mesh_(mesh), rings_(rings) {}
  [[nodiscard]] const VertexRings& rings() const { return rings_; }
  const detail::UntanglingFrame& untangling_frame() {
    if (!frame_) frame_ = detail::untangling_frame(mesh_, rings_);
    return *frame_;
  }

 private:
  const Mesh& mesh_;
  const VertexRings& rings_;
  std::optional<detail::UntanglingFrame> frame_;
};

Finished finish_map(const Mesh& mesh, InputStars& input, std::vector<Vec3> sphere, const MapOptions& options,
                    StageTimer* timer = nullptr) {
  Finished finished;
  finished.superposition = superpose_sphere_on_surface(mesh.positions, sphere);
  for (auto& p : sphere) p = rotate(finished.superposition.rotation, p);
  if (timer) timer->lap("superpose");
  finished.certificate = certify_sphere_map(mesh, sphere, options.collapse_floor, &finished.solid_angles);
  if (options.repair && !finished.certificate.certified() && std::abs(finished.certificate.coverage - 1) < 1e-9) {
    finished.untangling_moves =
        detail::untangle_on_sphere(mesh, input.rings(), input.untangling_frame(), sphere, options.collapse_floor,
                                   options.max_untangling_sweeps);
    finished.untangled = true;
    if (timer) timer->lap("untangle");
    finished.certificate = certify_sphere_map(mesh, sphere, options.collapse_floor, &finished.solid_angles);
  }
  if (timer) timer->lap("certify");
  finished.sphere = std::move(sphere);
  return finished;
}

struct ReweightingOutcome {
  Candidate best;
  int rounds = 0;
  int equalizing_rounds = 0;  // of `rounds`, those kept by the equalizing phase
  std::optional<Finished> finished;  // the best round finished (superposed, untangled, certified), if tried
};

// The fill-reducing order for the Cholesky factorizations of one map: AMD's when it needs fewer flops,
// else the geometric one (computed afresh for each analysis: it is nearly free).
struct OrderChoice {
  std::vector<char> always_fixed;                  // poles and rings: fixed in every system of the map
  std::optional<detail::EliminationOrder> chosen;  // when not the geometric order
};

std::unique_ptr<detail::ReusableCholesky> make_factor(const WorkingMesh& work, const OrderChoice& order,
                                                      const std::vector<std::int32_t>& last = {}) {
  if (order.chosen) return std::make_unique<detail::ReusableCholesky>(work.rings, *order.chosen, last);
  return std::make_unique<detail::ReusableCholesky>(work.rings, work.positions, order.always_fixed, last);
}

// Collapse: harmonic z and φ decay exponentially along pockets and limbs that lead to neither pole, so
// their triangles keep 1e-9 to 1e-22 of their share of the sphere. Each vertex j gets a gain g_j and
// edge (i, j) weighs base_ij · g_i · g_j (symmetric base weights: the Cholesky path; otherwise
// base_ij · g_j, the same solution up to row scaling): lowering the gains of a collapsed region lowers its
// conductance, which spreads the harmonic functions into it. All weights stay positive and z and φ share
// them, so the planar map stays one-to-one (Floater 2003).
ReweightingOutcome reweight_against_collapse(const Mesh& mesh, const WorkingMesh& work, std::int32_t north,
                                             std::int32_t south, double mercator_c,
                                             const detail::EdgeWeights& base, const MapOptions& options,
                                             InputStars& input, Candidate plain, OrderChoice& order) {
  const auto n = static_cast<std::int32_t>(mesh.positions.size());
  const auto count = work.rings.vertex_count();
  ReweightingOutcome outcome{std::move(plain), 0, 0, std::nullopt};
  // The sparsity pattern is the same in every round: one ordering and symbolic analysis (again only
  // if the kept meridian changes), one numeric factorization per round for both z and φ.
  const bool reuse = options.solver == Solver::kDirect && base.symmetric;
  std::unique_ptr<detail::ReusableCholesky> factor;

  std::vector<double> log_gain(count, 0.0), proposal(count), signal(count), smoothed(count);
  // Areas are the same every round; without split edges the working mesh is the input, and a candidate's
  // solid angles (its certificate's) serve its area ratios and distortion too.
  const TriangleAreas input_areas = triangle_areas(mesh.positions, mesh.triangles);
  const bool split = work.triangles.size() != mesh.triangles.size();
  const TriangleAreas work_areas = split ? triangle_areas(work.positions, work.triangles) : TriangleAreas{};
  auto ratios_of = [&](const Candidate& candidate) {
    if (!split) return vertex_area_ratios(work, input_areas, candidate.solid_angles);
    const auto sphere_all = all_sphere_points(candidate.planar, north, south, mercator_c);
    std::vector<double> solid_angles(work.triangles.size());
    for (std::size_t k = 0; k < work.triangles.size(); ++k) {
      const auto& t = work.triangles[k];
      solid_angles[k] = signed_solid_angle(sphere_all[t[0]], sphere_all[t[1]], sphere_all[t[2]]);
    }
    return vertex_area_ratios(work, work_areas, solid_angles);
  };
  auto ratio = ratios_of(outcome.best);
  double max_step = kReweightingMaxStep;
  int rejections = 0;
  detail::EdgeWeights weights = base;
  // The map with edge weights base_ij · g_i · g_j, g = exp(proposal), from the reused factorization
  // (analysed again only when the best round's meridian changed).
  std::vector<double> gain(count);
  auto solve_with_gains = [&](int round) {
    for (std::int32_t v = 0; v < count; ++v) gain[v] = std::exp(proposal[v]);
    for (std::int32_t v = 0; v < count; ++v) {
      const auto ring = work.rings.ring(v);
      for (std::size_t k = 0; k < ring.size(); ++k) {
        const auto slot = work.rings.offsets[v] + static_cast<std::int64_t>(k);
        // g_v · g_w is the same product seen from either end: the weights stay exactly symmetric.
        weights.values[slot] = base.values[slot] * (base.symmetric ? gain[v] * gain[ring[k]] : gain[ring[k]]);
      }
    }
    if (reuse) {
      const auto& meridian = outcome.best.planar.meridian;
      const std::vector<std::int32_t> interior(meridian.begin() + 1, meridian.end() - 1);
      if (!factor || factor->last() != interior) factor = make_factor(work, order, interior);
    }
    Candidate candidate;
    candidate.planar = solve_planar(work, north, south, weights, options, factor.get(), &outcome.best.planar, round);
    candidate.sphere = to_sphere(candidate.planar, north, south, mercator_c, n);
    candidate.certificate = certify_sphere_map(mesh, candidate.sphere, options.collapse_floor, &candidate.solid_angles);
    return candidate;
  };
  for (int round = 1; round <= options.max_reweighting_rounds; ++round) {
    // Only vertices below the target move (one-sided: the rest of the map stays the paper's, and no
    // noise from ratios around 1 accumulates in the gains); the 1-ring averages keep neighbouring gains
    // close, so that the systems stay well scaled and a single vertex cannot run away.
    for (std::int32_t v = 0; v < count; ++v)
      signal[v] = std::min(0.0, std::log(std::max(ratio[v], 1e-300) / kReweightingTarget));
    for (int pass = 0; pass < kReweightingSmoothing; ++pass) {
      for (std::int32_t v = 0; v < count; ++v) {
        double sum = signal[v];
        for (auto w : work.rings.ring(v)) sum += signal[w];
        smoothed[v] = sum / (1 + work.rings.degree(v));
      }
      signal.swap(smoothed);
    }
    double top = -INFINITY, largest_step = 0;
    for (std::int32_t v = 0; v < count; ++v) {
      const double step = std::max(kReweightingExponent * signal[v], -max_step);
      largest_step = std::max(largest_step, -step);
      proposal[v] = log_gain[v] + step;
      top = std::max(top, proposal[v]);
    }
    if (largest_step == 0) break;  // every vertex is above the target: what is left is for untangling
    // Only ratios of gains matter: the largest is 1, and none below e^-300 keeps every weight positive.
    for (auto& g : proposal) g = std::max(g - top, -300.0);
    Candidate candidate = solve_with_gains(round);
    outcome.rounds = round;
    // Kept if it has fewer bad triangles and its smallest area ratio is at most kReweightingDip times
    // lower, or as many bad triangles and a larger smallest ratio: a round that trades fewer bad
    // triangles for a much deeper collapse elsewhere is an overshoot.
    const auto& c = candidate.certificate;
    const auto& b = outcome.best.certificate;
    const auto bad = c.collapsed + c.folded, best_bad = b.collapsed + b.folded;
    const bool accepted = (bad < best_bad && c.min_area_ratio >= b.min_area_ratio / kReweightingDip) ||
                          (bad <= best_bad && c.min_area_ratio > b.min_area_ratio);
    if (!accepted) {
      max_step /= 4;
      if (++rejections >= kReweightingPatience) break;
      continue;
    }
    log_gain = proposal;
    outcome.best = std::move(candidate);
    outcome.finished.reset();
    ratio = ratios_of(outcome.best);
    max_step = std::min(2 * max_step, kReweightingMaxStep);
    rejections = 0;
    // Few bad triangles left: untangling may certify this round, far more cheaply than another round.
    if (bad <= kUntanglingAttempt) {
      outcome.finished = finish_map(mesh, input, outcome.best.sphere, options);
      if (outcome.finished->certificate.certified()) break;
    }
  }

  // Rounds that stop with bad triangles left (patience, or too many for the attempt above) leave them to
  // untangling, which map_to_sphere would try anyway; trying it here lets a certified result be equalized.
  if (!outcome.best.certificate.certified() && !outcome.finished)
    outcome.finished = finish_map(mesh, input, outcome.best.sphere, options);

  // Equalizing, once the best round is certified (by itself or after untangling).
  const bool certified_by_itself = outcome.best.certificate.certified();
  const bool certified_untangled = outcome.finished && outcome.finished->certificate.certified();
  if (!(certified_by_itself || certified_untangled) || options.max_equalizing_rounds <= 0) return outcome;
  double distortion = mean_area_distortion(input_areas, certified_by_itself ? outcome.best.solid_angles : outcome.finished->solid_angles);
  rejections = 0;
  double step_limit = kEqualizingStep;
  auto vertex_ratio = ratios_of(outcome.best);
  for (int round = 1; round <= options.max_equalizing_rounds; ++round) {
    double mean_log = 0;
    for (std::int32_t v = 0; v < count; ++v) {
      const double factor = std::clamp(std::pow(std::max(vertex_ratio[v], 1e-300), kEqualizingExponent), 1 / step_limit, step_limit);
      proposal[v] = log_gain[v] + std::log(factor);
      mean_log += proposal[v] / count;
    }
    for (auto& g : proposal) g = std::clamp(g - mean_log, -300.0, 300.0);
    Candidate candidate = solve_with_gains(outcome.rounds + 1);
    // An equalizing round can fold a few chords on the sphere while the planar map stays one-to-one
    // (measured: 15-650 on the limb meshes), and push a few triangles that untangling left just above
    // the collapse floor below it (GroEL at 0.5 Å: 201 and 237 of 1.1M, so no round was kept and its
    // area distortion stayed at 186%; with them untangled, 5 rounds and 134%): such a round is judged
    // by its untangled map.
    double candidate_distortion = INFINITY;
    std::optional<Finished> untangled;
    const auto& cc = candidate.certificate;
    if (cc.certified()) {
      candidate_distortion = mean_area_distortion(input_areas, candidate.solid_angles);
    } else if (std::abs(cc.coverage - 1) < 1e-9 &&
               cc.folded + cc.collapsed <= std::max<std::int64_t>(kUntanglingAttempt, static_cast<std::int64_t>(mesh.triangles.size()) / 100)) {
      untangled = finish_map(mesh, input, candidate.sphere, options);
      if (untangled->certificate.certified()) candidate_distortion = mean_area_distortion(input_areas, untangled->solid_angles);
    }
    if (!(candidate_distortion < distortion)) {
      step_limit = std::sqrt(step_limit);
      if (++rejections >= kEqualizingPatience) break;
      continue;
    }
    ++outcome.rounds;
    ++outcome.equalizing_rounds;
    log_gain = proposal;
    const bool small_gain = candidate_distortion > (1 - kEqualizingMinGain) * distortion;
    distortion = candidate_distortion;
    outcome.best = std::move(candidate);
    outcome.finished = std::move(untangled);
    rejections = 0;
    step_limit = kEqualizingStep;
    if (small_gain && outcome.equalizing_rounds >= kEqualizingMinRounds) break;
    vertex_ratio = ratios_of(outcome.best);
  }
  return outcome;
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
  OrderChoice order;
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
    order.always_fixed.assign(work.positions.size(), 0);
    order.always_fixed[north] = order.always_fixed[south] = 1;
    for (auto v : work.rings.ring(north)) order.always_fixed[v] = 1;
    for (auto v : work.rings.ring(south)) order.always_fixed[v] = 1;
    timer.lap("rings");
    // z and φ of the plain map from one analysis (φ's meridian as decoupled rows).
    std::unique_ptr<detail::ReusableCholesky> plain_factor;
    if (options.solver == Solver::kDirect && weights.symmetric) {
      plain_factor = make_factor(work, order);
      const double vertices = static_cast<double>(work.positions.size());
      if (plain_factor->flops() > kTryAmd * vertices * std::sqrt(vertices) && work.positions.size() >= kTryAmdVertices) {
        auto amd = detail::amd_elimination_order(work.rings, work.positions, order.always_fixed);
        auto amd_factor = std::make_unique<detail::ReusableCholesky>(work.rings, amd);
        if (amd_factor->flops() < plain_factor->flops()) order.chosen = std::move(amd), plain_factor = std::move(amd_factor);
      }
      // Re-weighting factorizes in the same order (its systems have the same unknowns).
      result.elimination_order = order.chosen ? order.chosen->method : "geometric";
    }
    planar = solve_planar(work, north, south, weights, options, plain_factor.get());
    plain_factor.reset();
    result.solver_used = planar.z_stats.solver;
    result.gauss_seidel_sweeps = planar.z_stats.sweeps + planar.phi_stats.sweeps;
    result.gauss_seidel_converged = planar.z_stats.converged && planar.phi_stats.converged;
    sphere = to_sphere(planar, north, south, result.mercator_c, n);
    timer.lap("solve");
  }
  std::vector<double> plain_solid_angles;
  result.plain_certificate = certify_sphere_map(mesh, sphere, options.collapse_floor, &plain_solid_angles);
  timer.lap("certify-plain");

  std::optional<VertexRings> unsplit_rings;
  InputStars input(mesh, work.rings.vertex_count() == n ? work.rings : unsplit_rings.emplace(build_vertex_rings(n, mesh.triangles)));
  std::optional<Finished> finished;
  if (options.repair && result.method == "poles-and-rings" && result.plain_certificate.collapsed > 0) {
    auto outcome = reweight_against_collapse(mesh, work, north, south, result.mercator_c, weights, options, input,
                                             Candidate{planar, sphere, result.plain_certificate, std::move(plain_solid_angles)}, order);
    planar = std::move(outcome.best.planar);
    sphere = std::move(outcome.best.sphere);
    finished = std::move(outcome.finished);
    result.reweighting_rounds = outcome.rounds;
    result.equalizing_rounds = outcome.equalizing_rounds;
    result.solver_used = planar.z_stats.solver;
    timer.lap("reweight");
  }
  if (!finished) finished = finish_map(mesh, input, std::move(sphere), options, &timer);
  result.superposition = finished->superposition;
  result.untangling_moves = finished->untangling_moves;
  result.certificate = std::move(finished->certificate);
  sphere = std::move(finished->sphere);

  result.theta.resize(n);
  result.phi.resize(n);
  const auto& r = result.superposition.rotation;
  const std::array<double, 9> inverse{r[0], r[3], r[6], r[1], r[4], r[7], r[2], r[5], r[8]};
  for (std::int32_t v = 0; v < n; ++v) {
    const Vec3 u = rotate(inverse, sphere[v]);
    // atan2, not acos(u_z): rotating back rounds a pole's z to 1 - 2^-53 at worst, where acos is
    // 2e-8 away from 0; atan2 keeps full precision near the poles.
    result.theta[v] = std::atan2(std::hypot(u[0], u[1]), u[2]);
    double phi = std::atan2(u[1], u[0]);
    if (phi < 0) phi += 2 * kPi;
    if (phi >= 2 * kPi) phi = 0;  // -0 and tiny negatives round up to 2π
    result.phi[v] = phi;
  }
  if (result.method == "poles-and-rings") {
    result.meridian = planar.meridian;
    result.meridian_method = planar.meridian_by_descent ? "steepest-descent" : "shortest-path";
    result.meridian_round = planar.meridian_round;
  }
  result.sphere = std::move(sphere);
  return result;
}

}  // namespace spheremap
