#include "spheremap/geometry/superposition.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <stdexcept>
#include <vector>

#include "../test_geometry.hpp"
#include "spheremap/geometry/vec.hpp"

namespace spheremap {
namespace {

using testing_support::rotation_about;
using testing_support::subdivided_octahedron;

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
  const double determinant =
      r[0] * (r[4] * r[8] - r[5] * r[7]) - r[1] * (r[3] * r[8] - r[5] * r[6]) + r[2] * (r[3] * r[7] - r[4] * r[6]);
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

TEST(Superposition, TransposedInvertsARotation) {
  const auto rotation = rotation_about({0.2, -1, 0.7}, 1.3);
  const Vec3 v{0.3, -2, 5};
  const Vec3 back = rotate(transposed(rotation), rotate(rotation, v));
  for (int i = 0; i < 3; ++i) EXPECT_NEAR(back[i], v[i], 1e-14);
  EXPECT_EQ(transposed(std::array<double, 9>{1, 2, 3, 4, 5, 6, 7, 8, 9}),
            (std::array<double, 9>{1, 4, 7, 2, 5, 8, 3, 6, 9}));
}

}  // namespace
}  // namespace spheremap
