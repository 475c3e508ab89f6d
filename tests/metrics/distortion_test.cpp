#include "spheremap/metrics/distortion.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "../test_geometry.hpp"
#include "spheremap/geometry/superposition.hpp"
#include "spheremap/geometry/vec.hpp"

namespace spheremap {
namespace {

using testing_support::rotation_about;
using testing_support::subdivided_octahedron;

void expect_same_metrics(const DistortionMetrics& x, const DistortionMetrics& y, double tolerance) {
  EXPECT_NEAR(x.area_distortion_mean_percent, y.area_distortion_mean_percent, tolerance);
  EXPECT_NEAR(x.area_distortion_max_percent, y.area_distortion_max_percent, tolerance);
  EXPECT_NEAR(x.area_log_ratio_mean, y.area_log_ratio_mean, tolerance);
  EXPECT_NEAR(x.angle_distortion_mean_degrees, y.angle_distortion_mean_degrees, tolerance);
  EXPECT_NEAR(x.angle_distortion_rms_degrees, y.angle_distortion_rms_degrees, tolerance);
  EXPECT_NEAR(x.angle_distortion_max_degrees, y.angle_distortion_max_degrees, tolerance);
  EXPECT_NEAR(x.dilatation_mean, y.dilatation_mean, tolerance);
  EXPECT_NEAR(x.dilatation_max, y.dilatation_max, tolerance);
  for (int i = 0; i < 8; ++i) EXPECT_NEAR(x.octant_area_percent[i], y.octant_area_percent[i], tolerance);
  EXPECT_NEAR(x.octant_rms_deviation_percent, y.octant_rms_deviation_percent, tolerance);
}

TEST(Distortion, SphereMappedOntoItselfIsNearlyUndistorted) {
  // The only distortion left is between flat facets and the spherical triangles over them, which
  // shrinks as the mesh is refined; the chord triangles *are* the facets, so K = 1 exactly.
  double previous_area = INFINITY, previous_angle = INFINITY;
  for (int levels = 2; levels <= 4; ++levels) {
    const Mesh surface = subdivided_octahedron(levels);
    const DistortionMetrics m = measure_distortion(surface, surface.positions);
    EXPECT_LT(m.area_distortion_mean_percent, previous_area);
    EXPECT_LT(m.angle_distortion_mean_degrees, previous_angle);
    previous_area = m.area_distortion_mean_percent;
    previous_angle = m.angle_distortion_mean_degrees;
    EXPECT_LE(m.angle_distortion_mean_degrees, m.angle_distortion_rms_degrees);
    EXPECT_LE(m.angle_distortion_rms_degrees, m.angle_distortion_max_degrees);
    EXPECT_LE(m.area_distortion_mean_percent, m.area_distortion_max_percent);
    EXPECT_NEAR(m.dilatation_mean, 1.0, 1e-12);
    EXPECT_NEAR(m.dilatation_max, 1.0, 1e-12);
    for (const double percent : m.octant_area_percent) EXPECT_NEAR(percent, 12.5, 1e-10);
    EXPECT_NEAR(m.octant_rms_deviation_percent, 0.0, 1e-10);
  }
  EXPECT_LT(previous_area, 5.0);
  EXPECT_LT(previous_angle, 1.0);
}

TEST(Distortion, SimilarityOfTheSurfaceChangesNothing) {
  const Mesh unit = subdivided_octahedron(3);
  // A non-trivial map: the sphere points of a stretched octahedron.
  std::vector<Vec3> sphere;
  for (const auto& p : unit.positions) sphere.push_back(normalized({p[0], 2 * p[1], 0.5 * p[2]}));
  const DistortionMetrics reference = measure_distortion(unit, sphere);
  EXPECT_GT(reference.angle_distortion_mean_degrees, 1.0);
  EXPECT_GT(reference.dilatation_mean, 1.1);

  Mesh scaled = unit;
  const auto rotation = rotation_about({1, 2, 3}, 0.7);
  for (auto& p : scaled.positions) p = 7.0 * rotate(rotation, p) + Vec3{10, -3, 2};
  expect_same_metrics(measure_distortion(scaled, sphere), reference, 1e-9);
}

TEST(Distortion, DegenerateTrianglesKeepTheFiguresFinite) {
  Mesh surface = subdivided_octahedron(1);
  std::vector<Vec3> sphere = surface.positions;
  // One sphere triangle collapses to a point, one surface triangle to a segment.
  const Triangle collapsed = surface.triangles[0];
  sphere[collapsed[1]] = sphere[collapsed[0]];
  const Triangle flat = surface.triangles.back();
  surface.positions[flat[2]] = 0.5 * (surface.positions[flat[0]] + surface.positions[flat[1]]);
  const DistortionMetrics m = measure_distortion(surface, sphere);
  EXPECT_TRUE(std::isfinite(m.area_distortion_mean_percent));
  EXPECT_TRUE(std::isfinite(m.area_log_ratio_mean));
  EXPECT_TRUE(std::isfinite(m.angle_distortion_mean_degrees));
  EXPECT_TRUE(std::isfinite(m.dilatation_mean));
  EXPECT_EQ(m.dilatation_max, INFINITY);
  EXPECT_GE(m.area_distortion_max_percent, 100.0);
}

TEST(Distortion, SizeMismatchThrows) {
  const Mesh surface = subdivided_octahedron(1);
  std::vector<Vec3> sphere = surface.positions;
  sphere.pop_back();
  EXPECT_THROW(measure_distortion(surface, sphere), std::invalid_argument);
}

}  // namespace
}  // namespace spheremap
