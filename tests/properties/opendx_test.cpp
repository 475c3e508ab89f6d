#include "spheremap/properties/opendx.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <fstream>
#include <random>
#include <string>

#include <fmt/format.h>

#include "spheremap/error.hpp"

namespace spheremap {
namespace {

std::filesystem::path temporary(const std::string& name) {
  return std::filesystem::temp_directory_path() / fmt::format("spheremap-dx-{}-{}", ::getpid(), name);
}

// A map in APBS's layout (3 values a line, z fastest) of f at the grid points.
template <typename F>
std::string dx_text(std::array<int, 3> n, const Vec3& origin, const std::array<Vec3, 3>& delta, F f) {
  std::string text = "# Data from APBS 3.4.1\n# \n# POTENTIAL (kT/e)\n# \n";
  text += fmt::format("object 1 class gridpositions counts {} {} {}\n", n[0], n[1], n[2]);
  text += fmt::format("origin {:e} {:e} {:e}\n", origin[0], origin[1], origin[2]);
  for (const auto& d : delta) text += fmt::format("delta {:e} {:e} {:e}\n", d[0], d[1], d[2]);
  text += fmt::format("object 2 class gridconnections counts {} {} {}\n", n[0], n[1], n[2]);
  text += fmt::format("object 3 class array type double rank 0 items {} data follows\n", n[0] * n[1] * n[2]);
  int column = 0;
  for (int i = 0; i < n[0]; ++i)
    for (int j = 0; j < n[1]; ++j)
      for (int k = 0; k < n[2]; ++k) {
        Vec3 p = origin;
        for (int a = 0; a < 3; ++a) p[a] += i * delta[0][a] + j * delta[1][a] + k * delta[2][a];
        text += fmt::format("{}{}", fmt::format("{:.17g}", f(p)), ++column % 3 == 0 ? "\n" : " ");
      }
  if (column % 3 != 0) text += "\n";
  text +=
      "attribute \"dep\" string \"positions\"\nobject \"regular positions regular connections\" class field\n"
      "component \"positions\" value 1\ncomponent \"connections\" value 2\ncomponent \"data\" value 3\n";
  return text;
}

std::filesystem::path write(const std::string& name, const std::string& text) {
  const auto path = temporary(name);
  std::ofstream(path) << text;
  return path;
}

double linear(const Vec3& p) { return 0.75 * p[0] - 1.25 * p[1] + 2.5 * p[2] - 3; }

TEST(OpenDx, TrilinearInterpolationOfALinearFieldIsExact) {
  const std::array<int, 3> n = {5, 4, 6};
  const Vec3 origin = {-7.5, 15.0, -21.5};
  const std::array<Vec3, 3> delta = {Vec3{0.5, 0, 0}, Vec3{0, 0.75, 0}, Vec3{0, 0, 0.25}};
  const auto path = write("linear.dx", dx_text(n, origin, delta, linear));
  const DxGrid grid = read_dx(path);
  std::filesystem::remove(path);
  EXPECT_EQ(grid.counts, (std::array<std::int64_t, 3>{5, 4, 6}));
  EXPECT_EQ(grid.origin, origin);
  ASSERT_EQ(grid.values.size(), 120u);
  EXPECT_EQ(grid.values[(1 * 4 + 2) * 6 + 3], linear({-7.0, 16.5, -20.75}));  // z fastest
  std::mt19937 random(2);
  std::uniform_real_distribution<double> x(-7.5, -5.5), y(15.0, 17.25), z(-21.5, -20.25);
  std::vector<Vec3> points = {origin, {-5.5, 17.25, -20.25}, {-6.0, 15.75, -21.0}};  // corners and a grid point
  for (int i = 0; i < 500; ++i) points.push_back({x(random), y(random), z(random)});
  const auto values = interpolate_dx(grid, points, "linear.dx");
  for (std::size_t i = 0; i < points.size(); ++i) EXPECT_NEAR(values[i], linear(points[i]), 1e-12) << i;
}

TEST(OpenDx, SkewGridsInterpolateExactlyToo) {
  const std::array<Vec3, 3> delta = {Vec3{0.5, 0.1, 0}, Vec3{0, 0.5, 0.2}, Vec3{0.1, 0, 0.5}};
  const auto path = write("skew.dx", dx_text({4, 4, 4}, {1, 2, 3}, delta, linear));
  const DxGrid grid = read_dx(path);
  std::filesystem::remove(path);
  const Vec3 inside = {1 + 0.5 * 1.5 + 0.1 * 2.2, 2 + 0.1 * 1.5 + 0.5 * 0.7, 3 + 0.2 * 0.7 + 0.5 * 2.2};
  EXPECT_NEAR(interpolate_dx(grid, {inside}, "skew")[0], linear(inside), 1e-12);
}

TEST(OpenDx, APointOutsideTheMapSaysHowFarAndTheFix) {
  const auto path =
      write("outside.dx", dx_text({3, 3, 3}, {0, 0, 0}, {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}, linear));
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

// Each bad file gives an InputError whose message names the file, the line and the problem.
void expect_bad(const std::string& text, const std::string& where, const std::string& problem) {
  const auto path = write("bad.dx", text);
  try {
    read_dx(path);
    ADD_FAILURE() << "no error for a map with " << problem;
  } catch (const InputError& e) {
    const std::string message = e.what();
    EXPECT_NE(message.find(path.string() + where), std::string::npos) << message;
    EXPECT_NE(message.find(problem), std::string::npos) << message;
  }
  std::filesystem::remove(path);
}

TEST(OpenDx, BadFilesNameTheLineAndTheProblem) {
  const std::string good = dx_text({2, 2, 3}, {0, 0, 0}, {Vec3{1, 0, 0}, Vec3{0, 1, 0}, Vec3{0, 0, 1}}, linear);
  auto replace = [&](const std::string& from, const std::string& to) {
    std::string text = good;
    text.replace(text.find(from), from.size(), to);
    return text;
  };
  // The header: lines 1-4 are comments, 5 gridpositions, 6 origin, 7-9 deltas, 10 connections, 11 array.
  expect_bad(replace("counts 2 2 3\norigin", "counts 2 2 4\norigin"), ":10:", "gridconnections counts differ");
  expect_bad(replace("items 12", "items 13"), ":11:", "13 items announced, but the grid has 2 x 2 x 3 = 12 points");
  expect_bad(replace("gridpositions counts 2 2 3", "gridpositions counts 2 x 3"),
             ":5:", "'x' in the grid counts is not a number");
  expect_bad(replace("gridpositions counts 2 2 3", "gridpositions counts 1 2 3"), ":5:", "a grid count of 1");
  expect_bad(replace("origin", "origine"), ":6:", "expected 'origin x y z'");
  expect_bad(replace("delta 0.000000e+00 0.000000e+00 1.000000e+00", "delta 1.000000e+00 1.000000e+00 0.000000e+00"),
             ":9:", "lie in a plane");
  // Values start on line 12, three a line.
  std::string text = good;
  const auto data = text.find("data follows\n") + 13;
  text.replace(data, text.find(' ', data) - data, "0.5x");
  expect_bad(text, ":12:", "'0.5x' is not a number");
  text = good;
  text.replace(text.find(' ', data) + 1, 0, "nan ");
  expect_bad(text, ":12:", "'nan' is not a finite number");
  expect_bad(good.substr(0, good.find("attribute")) + "1.0\n", ":16:", "more values than the 12 announced");
  const std::string truncated = good.substr(0, good.find('\n', data + 1) + 1);  // only the first 3 values
  expect_bad(truncated, ": only 3 of the 12 values", "looks truncated");
  std::string cut = good;
  cut.erase(data, cut.find('\n', data) + 1 - data);  // 9 values, then the attribute line
  expect_bad(cut, ":15:", "'attribute' after only 9 of the 12 values announced");
  expect_bad("# nothing\n", ": the file ends before its 'object 1 class gridpositions", "truncated");
  EXPECT_THROW(read_dx(temporary("missing.dx")), InputError);
}

}  // namespace
}  // namespace spheremap
