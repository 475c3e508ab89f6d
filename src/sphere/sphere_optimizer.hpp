// Private to the sphere stage: optimize_on_sphere (sphere/optimize.hpp) as an object that runs several
// times on one mesh (the stages of an objective), building the Hessian's pattern, CHOLMOD's symbolic
// analysis and the rest triangles once.
#pragma once

#include <memory>
#include <vector>

#include "spheremap/mesh.hpp"
#include "spheremap/sphere/optimize.hpp"

namespace spheremap::detail {

class SphereOptimizer {
 public:
  /// `options`' energy, rest scaling (min_rest_area_fraction, min_rest_angle) and threads hold for every
  /// run. Preconditions: rest.size() == fixed.size(); indices valid; `rest`, `triangles` outlive the
  /// object (`triangles` is kept by reference). Throws std::invalid_argument if the sizes disagree.
  SphereOptimizer(const std::vector<Vec3>& rest, const std::vector<Triangle>& triangles, const std::vector<char>& fixed,
                  const SphereOptimizeOptions& options);
  ~SphereOptimizer();
  SphereOptimizer(const SphereOptimizer&) = delete;
  SphereOptimizer& operator=(const SphereOptimizer&) = delete;

  /// optimize_on_sphere from `sphere` with `options`' weights, relative_tolerance and max_iterations
  /// (its other fields are the constructor's): the same points and report as optimize_on_sphere with
  /// the constructor's options and these. Preconditions and throws as optimize_on_sphere's.
  SphereOptimizeReport run(std::vector<Vec3>& sphere, const SphereOptimizeOptions& options);

  /// The energy of `sphere` (one unit vector per vertex) per unit of the map's area, with the weights of
  /// the last run (the constructor's before any): what a run's report gives as energy_before. +inf when a
  /// triangle is not positively oriented. Throws std::invalid_argument if the count of points is wrong.
  double energy(const std::vector<Vec3>& sphere) const;

 private:
  class Optimizer;
  std::unique_ptr<Optimizer> optimizer_;
};

}  // namespace spheremap::detail
