// Distortion of a sphere map, as in the paper's Table 1 and beyond (stage: metrics).
#pragma once

#include <array>
#include <vector>

#include "spheremap/mesh.hpp"

namespace spheremap {

/// Every figure is defined in docs/report.md.
/// Degenerate cases: area figures average over triangles of nonzero surface area, using the unsigned
/// spherical area (|ln ratio| with ratio floored at the smallest normal double, so a collapsed triangle
/// weighs ~708 instead of making the mean infinite); a corner whose angle is undefined on either side
/// (coincident points) is skipped; a triangle degenerate on the surface has no dilatation, one
/// degenerate only on the sphere has K = +inf, which counts in the max but not in the mean.
struct DistortionMetrics {
  // Area: ratio(t) = (spherical area of t / 4π) / (surface area of t / total surface area).
  double area_distortion_mean_percent = 0;  // mean over triangles of |ratio - 1|, in %
  double area_distortion_max_percent = 0;   // max over triangles of |ratio - 1|, in %
  double area_log_ratio_mean = 0;           // mean over triangles of |ln ratio|
  // Angle: |corner angle on the sphere (between great-circle arcs) - corner angle on the surface|.
  double angle_distortion_mean_degrees = 0;
  double angle_distortion_rms_degrees = 0;
  double angle_distortion_max_degrees = 0;
  // Quasi-conformal dilatation K = σ_max/σ_min of the affine map surface triangle -> flat sphere
  // triangle (chords); 1 for a similarity.
  double dilatation_mean = 0;
  double dilatation_max = 0;
  // Share (%) of the original surface area whose image (triangle centroid direction) falls in each
  // octant of the sphere, in the order (+x+y+z, -x+y+z, +x-y+z, -x-y+z, +x+y-z, -x+y-z, +x-y-z, -x-y-z).
  std::array<double, 8> octant_area_percent{};
  double octant_rms_deviation_percent = 0;  // RMS of (octant % - 12.5)
};

/// Preconditions: sphere.size() == surface.positions.size(), unit vectors; triangles valid.
/// Triangles that are folded or degenerate on either side still count (angles/areas as measured).
/// Throws std::invalid_argument if the sizes disagree.
DistortionMetrics measure_distortion(const Mesh& surface, const std::vector<Vec3>& sphere);

}  // namespace spheremap
