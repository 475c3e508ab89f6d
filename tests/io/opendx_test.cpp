#include "spheremap/io/opendx.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <filesystem>
#include <random>
#include <string>

#include "dx_text.hpp"
#include "spheremap/error.hpp"

namespace spheremap {
namespace {

using testing_support::dx_text;
using testing_support::linear;
using testing_support::temporary;
using testing_support::write_dx;

TEST(OpenDx, ReadsApbsLayoutWithZFastest) {
  const Vec3 origin = {-7.5, 15.0, -21.5};
  const std::array<Vec3, 3> delta = {Vec3{0.5, 0, 0}, Vec3{0, 0.75, 0}, Vec3{0, 0, 0.25}};
  const auto path = write_dx("layout.dx", dx_text({5, 4, 6}, origin, delta, linear));
  const DxGrid grid = read_dx(path);
  std::filesystem::remove(path);
  EXPECT_EQ(grid.counts, (std::array<std::int64_t, 3>{5, 4, 6}));
  EXPECT_EQ(grid.origin, origin);
  EXPECT_EQ(grid.delta, delta);
  ASSERT_EQ(grid.values.size(), 120u);
  EXPECT_EQ(grid.values[(1 * 4 + 2) * 6 + 3], linear({-7.0, 16.5, -20.75}));  // i = 1, j = 2, k = 3
  EXPECT_EQ(grid.values.back(), linear({-5.5, 17.25, -20.25}));
}

// Each bad file gives an InputError whose message names the file, the line and the problem.
void expect_bad(const std::string& text, const std::string& where, const std::string& problem) {
  const auto path = write_dx("bad.dx", text);
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
