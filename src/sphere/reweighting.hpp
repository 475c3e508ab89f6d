// Private to the sphere stage: the repair against collapse. Re-weighting rounds lower the harmonic
// weights of collapsed regions until the map is certified (by itself or after untangling), then
// equalizing rounds spread area ratios while it stays certified.
#pragma once

#include <optional>
#include <vector>

#include "finish.hpp"
#include "harmonic.hpp"
#include "planar.hpp"
#include "spheremap/mesh.hpp"
#include "spheremap/sphere/certify.hpp"
#include "spheremap/sphere/map.hpp"

namespace spheremap::detail {

/// One map of the working mesh, for the input's vertices.
struct Candidate {
  PlanarCoordinates planar;
  std::vector<Vec3> sphere;  // of the input's vertices, before the superposition
  Certificate certificate;
  std::vector<double> solid_angles;  // of the input's triangles on `sphere`, from the certificate
};

struct ReweightingOutcome {
  Candidate best;
  int rounds = 0;
  int equalizing_rounds = 0;         // of `rounds`, those kept by the equalizing phase
  std::optional<Finished> finished;  // the best round finished (superposed, untangled, certified), if tried
  int singular_systems = 0;          // rounds whose system the sparse LU found singular (rejected)
};

// Collapse: harmonic z and φ decay exponentially along pockets and limbs that lead to neither pole, so
// their triangles keep 1e-9 to 1e-22 of their share of the sphere. Each vertex j gets a gain g_j and
// edge (i, j) weighs base_ij · g_i · g_j (symmetric base weights: the Cholesky path; otherwise
// base_ij · g_j, the same solution up to row scaling): lowering the gains of a collapsed region lowers its
// conductance, which spreads the harmonic functions into it. All weights stay positive and z and φ share
// them, so the planar map stays one-to-one (Floater 2003).
/// `plain` is the plain map; `order` its factorization order (order.chosen may be set for later rounds).
/// Preconditions: `work` is `mesh` with its dividing edges split (the input's vertices first); north and
/// south at least 4 edges apart; base weights positive. Throws as the solvers do.
ReweightingOutcome reweight_against_collapse(const Mesh& mesh, const WorkingMesh& work, std::int32_t north,
                                             std::int32_t south, double mercator_c, const EdgeWeights& base,
                                             const MapOptions& options, InputStars& input, Candidate plain,
                                             OrderChoice& order);

}  // namespace spheremap::detail
