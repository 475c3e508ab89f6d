#include "spheremap/properties/potential_map.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>

#include "../io/dx_text.hpp"
#include "spheremap/error.hpp"

namespace spheremap {
namespace {

using testing_support::dx_text;
using testing_support::linear;
using testing_support::write_dx;

TEST(PotentialMap, TrilinearInterpolationOfALinearFieldIsExact) {
  const std::array<int, 3> n = {5, 4, 6};
  const Vec3 origin = {-7.5, 15.0, -21.5};
  const std::array<Vec3, 3> delta = {Vec3{0.5, 0, 0}, Vec3{0, 0.75, 0}, Vec3{0, 0, 0.25}};
  const auto path = write_dx("linear.dx", dx_text(n, origin, delta, linear));
  const DxGrid grid = read_dx(path);
  std::filesystem::remove(path);
  std::mt19937 random(2);
  std::uniform_real_distribution<double> x(-7.5, -5.5), y(15.0, 17.25), z(-21.5, -20.25);
  std::vector<Vec3> points = {origin, {-5.5, 17.25, -20.25}, {-6.0, 15.75, -21.0}};  // corners and a grid point
  for (int i = 0; i < 500; ++i) points.push_back({x(random), y(random), z(random)});
  const auto values = interpolate_dx(grid, points, "linear.dx");
  for (std::size_t i = 0; i < points.size(); ++i) EXPECT_NEAR(values[i], linear(points[i]), 1e-12) << i;
}

TEST(PotentialMap, SkewGridsInterpolateExactlyToo) {
  const std::array<Vec3, 3> delta = {Vec3{0.5, 0.1, 0}, Vec3{0, 0.5, 0.2}, Vec3{0.1, 0, 0.5}};
  const auto path = write_dx("skew.dx", dx_text({4, 4, 4}, {1, 2, 3}, delta, linear));
  const DxGrid grid = read_dx(path);
  std::filesystem::remove(path);
  const Vec3 inside = {1 + 0.5 * 1.5 + 0.1 * 2.2, 2 + 0.1 * 1.5 + 0.5 * 0.7, 3 + 0.2 * 0.7 + 0.5 * 2.2};
  EXPECT_NEAR(interpolate_dx(grid, {inside}, "skew")[0], linear(inside), 1e-12);
}

TEST(PotentialMap, APointOutsideTheMapSaysHowFarAndTheFix) {
  const auto path =
      write_dx("outside.dx", dx_text({3, 3, 3}, {0, 0, 0}, {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}, linear));
  const DxGrid grid = read_dx(path);
  std::filesystem::remove(path);
  try {
    interpolate_dx(grid, {{1, 1, 1}, {5, 1, 1}, {1, -0.5, 1}}, "map.dx");
    FAIL() << "no error for points outside";
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find("map.dx: 2 of the 3 points"), std::string::npos) << message;
    EXPECT_NE(message.find("3.00 Å outside"), std::string::npos) << message;
    EXPECT_NE(message.find("larger grid"), std::string::npos) << message;
  }
  EXPECT_NO_THROW(interpolate_dx(grid, {{2, 2, 2}, {0, 0, 0}}, "map.dx"));  // the far corner is inside
}

}  // namespace
}  // namespace spheremap
