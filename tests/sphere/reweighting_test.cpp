// The repair of collapse: re-weighting on shapes whose harmonic map collapses (a deep narrow pocket, a
// thin finger that leads to neither pole), and the factorization it reuses from round to round.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <memory>
#include <numbers>
#include <random>

#include "../../src/sphere/harmonic.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/metrics/distortion.hpp"
#include "spheremap/shapes/shapes.hpp"
#include "spheremap/sphere/map.hpp"
#include "spheremap/sphere/poles.hpp"
#include "spheremap/topology/connectivity.hpp"
#include "spheremap/topology/prepare.hpp"

namespace spheremap {
namespace {

using Profile = std::vector<std::array<double, 2>>;  // (x, r) from the axis back to the axis

// The closed surface swept by `profile` around the x axis: its first and last points lie on the axis
// and become the two axis vertices, every other point a ring of `segments` vertices.
Mesh revolve(const Profile& profile, int segments) {
  Mesh mesh;
  const int rings = static_cast<int>(profile.size()) - 2;
  for (int i = 1; i <= rings; ++i)
    for (int s = 0; s < segments; ++s) {
      const double angle = 2 * std::numbers::pi * s / segments;
      mesh.positions.push_back({profile[i][0], profile[i][1] * std::cos(angle), profile[i][1] * std::sin(angle)});
    }
  const auto first = static_cast<std::int32_t>(mesh.positions.size());
  mesh.positions.push_back({profile.front()[0], 0, 0});
  const auto last = first + 1;
  mesh.positions.push_back({profile.back()[0], 0, 0});
  auto at = [&](int ring, int s) { return static_cast<std::int32_t>(ring * segments + s % segments); };
  for (int s = 0; s < segments; ++s) mesh.triangles.push_back({first, at(0, s + 1), at(0, s)});
  for (int i = 0; i + 1 < rings; ++i)
    for (int s = 0; s < segments; ++s) {
      mesh.triangles.push_back({at(i, s), at(i, s + 1), at(i + 1, s + 1)});
      mesh.triangles.push_back({at(i, s), at(i + 1, s + 1), at(i + 1, s)});
    }
  for (int s = 0; s < segments; ++s) mesh.triangles.push_back({last, at(rings - 1, s), at(rings - 1, s + 1)});
  return prepare_mesh(mesh).mesh;  // orients outward whichever way the profile runs
}

// Points from a to b (a included, b not) at most `step` apart.
void append_segment(Profile& profile, std::array<double, 2> a, std::array<double, 2> b, double step) {
  const int pieces = std::max(1, static_cast<int>(std::ceil(std::hypot(b[0] - a[0], b[1] - a[1]) / step)));
  for (int k = 0; k < pieces; ++k)
    profile.push_back({a[0] + (b[0] - a[0]) * k / pieces, a[1] + (b[1] - a[1]) * k / pieces});
}

// A closed cup: a cylinder of radius 1 and height 3 with an axial hole of radius 0.1 and depth 2.9
// (the GroEL channel in miniature). The farthest vertices are on the outer rims, so the hole leads to
// neither pole and harmonic z decays along it like exp(-depth / radius): the plain map keeps 1e-20 of
// the hole's share of the sphere.
Mesh deep_cup() {
  Profile profile;
  append_segment(profile, {0, 0}, {0, 1}, 0.1);
  append_segment(profile, {0, 1}, {3, 1}, 0.1);
  append_segment(profile, {3, 1}, {3, 0.1}, 0.1);
  append_segment(profile, {3, 0.1}, {0.1, 0.1}, 0.02);
  append_segment(profile, {0.1, 0.1}, {0.1, 0}, 0.02);
  profile.push_back({0.1, 0});
  return revolve(profile, 32);
}

// A unit ball with a finger of radius 0.1 and length 3 along +x; mapped with poles on the ball's
// equator, so the finger leads to neither pole.
Mesh ball_with_finger() {
  Profile profile;
  const double joint = std::acos(0.1);  // the ball's polar angle where its radius is the finger's
  const int arc = 40;
  for (int k = 0; k < arc; ++k) {
    const double angle = std::numbers::pi - (std::numbers::pi - joint) * k / arc;
    profile.push_back({std::cos(angle), std::sin(angle)});
  }
  append_segment(profile, {std::cos(joint), 0.1}, {4, 0.1}, 0.02);
  profile.push_back({4.05, 0});
  return revolve(profile, 32);
}

std::int32_t nearest_vertex(const Mesh& mesh, const Vec3& p) {
  std::int32_t best = 0;
  for (std::int32_t v = 1; v < static_cast<std::int32_t>(mesh.vertex_count()); ++v)
    if (squared_distance(mesh.positions[v], p) < squared_distance(mesh.positions[best], p)) best = v;
  return best;
}

TEST(Reweighting, DeepNarrowPocketIsCertifiedInFewRounds) {
  const Mesh mesh = deep_cup();
  const auto map = map_to_sphere(mesh);
  // The paper's algorithm collapses the hole far below what re-weighting by at most 4x per round could
  // undo in 40 rounds (the previous repair: 40 rounds, 1,819 triangles still collapsed).
  EXPECT_GT(map.diagnostics.repair.plain_certificate.collapsed, 1000);
  EXPECT_LT(map.diagnostics.repair.plain_certificate.min_area_ratio, 1e-15);
  EXPECT_TRUE(map.certificate.certified())
      << map.certificate.folded << " folded, " << map.certificate.collapsed << " collapsed after "
      << map.diagnostics.repair.reweighting_rounds << " rounds";
  EXPECT_LE(map.diagnostics.repair.reweighting_rounds - map.diagnostics.repair.equalizing_rounds,
            8);  // rounds until certified
  EXPECT_EQ(map.diagnostics.repair.plain_certificate.folded, 0);
}

TEST(Reweighting, ThinFingerLeadingToNeitherPoleIsCertifiedInFewRounds) {
  const Mesh mesh = ball_with_finger();
  MapOptions options;
  options.poles = std::make_pair(nearest_vertex(mesh, {0, 0, 1}), nearest_vertex(mesh, {0, 0, -1}));
  const auto map = map_to_sphere(mesh, options);
  EXPECT_GT(map.diagnostics.repair.plain_certificate.collapsed, 1000);
  EXPECT_TRUE(map.certificate.certified())
      << map.certificate.folded << " folded, " << map.certificate.collapsed << " collapsed after "
      << map.diagnostics.repair.reweighting_rounds << " rounds";
  EXPECT_LE(map.diagnostics.repair.reweighting_rounds - map.diagnostics.repair.equalizing_rounds, 8);
}

// The first certified round leaves the finger tiny on the sphere; equalizing must spread it (lower
// mean area distortion) and keep the map certified.
TEST(Reweighting, EqualizingLowersAreaDistortionAndStaysCertified) {
  const Mesh mesh = ball_with_finger();
  MapOptions options;
  options.poles = std::make_pair(nearest_vertex(mesh, {0, 0, 1}), nearest_vertex(mesh, {0, 0, -1}));
  options.max_equalizing_rounds = 0;
  const auto first_certified = map_to_sphere(mesh, options);
  options.max_equalizing_rounds = MapOptions{}.max_equalizing_rounds;
  const auto equalized = map_to_sphere(mesh, options);
  ASSERT_TRUE(first_certified.certificate.certified());
  ASSERT_TRUE(equalized.certificate.certified());
  EXPECT_EQ(first_certified.diagnostics.repair.equalizing_rounds, 0);
  EXPECT_GT(equalized.diagnostics.repair.equalizing_rounds, 0);
  const double before = measure_distortion(mesh, first_certified.sphere).area_distortion_mean_percent;
  const double after = measure_distortion(mesh, equalized.sphere).area_distortion_mean_percent;
  EXPECT_LT(after, 0.8 * before) << before << "% -> " << after << "%";
}

TEST(Reweighting, RepairedMapsAreReproducible) {
  const Mesh mesh = deep_cup();
  const auto first = map_to_sphere(mesh);
  const auto second = map_to_sphere(mesh);
  EXPECT_EQ(first.sphere, second.sphere);
  EXPECT_EQ(first.diagnostics.construction.meridian, second.diagnostics.construction.meridian);
  EXPECT_EQ(first.diagnostics.repair.reweighting_rounds, second.diagnostics.repair.reweighting_rounds);
}

TEST(Reweighting, PlainAlgorithmIsReportedUnchangedByTheRepair) {
  const Mesh mesh = deep_cup();
  MapOptions plain_options;
  plain_options.repair = false;
  const auto plain = map_to_sphere(mesh, plain_options);
  const auto repaired = map_to_sphere(mesh);
  EXPECT_EQ(plain.diagnostics.repair.plain_certificate.collapsed,
            repaired.diagnostics.repair.plain_certificate.collapsed);
  EXPECT_EQ(plain.diagnostics.repair.plain_certificate.folded, repaired.diagnostics.repair.plain_certificate.folded);
  EXPECT_EQ(plain.diagnostics.repair.plain_certificate.min_area_ratio,
            repaired.diagnostics.repair.plain_certificate.min_area_ratio);
  EXPECT_EQ(plain.diagnostics.repair.reweighting_rounds, 0);
  EXPECT_FALSE(plain.certificate.certified());
}

// The factorization the rounds reuse must give the solutions of fresh solves: z (meridian free), φ
// with `last` fixed through the leading block of the same factor, and the decoupled-row path.
TEST(Reweighting, ReusedFactorizationMatchesFreshSolves) {
  const Mesh mesh = prepare_mesh(perturb_vertices(make_icosphere(3), 0.2, 5)).mesh;
  const auto n = static_cast<std::int32_t>(mesh.vertex_count());
  const VertexRings rings = build_vertex_rings(n, mesh.triangles);
  std::mt19937 random(11);
  std::uniform_real_distribution<double> unit(0.0, 1.0);
  // Symmetric positive weights spanning 12 orders of magnitude, as after a few rounds. The two orders
  // of elimination round differently on such a badly conditioned system (measured: up to 3e-12 apart);
  // an error in the reuse would be of the order of the values (0.1 to 1).
  detail::EdgeWeights weights{std::vector<double>(rings.neighbors.size()), true, 0};
  std::vector<double> gain(n);
  for (auto& g : gain) g = std::pow(10.0, -6 * unit(random));
  for (std::int32_t v = 0; v < n; ++v) {
    const auto ring = rings.ring(v);
    for (std::size_t k = 0; k < ring.size(); ++k) weights.values[rings.offsets[v] + k] = gain[v] * gain[ring[k]];
  }
  std::vector<char> always_fixed(n, 0);
  std::vector<double> x(n, 0.0);
  for (std::int32_t pole : {0, 5}) {
    always_fixed[pole] = 1;
    x[pole] = pole == 0 ? 1 : -1;
    for (auto w : rings.ring(pole)) always_fixed[w] = 1, x[w] = x[pole];
  }
  std::vector<std::int32_t> last;
  for (std::int32_t v = 0; v < n && last.size() < 20; v += 17)
    if (!always_fixed[v]) last.push_back(v);

  // The geometric order computed for this set of unknowns, and METIS's and AMD's orders of all unknowns
  // with `last` taken out and moved to the end. On this mesh CHOLMOD factors the first as LL'
  // (supernodal) and the second as LDL' (simplicial): the leading-block solve must hold for both (it once
  // assumed LL' and gave a wrong φ with a simplicial factor).
  const std::vector<detail::EliminationOrder> orders{
      detail::geometric_elimination_order(rings, mesh.positions, always_fixed),
      detail::metis_elimination_order(rings, mesh.positions, always_fixed),
      detail::amd_elimination_order(rings, mesh.positions, always_fixed)};
  ASSERT_EQ(orders[1].method, FillReducingOrder::kMetis);
  ASSERT_EQ(orders[2].method, FillReducingOrder::kAmd);
  std::vector<bool> supernodal;
  for (std::size_t o = 0; o < orders.size(); ++o) {
    SCOPED_TRACE(std::string(to_string(orders[o].method)) + " order");
    auto factor = o == 0 ? std::make_unique<detail::ReusableCholesky>(rings, mesh.positions, always_fixed, last)
                         : std::make_unique<detail::ReusableCholesky>(rings, orders[o], last);
    supernodal.push_back(factor->supernodal());
    const detail::HarmonicProblem z_problem{&rings, &weights, &mesh.positions, always_fixed, {}};
    ASSERT_TRUE(factor->factorize(z_problem));
    auto reused = x, fresh = x;
    factor->solve(z_problem, reused);
    detail::solve_harmonic(z_problem, fresh, Solver::kDirect, 0, 0);
    for (std::int32_t v = 0; v < n; ++v) EXPECT_NEAR(reused[v], fresh[v], 1e-9) << v;

    auto fixed_more = always_fixed;
    auto y = x;
    for (auto v : last) fixed_more[v] = 1, y[v] = 2 * unit(random) - 1;
    const detail::HarmonicProblem phi_problem{&rings, &weights, &mesh.positions, fixed_more, {}};
    auto through_leading_block = y, through_decoupled_rows = y, fresh_phi = y;
    factor->solve(phi_problem, through_leading_block, true);
    detail::solve_harmonic(phi_problem, fresh_phi, Solver::kDirect, 0, 0);
    ASSERT_TRUE(factor->factorize(phi_problem));
    factor->solve(phi_problem, through_decoupled_rows);
    for (std::int32_t v = 0; v < n; ++v) {
      EXPECT_NEAR(through_leading_block[v], fresh_phi[v], 1e-9) << v;
      EXPECT_NEAR(through_decoupled_rows[v], fresh_phi[v], 1e-9) << v;
    }
    for (auto v : last) EXPECT_EQ(through_leading_block[v], y[v]);
  }
  EXPECT_EQ(supernodal.front(), true) << "both kinds of factor should be covered";
  EXPECT_EQ(supernodal[1], false) << "both kinds of factor should be covered";
}

// METIS's and AMD's orders (through CHOLMOD): every vertex that is not always fixed exactly once, the
// same on every call; the analysis of their factors counts flops like the geometric one's (the map
// chooses by that count).
TEST(Reweighting, CholmodOrdersAreRepeatablePermutationsOfTheUnknowns) {
  const Mesh mesh = prepare_mesh(perturb_vertices(make_icosphere(4), 0.2, 9)).mesh;
  const auto n = static_cast<std::int32_t>(mesh.vertex_count());
  const VertexRings rings = build_vertex_rings(n, mesh.triangles);
  std::vector<char> always_fixed(n, 0);
  for (std::int32_t pole : {0, 7}) {
    always_fixed[pole] = 1;
    for (auto w : rings.ring(pole)) always_fixed[w] = 1;
  }
  const auto geometric = detail::geometric_elimination_order(rings, mesh.positions, always_fixed);
  EXPECT_EQ(geometric.method, FillReducingOrder::kGeometric);
  const detail::ReusableCholesky by_geometry(rings, geometric);
  EXPECT_GT(by_geometry.flops(), 0);
  using Ordering = detail::EliminationOrder (*)(const VertexRings&, const std::vector<Vec3>&, const std::vector<char>&);
  for (const auto& [method, ordering] :
       {std::pair<FillReducingOrder, Ordering>{FillReducingOrder::kMetis, detail::metis_elimination_order},
        std::pair<FillReducingOrder, Ordering>{FillReducingOrder::kAmd, detail::amd_elimination_order}}) {
    SCOPED_TRACE(to_string(method));
    const auto order = ordering(rings, mesh.positions, always_fixed);
    ASSERT_EQ(order.method, method);
    std::vector<int> seen(n, 0);
    for (auto v : order.vertices) ++seen[v];
    for (std::int32_t v = 0; v < n; ++v) EXPECT_EQ(seen[v], always_fixed[v] ? 0 : 1) << v;
    EXPECT_EQ(ordering(rings, mesh.positions, always_fixed).vertices, order.vertices);
    const detail::ReusableCholesky factor(rings, order);
    EXPECT_GT(factor.flops(), 0);
  }
}

// The fixed vertices of the maps' systems in these tests: the farthest pair and their rings.
std::vector<char> poles_and_rings(const Mesh& mesh, const VertexRings& rings) {
  std::vector<char> fixed(mesh.vertex_count(), 0);
  const auto [north, south] = farthest_pair(mesh.positions);
  for (const auto pole : {north, south}) {
    fixed[pole] = 1;
    for (auto w : rings.ring(pole)) fixed[w] = 1;
  }
  return fixed;
}

// The geometric order splits its blocks in place, in one array: every unknown must come out exactly once,
// the same on every call, both where blocks are split at the median (below 5,000 vertices) and where they
// are split in the widest gap (a perturbed cube of 10,088 vertices), and where every point coincides (ties
// are broken by number).
TEST(Reweighting, GeometricOrderIsARepeatablePermutationOfTheUnknowns) {
  const Mesh small = prepare_mesh(perturb_vertices(make_icosphere(4), 0.2, 9)).mesh;
  const Mesh large = prepare_mesh(perturb_vertices(make_subdivided_cube(41), 0.05, 1)).mesh;
  ASSERT_LT(small.vertex_count(), 5000u);
  ASSERT_GE(large.vertex_count(), 5000u);
  for (const Mesh* mesh : {&small, &large}) {
    SCOPED_TRACE(mesh->vertex_count());
    const auto n = static_cast<std::int32_t>(mesh->vertex_count());
    const auto rings = build_vertex_rings(n, mesh->triangles);
    const auto fixed = poles_and_rings(*mesh, rings);
    const std::vector<Vec3> one_point(mesh->positions.size(), Vec3{1, 2, 3});
    for (const auto* positions : {&mesh->positions, &one_point}) {
      const auto order = detail::geometric_elimination_order(rings, *positions, fixed);
      std::vector<int> seen(n, 0);
      for (auto v : order.vertices) ++seen[v];
      for (std::int32_t v = 0; v < n; ++v) EXPECT_EQ(seen[v], fixed[v] ? 0 : 1) << v;
      EXPECT_EQ(detail::geometric_elimination_order(rings, *positions, fixed).vertices, order.vertices);
    }
  }
}

// Moving every vertex of a subdivided cube by up to 5% of an edge must not spoil the geometric order:
// splitting at the exact median scattered the median's row over both halves, and the factor of the
// perturbed 39k-vertex cube needed 1.5x the flops of the plain one's (3.8x at 135k vertices), which made
// the map switch to AMD's slower order (issue 26). Now both need about the same, and fewer than AMD's.
TEST(Reweighting, GeometricOrderIsAsGoodOnAPerturbedGrid) {
  const Mesh plain = prepare_mesh(make_subdivided_cube(81)).mesh;
  const Mesh perturbed = prepare_mesh(perturb_vertices(make_subdivided_cube(81), 0.05, 1)).mesh;
  std::vector<double> flops;
  for (const Mesh* mesh : {&plain, &perturbed}) {
    const auto rings = build_vertex_rings(static_cast<std::int32_t>(mesh->vertex_count()), mesh->triangles);
    const auto fixed = poles_and_rings(*mesh, rings);
    const detail::ReusableCholesky factor(rings, detail::geometric_elimination_order(rings, mesh->positions, fixed));
    flops.push_back(factor.flops());
    const auto amd = detail::amd_elimination_order(rings, mesh->positions, fixed);
    EXPECT_LT(factor.flops(), amd.flops);
  }
  EXPECT_LT(flops[1], 1.1 * flops[0]);
}

// The map compares AMD's flops as AMD counts them with the geometric order's analysis: the two counts
// must agree (CHOLMOD's analysis of AMD's order gives AMD's count).
TEST(Reweighting, AmdCountsTheFlopsOfItsOrderAsTheAnalysisDoes) {
  const Mesh mesh = prepare_mesh(perturb_vertices(make_icosphere(4), 0.2, 9)).mesh;
  const auto rings = build_vertex_rings(static_cast<std::int32_t>(mesh.vertex_count()), mesh.triangles);
  const auto fixed = poles_and_rings(mesh, rings);
  const auto amd = detail::amd_elimination_order(rings, mesh.positions, fixed);
  ASSERT_EQ(amd.method, FillReducingOrder::kAmd);
  const detail::ReusableCholesky factor(rings, amd);
  EXPECT_GT(amd.flops, 0);
  EXPECT_NEAR(amd.flops, factor.flops(), 1e-9 * factor.flops());
}

// Small meshes keep the geometric order (nearly free); the report says which order was used.
TEST(Reweighting, SmallMeshesUseTheGeometricOrder) {
  const Mesh mesh = prepare_mesh(perturb_vertices(make_icosphere(3), 0.2, 5)).mesh;
  EXPECT_EQ(map_to_sphere(mesh).diagnostics.solve.elimination_order, FillReducingOrder::kGeometric);
  MapOptions relaxed;
  relaxed.solver = Solver::kGaussSeidel;
  EXPECT_EQ(map_to_sphere(mesh, relaxed).diagnostics.solve.elimination_order, FillReducingOrder::kNone);
}

}  // namespace
}  // namespace spheremap
