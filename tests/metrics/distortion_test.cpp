#include "spheremap/metrics/distortion.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <map>
#include <numbers>
#include <stdexcept>
#include <utility>

#include "spheremap/geometry/vec.hpp"

namespace spheremap {
namespace {

// Octahedron split `levels` times into four by its edge midpoints, vertices on the unit sphere.
// Symmetric under the reflections x -> -x, y -> -y, z -> -z, and every face stays inside one octant.
Mesh subdivided_octahedron(int levels) {
  Mesh mesh;
  mesh.positions = {{1, 0, 0}, {-1, 0, 0}, {0, 1, 0}, {0, -1, 0}, {0, 0, 1}, {0, 0, -1}};
  mesh.triangles = {{0, 2, 4}, {2, 1, 4}, {1, 3, 4}, {3, 0, 4}, {2, 0, 5}, {1, 2, 5}, {3, 1, 5}, {0, 3, 5}};
  for (int level = 0; level < levels; ++level) {
    std::map<std::pair<int, int>, int> midpoints;
    const auto midpoint = [&](int i, int j) {
      const auto key = std::minmax(i, j);
      const auto [it, inserted] = midpoints.try_emplace(key, static_cast<int>(mesh.positions.size()));
      if (inserted) mesh.positions.push_back(normalized(0.5 * (mesh.positions[i] + mesh.positions[j])));
      return it->second;
    };
    std::vector<Triangle> finer;
    for (const auto& [a, b, c] : mesh.triangles) {
      const int ab = midpoint(a, b), bc = midpoint(b, c), ca = midpoint(c, a);
      finer.insert(finer.end(), {{a, ab, ca}, {ab, b, bc}, {ca, bc, c}, {ab, bc, ca}});
    }
    mesh.triangles = std::move(finer);
  }
  return mesh;
}

std::array<double, 9> rotation_about(const Vec3& axis, double angle) {
  const Vec3 k = normalized(axis);
  const double c = std::cos(angle), s = std::sin(angle), t = 1 - c;
  return {t * k[0] * k[0] + c,        t * k[0] * k[1] - s * k[2], t * k[0] * k[2] + s * k[1],
          t * k[0] * k[1] + s * k[2], t * k[1] * k[1] + c,        t * k[1] * k[2] - s * k[0],
          t * k[0] * k[2] - s * k[1], t * k[1] * k[2] + s * k[0], t * k[2] * k[2] + c};
}

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

TEST(Superposition, RecoversAKnownRotationScaleAndCentre) {
  const std::vector<Vec3> sphere = subdivided_octahedron(2).positions;  // centred at the origin
  const auto rotation = rotation_about({-0.3, 0.8, 0.5}, 2.1);
  const Vec3 centre{4, -1, 2.5};
  std::vector<Vec3> surface;
  for (const auto& s : sphere) surface.push_back(5.0 * rotate(rotation, s) + centre);

  const Superposition result = superpose_sphere_on_surface(surface, sphere);
  for (int i = 0; i < 9; ++i) EXPECT_NEAR(result.rotation[i], rotation[i], 1e-12) << "entry " << i;
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(result.centroid[i], centre[i], 1e-12);
  EXPECT_NEAR(result.scale, 5.0, 1e-12);
  EXPECT_NEAR(result.rmsd, 0.0, 1e-11);

  const Superposition again = superpose_sphere_on_surface(surface, sphere);
  EXPECT_EQ(again.rotation, result.rotation) << "deterministic";
}

TEST(Superposition, RotationIsProperAndRmsdMatchesItsDefinition) {
  // An ellipsoid cannot be matched exactly: rmsd > 0, and R stays a proper rotation.
  const std::vector<Vec3> sphere = subdivided_octahedron(2).positions;
  const auto rotation = rotation_about({1, 1, 0}, 0.4);
  std::vector<Vec3> surface;
  for (const auto& s : sphere) surface.push_back(rotate(rotation, {3 * s[0], s[1], 0.5 * s[2]}));
  const Superposition result = superpose_sphere_on_surface(surface, sphere);
  const auto& r = result.rotation;
  const double determinant = r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) +
                             r[2] * (r[3] * r[7] - r[4] * r[6]);
  EXPECT_NEAR(determinant, 1.0, 1e-12);
  for (int i = 0; i < 3; ++i)
    for (int j = 0; j < 3; ++j)
      EXPECT_NEAR(r[3 * i] * r[3 * j] + r[3 * i + 1] * r[3 * j + 1] + r[3 * i + 2] * r[3 * j + 2], i == j ? 1 : 0,
                  1e-12);
  double squared = 0;
  for (std::size_t i = 0; i < sphere.size(); ++i)
    squared += squared_distance(result.scale * rotate(r, sphere[i]), surface[i] - result.centroid);
  EXPECT_NEAR(result.rmsd, std::sqrt(squared / static_cast<double>(sphere.size())), 1e-12);
  EXPECT_GT(result.rmsd, 0.1);
  // The long axis of the ellipsoid is R x̂ (up to sign): the fit must put it there.
  const Vec3 long_axis = rotate(r, {1, 0, 0});
  EXPECT_NEAR(std::fabs(dot(long_axis, rotate(rotation, {1, 0, 0}))), 1.0, 1e-9);
}

TEST(Superposition, BadInputThrows) {
  const std::vector<Vec3> two{{1, 0, 0}, {0, 1, 0}};
  EXPECT_THROW(superpose_sphere_on_surface(two, two), std::invalid_argument);
  const std::vector<Vec3> three{{1, 0, 0}, {0, 1, 0}, {0, 0, 1}};
  EXPECT_THROW(superpose_sphere_on_surface(three, two), std::invalid_argument);
}

TEST(Superposition, RotateIsRowMajorMatrixTimesVector) {
  const std::array<double, 9> m{1, 2, 3, 4, 5, 6, 7, 8, 9};
  const Vec3 v = rotate(m, {1, 0, -1});
  EXPECT_EQ(v, (Vec3{-2, -2, -2}));
}

}  // namespace
}  // namespace spheremap
