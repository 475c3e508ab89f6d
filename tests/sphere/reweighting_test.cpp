// The factorization the re-weighting rounds reuse from round to round.
#include <gtest/gtest.h>

#include <algorithm>
#include <array>
#include <cmath>
#include <numbers>
#include <random>

#include "../../src/sphere/harmonic.hpp"
#include "spheremap/geometry/vec.hpp"
#include "spheremap/shapes.hpp"
#include "spheremap/sphere/map.hpp"
#include "spheremap/topology/connectivity.hpp"
#include "spheremap/topology/prepare.hpp"

namespace spheremap {
namespace {

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

  detail::ReusableCholesky factor(rings, mesh.positions, always_fixed, last);
  const detail::HarmonicProblem z_problem{&rings, &weights, &mesh.positions, always_fixed, {}};
  ASSERT_TRUE(factor.factorize(z_problem));
  auto reused = x, fresh = x;
  factor.solve(z_problem, reused);
  detail::solve_harmonic(z_problem, fresh, Solver::kDirect, 0, 0);
  for (std::int32_t v = 0; v < n; ++v) EXPECT_NEAR(reused[v], fresh[v], 1e-9) << v;

  auto fixed_more = always_fixed;
  auto y = x;
  for (auto v : last) fixed_more[v] = 1, y[v] = 2 * unit(random) - 1;
  const detail::HarmonicProblem phi_problem{&rings, &weights, &mesh.positions, fixed_more, {}};
  auto through_leading_block = y, through_decoupled_rows = y, fresh_phi = y;
  factor.solve(phi_problem, through_leading_block, true);
  detail::solve_harmonic(phi_problem, fresh_phi, Solver::kDirect, 0, 0);
  ASSERT_TRUE(factor.factorize(phi_problem));
  factor.solve(phi_problem, through_decoupled_rows);
  for (std::int32_t v = 0; v < n; ++v) {
    EXPECT_NEAR(through_leading_block[v], fresh_phi[v], 1e-9) << v;
    EXPECT_NEAR(through_decoupled_rows[v], fresh_phi[v], 1e-9) << v;
  }
  for (auto v : last) EXPECT_EQ(through_leading_block[v], y[v]);
}

}  // namespace
}  // namespace spheremap
