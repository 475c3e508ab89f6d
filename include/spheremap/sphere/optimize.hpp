// Optimization of a sphere map's vertex positions that never leaves the set of valid maps (every
// triangle positively oriented by the exact predicate): projected Newton in each vertex's tangent plane,
// sparse solves with CHOLMOD, a barrier in the energy, an exact orientation check in the line search,
// and a retraction back onto the unit sphere (stage: sphere).
#pragma once

#include <cstdint>
#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// What the optimization minimizes, summed over triangles. Each is infinite on a triangle that is not
/// positively oriented, so a descent from a valid map stays valid.
enum class SphereEnergy {
  /// Symmetric Dirichlet of the affine map from each surface triangle (scaled so the surface's area is
  /// the map's) to its chord triangle on the sphere, with ½·det[a, b, c] as the image area: area and
  /// angles together, +inf as a triangle collapses or folds.
  kSymmetricDirichlet,
  /// Equal area: A·ln²(S/A) per triangle (A its target area, S its ½·det), plus shape_weight times the
  /// conformal distortion A·N/S (N the Dirichlet energy of the affine map), which pins the shapes the
  /// area term leaves free and is the barrier: +inf as a triangle collapses or folds.
  kLogAreaRatio,
  /// Conformal: A·N/S (MIPS: σ₁/σ₂ + σ₂/σ₁ of each triangle's affine map, weighted by its area, 2 at a
  /// similarity whatever the scale) plus a collapse barrier: collapse_barrier_weight·A·(A/S)², which
  /// only matters when a triangle keeps less than about 1e-5 of its share (at the default weight), or
  /// with collapse_threshold set, one that acts only below that share (+inf as it collapses or folds).
  /// map_to_sphere runs the first, then the second with threshold 2e-6 (armadillo: 6.49° mean angle
  /// error after the first, 4.87° after the second, both certified).
  kConformal,
};

/// Default weights of the secondary terms of kLogAreaRatio and kConformal (see there).
inline constexpr double kShapeWeight = 0.1;
inline constexpr double kCollapseBarrierWeight = 1e-10;

struct SphereOptimizeOptions {
  SphereEnergy energy = SphereEnergy::kSymmetricDirichlet;
  /// kLogAreaRatio's shape term and kConformal's collapse barrier (> 0: each is what keeps its energy
  /// infinite as a triangle collapses).
  double shape_weight = kShapeWeight;
  double collapse_barrier_weight = kCollapseBarrierWeight;
  /// If > 0, kConformal's collapse barrier is collapse_barrier_weight·A·φ(S/(κA)) with κ this threshold,
  /// φ(x) = -(x-1)²·ln x below x = 1 and 0 above: nothing on the triangles that keep more than κ of their
  /// share, unbounded as one goes to 0 (instead of the power law, which acts a little on all of them).
  double collapse_threshold = 0;
  int max_iterations = 100;
  /// Stop when an iteration lowers the energy by less than this fraction of it.
  double relative_tolerance = 1e-6;
  /// Surface triangles smaller than this fraction of the mean triangle area count as this large: tiny
  /// input triangles (stacked triangulations reach 1e-15 of the total) are then not asked to become
  /// tiny on the sphere, where doubles could not represent them; they stay above their share.
  double min_rest_area_fraction = 1e-3;
  /// Surface triangles with an angle below this (radians) count as equilateral of their area: a needle
  /// would make the energy as stiff as its cotangent.
  double min_rest_angle = 1e-3;
  /// Threads for the per-triangle work (0: one per hardware thread). The result is the same for any count.
  int threads = 0;
};

/// Why optimize_on_sphere stopped (report.json: map.fallback.final_stop_reason).
enum class OptimizeStop {
  kNone,           // "": not run
  kConverged,      // "converged": an iteration lowered the energy by less than the tolerance, or nothing is free
  kIterations,     // "iterations": max_iterations reached
  kLineSearch,     // "line-search": no step along the descent direction kept the map valid and lowered the energy
  kFactorization,  // "factorization": the Newton system could not be factorized
};

struct SphereOptimizeReport {
  int iterations = 0;        // accepted Newton steps
  int factorizations = 0;    // numeric factorizations of the Newton system (failed ones included)
  double energy_before = 0;  // of the start, per unit of the map's area
  double energy_after = 0;
  OptimizeStop stop_reason = OptimizeStop::kNone;
};

/// Minimizes `energy` over the positions `sphere` of the vertices not marked in `fixed`, keeping every
/// triangle of `triangles` positively oriented (exact orientation_sign > 0) and every point a unit
/// vector. `rest` holds the surface positions the energy compares with (one per vertex).
/// Preconditions: rest.size() == sphere.size() == fixed.size(); indices valid; every point of `sphere`
/// a unit vector, every triangle positively oriented on it (a valid map); the map's triangles are a
/// closed triangulation of the sphere (for the rest scaling). The rest's size does not matter (a copy
/// scaled by a power of two is used: same map to the bit). Throws std::invalid_argument if the sizes
/// disagree, a rest coordinate is not finite, or the start is not valid. Deterministic.
SphereOptimizeReport optimize_on_sphere(const std::vector<Vec3>& rest, const std::vector<Triangle>& triangles,
                                        std::vector<Vec3>& sphere, const std::vector<char>& fixed,
                                        const SphereOptimizeOptions& options = {});

/// The names report.json uses (e.g. "symmetric-dirichlet", "converged"). Never throw.
const char* to_string(SphereEnergy energy);
const char* to_string(OptimizeStop stop);

}  // namespace spheremap
