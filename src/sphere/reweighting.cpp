#include "reweighting.hpp"

#include <algorithm>
#include <cmath>
#include <memory>
#include <numbers>
#include <utility>

#include "spheremap/geometry/vec.hpp"

namespace spheremap::detail {
namespace {

// Re-weighting against collapse (docs/algorithm.md, "Collapse: re-weighting", explains the choices). Each vertex whose
// normalized area ratio r (over its star) is below kReweightingTarget gets a step
// ln g += kReweightingExponent · ln(r / target), averaged twice over the 1-ring and at most
// kReweightingMaxStep per round; a round is kept only if it improves the map, else the step limit is
// quartered (patience kReweightingPatience). A full step (exponent 1), or equalizing every ratio towards
// 1 (the target 1), folds tens to thousands of triangles; these values need a few rounds.
constexpr double kReweightingExponent = 0.75;
constexpr double kReweightingTarget = 1e-2;
constexpr int kReweightingSmoothing = 2;
constexpr double kReweightingMaxStep = 13.815510557964274;  // ln 1e6
constexpr int kReweightingPatience = 3;
// A round may lower the smallest ratio this many times if it leaves fewer bad triangles: requiring it
// never to drop can stall on large surfaces (every round refused, the step limit shrinking to nothing),
// while untangling certifies the round that was refused.
constexpr double kReweightingDip = 4;
// With at most this many folded and collapsed triangles, untangling is tried before another round.
constexpr std::int64_t kUntanglingAttempt = 100;
// Equalizing after certification: the rounds above stop as soon as nothing is collapsed, which leaves
// limbs small on the sphere. Further rounds move every vertex's gain by r^kEqualizingExponent (at most
// kEqualizingStep-fold per round, both ways) and are kept only if the map stays certified without
// untangling and its mean area distortion drops.
constexpr double kEqualizingExponent = 0.25;
constexpr double kEqualizingStep = 4.0;
constexpr int kEqualizingPatience = 2;
// Equalizing stops once a kept round lowers the mean area distortion by less than this fraction: the
// first rounds give most of the gain, later ones cost a factorization each for a few percent.
constexpr double kEqualizingMinGain = 0.02;
constexpr int kEqualizingMinRounds = 3;  // before that, a small gain may precede large ones

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
std::vector<double> vertex_area_ratios(const WorkingMesh& work, const TriangleAreas& areas,
                                       const std::vector<double>& solid_angles) {
  const auto n = static_cast<std::int64_t>(work.positions.size());
  std::vector<double> sphere_area(n, 0), surface_area(n, 0);
  for (std::size_t k = 0; k < work.triangles.size(); ++k) {
    const double a = areas.area[k], s = std::abs(solid_angles[k]);
    for (auto v : work.triangles[k]) surface_area[v] += a, sphere_area[v] += s;
  }
  std::vector<double> ratio(n, 1.0);
  for (std::int64_t v = 0; v < n; ++v) {
    if (surface_area[v] > 0) ratio[v] = (sphere_area[v] / (4 * std::numbers::pi)) / (surface_area[v] / areas.total);
  }
  return ratio;
}

std::vector<Vec3> all_sphere_points(const PlanarCoordinates& planar, std::int32_t north, std::int32_t south, double c) {
  return to_sphere(planar, north, south, c, static_cast<std::int32_t>(planar.z.size()));
}

// Mean over the input's triangles of |r - 1|, r = (solid angle / 4π) / (area / total area): the
// report's area distortion (metrics), computed here to judge equalizing rounds.
double mean_area_distortion(const TriangleAreas& areas, const std::vector<double>& solid_angles) {
  if (!(areas.total > 0) || areas.area.empty()) return 0;
  double sum = 0;
  for (std::size_t k = 0; k < areas.area.size(); ++k) {
    const double share = areas.area[k] / areas.total;
    const double solid = std::abs(solid_angles[k]) / (4 * std::numbers::pi);
    sum += share > 0 ? std::abs(solid / share - 1) : 0;
  }
  return sum / static_cast<double>(areas.area.size());
}

// The maps of the working mesh with edge weights base_ij · g_i · g_j (symmetric base weights; otherwise
// base_ij · g_j), g = exp(log gain), from one reused factorization (analysed again only when the kept
// meridian changes): the sparsity pattern is the same in every round.
class GainedMaps {
 public:
  GainedMaps(const Mesh& mesh, const WorkingMesh& work, std::int32_t north, std::int32_t south, double mercator_c,
             const EdgeWeights& base, const MapOptions& options, OrderChoice& order)
      : mesh_(mesh),
        work_(work),
        north_(north),
        south_(south),
        mercator_c_(mercator_c),
        base_(base),
        options_(options),
        order_(order),
        reuse_(options.solver == Solver::kDirect && base.symmetric),
        weights_(base),
        gain_(static_cast<std::size_t>(work.rings.vertex_count())),
        input_areas_(triangle_areas(mesh.positions, mesh.triangles)),
        split_(work.triangles.size() != mesh.triangles.size()),
        work_areas_(split_ ? triangle_areas(work.positions, work.triangles) : TriangleAreas{}) {}

  // The map for `log_gain`; `best` is the best map so far, whose meridian is kept while it serves. None
  // when the sparse LU finds the system singular (gains and extreme geometry together): the caller
  // rejects that round like any other that does no better.
  std::optional<Candidate> solve(const std::vector<double>& log_gain, const PlanarCoordinates& best, int round) {
    const auto count = work_.rings.vertex_count();
    for (std::int32_t v = 0; v < count; ++v) gain_[v] = std::exp(log_gain[v]);
    for (std::int32_t v = 0; v < count; ++v) {
      const auto ring = work_.rings.ring(v);
      for (std::size_t k = 0; k < ring.size(); ++k) {
        const auto slot = work_.rings.offsets[v] + static_cast<std::int64_t>(k);
        // g_v · g_w is the same product seen from either end: the weights stay exactly symmetric.
        weights_.values[slot] = base_.values[slot] * (base_.symmetric ? gain_[v] * gain_[ring[k]] : gain_[ring[k]]);
      }
    }
    if (reuse_) {
      const std::vector<std::int32_t> interior(best.meridian.begin() + 1, best.meridian.end() - 1);
      if (!factor_ || factor_->last() != interior) factor_ = make_factor(work_, order_, interior);
    }
    Candidate candidate;
    try {
      candidate.planar = solve_planar(work_, north_, south_, weights_, options_, factor_.get(), &best, round);
    } catch (const SingularSystem&) {
      return std::nullopt;
    }
    const auto input_vertices = static_cast<std::int32_t>(mesh_.positions.size());
    candidate.sphere = to_sphere(candidate.planar, north_, south_, mercator_c_, input_vertices);
    candidate.certificate =
        certify_sphere_map(mesh_, candidate.sphere, options_.collapse_floor, &candidate.solid_angles);
    return candidate;
  }

  // Per-vertex area ratios of a candidate on the working mesh. Without split edges the working mesh is
  // the input, and the candidate's solid angles (its certificate's) serve.
  [[nodiscard]] std::vector<double> ratios_of(const Candidate& candidate) const {
    if (!split_) return vertex_area_ratios(work_, input_areas_, candidate.solid_angles);
    const auto sphere_all = all_sphere_points(candidate.planar, north_, south_, mercator_c_);
    std::vector<double> solid_angles(work_.triangles.size());
    for (std::size_t k = 0; k < work_.triangles.size(); ++k) {
      const auto& t = work_.triangles[k];
      solid_angles[k] = signed_solid_angle(sphere_all[t[0]], sphere_all[t[1]], sphere_all[t[2]]);
    }
    return vertex_area_ratios(work_, work_areas_, solid_angles);
  }

  // Areas of the input's triangles, the same every round.
  [[nodiscard]] const TriangleAreas& input_areas() const { return input_areas_; }

 private:
  const Mesh& mesh_;
  const WorkingMesh& work_;
  std::int32_t north_, south_;
  double mercator_c_;
  const EdgeWeights& base_;
  const MapOptions& options_;
  OrderChoice& order_;
  bool reuse_;
  std::unique_ptr<ReusableCholesky> factor_;
  EdgeWeights weights_;
  std::vector<double> gain_;
  TriangleAreas input_areas_;
  bool split_;
  TriangleAreas work_areas_;
};

// Whether a re-weighting round's map `c` is kept over the best so far, `b`: fewer bad triangles and a
// smallest area ratio at most kReweightingDip times lower, or as many bad triangles and a larger smallest
// ratio (a round that trades fewer bad triangles for a much deeper collapse elsewhere is an overshoot).
bool round_improves(const Certificate& c, const Certificate& b) {
  const auto bad = c.collapsed + c.folded, best_bad = b.collapsed + b.folded;
  return (bad < best_bad && c.min_area_ratio >= b.min_area_ratio / kReweightingDip) ||
         (bad <= best_bad && c.min_area_ratio > b.min_area_ratio);
}

// The re-weighting rounds, from the plain map in `outcome` and log_gain = 0: until the best round is
// certified after untangling, no vertex is below the target, or patience runs out.
void reweight_rounds(GainedMaps& maps, const Mesh& mesh, const WorkingMesh& work, const MapOptions& options,
                     InputStars& input, ReweightingOutcome& outcome, std::vector<double>& log_gain) {
  const auto count = work.rings.vertex_count();
  std::vector<double> proposal(count), signal(count), smoothed(count);
  auto ratio = maps.ratios_of(outcome.best);
  double max_step = kReweightingMaxStep;
  int rejections = 0;
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
    std::optional<Candidate> solved = maps.solve(proposal, outcome.best.planar, round);
    outcome.rounds = round;
    if (!solved) ++outcome.singular_systems;
    if (!solved || !round_improves(solved->certificate, outcome.best.certificate)) {
      max_step /= 4;
      if (++rejections >= kReweightingPatience) break;
      continue;
    }
    log_gain = proposal;
    outcome.best = std::move(*solved);
    outcome.finished.reset();
    ratio = maps.ratios_of(outcome.best);
    max_step = std::min(2 * max_step, kReweightingMaxStep);
    rejections = 0;
    // Few bad triangles left: untangling may certify this round, far more cheaply than another round.
    if (outcome.best.certificate.collapsed + outcome.best.certificate.folded <= kUntanglingAttempt) {
      outcome.finished = finish_map(mesh, input, outcome.best.sphere, options);
      if (outcome.finished->certificate.certified()) break;
    }
  }
}

// The equalizing rounds, once the best round is certified (by itself or after untangling): each kept
// only if the map stays certified (untangled if need be) and its mean area distortion drops.
void equalizing_rounds(GainedMaps& maps, const Mesh& mesh, const WorkingMesh& work, const MapOptions& options,
                       InputStars& input, ReweightingOutcome& outcome, std::vector<double>& log_gain) {
  const auto count = work.rings.vertex_count();
  std::vector<double> proposal(count);
  const bool certified_by_itself = outcome.best.certificate.certified();
  const auto& input_areas = maps.input_areas();
  double distortion = mean_area_distortion(
      input_areas, certified_by_itself ? outcome.best.solid_angles : outcome.finished->solid_angles);
  int rejections = 0;
  double step_limit = kEqualizingStep;
  auto vertex_ratio = maps.ratios_of(outcome.best);
  const auto untangling_limit =
      std::max<std::int64_t>(kUntanglingAttempt, static_cast<std::int64_t>(mesh.triangles.size()) / 100);
  for (int round = 1; round <= options.max_equalizing_rounds; ++round) {
    double mean_log = 0;
    for (std::int32_t v = 0; v < count; ++v) {
      const double factor =
          std::clamp(std::pow(std::max(vertex_ratio[v], 1e-300), kEqualizingExponent), 1 / step_limit, step_limit);
      proposal[v] = log_gain[v] + std::log(factor);
      mean_log += proposal[v] / count;
    }
    for (auto& g : proposal) g = std::clamp(g - mean_log, -300.0, 300.0);
    std::optional<Candidate> solved = maps.solve(proposal, outcome.best.planar, outcome.rounds + 1);
    if (!solved) {
      ++outcome.singular_systems;
      step_limit = std::sqrt(step_limit);
      if (++rejections >= kEqualizingPatience) break;
      continue;
    }
    Candidate& candidate = *solved;
    // An equalizing round can fold a few chords on the sphere while the planar map stays one-to-one, and
    // push a few triangles that untangling left just above the collapse floor below it (then no round
    // would ever be kept on a large surface): such a round is judged by its untangled map.
    double candidate_distortion = INFINITY;
    std::optional<Finished> untangled;
    const auto& cc = candidate.certificate;
    if (cc.certified()) {
      candidate_distortion = mean_area_distortion(input_areas, candidate.solid_angles);
    } else if (std::abs(cc.coverage - 1) < 1e-9 && cc.folded + cc.collapsed <= untangling_limit) {
      untangled = finish_map(mesh, input, candidate.sphere, options);
      if (untangled->certificate.certified())
        candidate_distortion = mean_area_distortion(input_areas, untangled->solid_angles);
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
    vertex_ratio = maps.ratios_of(outcome.best);
  }
}

}  // namespace

ReweightingOutcome reweight_against_collapse(const Mesh& mesh, const WorkingMesh& work, std::int32_t north,
                                             std::int32_t south, double mercator_c, const EdgeWeights& base,
                                             const MapOptions& options, InputStars& input, Candidate plain,
                                             OrderChoice& order) {
  ReweightingOutcome outcome{std::move(plain), 0, 0, std::nullopt};
  GainedMaps maps(mesh, work, north, south, mercator_c, base, options, order);
  std::vector<double> log_gain(work.rings.vertex_count(), 0.0);
  reweight_rounds(maps, mesh, work, options, input, outcome, log_gain);

  // Rounds that stop with bad triangles left (patience, or too many for the attempt above) leave them to
  // untangling, which map_to_sphere would try anyway; trying it here lets a certified result be equalized.
  if (!outcome.best.certificate.certified() && !outcome.finished)
    outcome.finished = finish_map(mesh, input, outcome.best.sphere, options);

  const bool certified =
      outcome.best.certificate.certified() || (outcome.finished && outcome.finished->certificate.certified());
  if (certified && options.max_equalizing_rounds > 0)
    equalizing_rounds(maps, mesh, work, options, input, outcome, log_gain);
  return outcome;
}

}  // namespace spheremap::detail
