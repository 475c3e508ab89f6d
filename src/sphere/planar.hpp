// Private to the sphere stage: the paper's planar problem (§2.3). The mesh with its dividing edges split,
// harmonic z between the circumpolar rings, the boundary meridian, harmonic φ, and the Mercator scaling
// that takes (z, φ) onto the sphere.
#pragma once

#include <cstdint>
#include <memory>
#include <optional>
#include <vector>

#include "harmonic.hpp"
#include "spheremap/mesh.hpp"
#include "spheremap/sphere/map.hpp"
#include "spheremap/topology/connectivity.hpp"

namespace spheremap::detail {

inline constexpr double kRingZ = 1.0;  // Z: the circumpolar rings sit at z = ±Z

/// The mesh the planar problem is solved on: the input plus one midpoint per split dividing edge
/// (appended after the input's vertices, so the input's indices stay valid).
struct WorkingMesh {
  std::vector<Vec3> positions;
  std::vector<Triangle> triangles;
  VertexRings rings;
};

/// Splits every edge joining two non-consecutive vertices of the ring around `pole` (a separating
/// triangle through the pole): such an edge would pin everything on its pole side to z = ±Z. Appends
/// each split to `splits` with `tag` ('N' or 'S'); work.rings are then stale (the caller rebuilds them).
/// Throws std::logic_error if a dividing edge is not shared by two triangles (not a closed manifold).
void split_dividing_edges(WorkingMesh& work, std::int32_t pole, char tag, std::vector<SplitEdge>& splits);

/// z, φ and the meridian of the planar map.
struct PlanarCoordinates {
  std::vector<double> z, phi;
  std::vector<std::int32_t> meridian;
  bool meridian_by_descent = true;
  int meridian_round = 0;  // the round whose z the meridian was found for (0: the plain map)
  SolveStats z_stats, phi_stats;
};

/// z, the meridian and φ. The re-weighting rounds pass `factor` (analysed once, with the meridian
/// interior ordered last) and the meridian of the best round so far, which is kept while z still
/// strictly decreases along it: then z and φ come from one numeric factorization (ReusableCholesky).
/// Preconditions: north and south at least 4 edges apart in work.rings; no dividing edges left.
PlanarCoordinates solve_planar(const WorkingMesh& work, std::int32_t north, std::int32_t south,
                               const EdgeWeights& weights, const MapOptions& options,
                               ReusableCholesky* factor = nullptr, const PlanarCoordinates* kept = nullptr,
                               int round = 0);

/// The fill-reducing order for the Cholesky factorizations of one map: AMD's when it needs fewer flops,
/// else the geometric one (computed afresh for each analysis).
struct OrderChoice {
  std::vector<char> always_fixed;          // poles and rings: fixed in every system of the map
  std::optional<EliminationOrder> chosen;  // when not the geometric order
};

/// A factorization of the map's systems in `order`, with the vertices of `last` ordered last.
/// Throws as ReusableCholesky's constructors do.
std::unique_ptr<ReusableCholesky> make_factor(const WorkingMesh& work, const OrderChoice& order,
                                              const std::vector<std::int32_t>& last = {});

/// The factorization of the plain map's systems: in the geometric order, or in AMD's where that needs
/// fewer flops on a mesh of 5,000 vertices or more (then order.chosen is set, for every later round).
/// Preconditions: order.always_fixed set; symmetric weights. Throws as make_factor does.
std::unique_ptr<ReusableCholesky> plain_map_factor(const WorkingMesh& work, OrderChoice& order);

/// The sphere points of the first `count` working vertices (the input's), by the Mercator scaling with
/// constant `c`; the poles exactly at (0, 0, ±1).
std::vector<Vec3> to_sphere(const PlanarCoordinates& planar, std::int32_t north, std::int32_t south, double c,
                            std::int32_t count);

}  // namespace spheremap::detail
