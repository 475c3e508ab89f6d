#include <gtest/gtest.h>

#include <cmath>
#include <limits>
#include <random>

#include "spheremap/surface/distance_transform.hpp"

namespace spheremap {
namespace {

// min over samples p of |q - p|² + start(p), sample by sample: what the transform must give at q.
double brute_force(const Grid3<double>& start, std::int64_t i, std::int64_t j, std::int64_t k) {
  double best = std::numeric_limits<double>::infinity();
  for (std::int64_t c = 0; c < start.size[2]; ++c)
    for (std::int64_t b = 0; b < start.size[1]; ++b)
      for (std::int64_t a = 0; a < start.size[0]; ++a)
        best = std::min(best, static_cast<double>((a - i) * (a - i) + (b - j) * (b - j) + (c - k) * (c - k)) +
                                  start.values[start.index(a, b, c)]);
  return best;
}

// The in-place transform of `start`, in double and in float, on 1, 2 and 3 threads, equals brute_force
// everywhere (the float results are integers below 2^24 here: exact).
void expect_in_place_matches_brute_force(const Grid3<double>& start) {
  for (int threads : {1, 2, 3}) {
    Grid3<double> d = start;
    squared_distance_transform_in_place(d, threads);
    Grid3<float> f;
    f.size = start.size;
    f.values.assign(start.values.begin(), start.values.end());
    squared_distance_transform_in_place(f, threads);
    for (std::int64_t k = 0; k < start.size[2]; ++k)
      for (std::int64_t j = 0; j < start.size[1]; ++j)
        for (std::int64_t i = 0; i < start.size[0]; ++i) {
          const double expected = brute_force(start, i, j, k);
          ASSERT_EQ(d.values[d.index(i, j, k)], expected) << threads << " " << i << " " << j << " " << k;
          ASSERT_EQ(static_cast<double>(f.values[f.index(i, j, k)]), expected)
              << threads << " " << i << " " << j << " " << k;
        }
  }
}

TEST(DistanceTransform, MatchesBruteForceOnRandomTargets) {
  std::mt19937 random(3);
  for (int trial = 0; trial < 5; ++trial) {
    Grid3<std::uint8_t> targets;
    targets.size = {7 + trial, 5 + 2 * trial, 6};
    targets.values.assign(static_cast<std::size_t>(targets.count()), 0);
    for (auto& t : targets.values) t = random() % 13 == 0;
    const auto d = squared_distance_transform(targets);
    for (std::int64_t k = 0; k < targets.size[2]; ++k)
      for (std::int64_t j = 0; j < targets.size[1]; ++j)
        for (std::int64_t i = 0; i < targets.size[0]; ++i) {
          double best = std::numeric_limits<double>::infinity();
          for (std::int64_t c = 0; c < targets.size[2]; ++c)
            for (std::int64_t b = 0; b < targets.size[1]; ++b)
              for (std::int64_t a = 0; a < targets.size[0]; ++a)
                if (targets.values[targets.index(a, b, c)])
                  best = std::min(best, static_cast<double>((a - i) * (a - i) + (b - j) * (b - j) + (c - k) * (c - k)));
          ASSERT_EQ(d.values[d.index(i, j, k)], best) << trial << " " << i << " " << j << " " << k;
        }
  }
}

TEST(DistanceTransform, InPlaceWithAnyStartValuesInDoubleAndFloatAndAnyThreads) {
  std::mt19937 random(5);
  Grid3<double> start;
  start.size = {23, 9, 14};  // wider than one block of lines along x
  start.values.resize(static_cast<std::size_t>(start.count()));
  for (auto& v : start.values)
    v = random() % 4 == 0 ? static_cast<double>(random() % 50) : std::numeric_limits<double>::infinity();
  ASSERT_NO_FATAL_FAILURE(expect_in_place_matches_brute_force(start));
}

TEST(DistanceTransform, EveryKindOfLineMatchesBruteForce) {
  // Lines of zeros and infinities only (two sweeps), of integers and of fractions (lower envelope), and
  // all-zero or all-infinite lines (nothing to do).
  std::mt19937 random(11);
  for (int kind = 0; kind < 3; ++kind) {
    Grid3<double> start;
    start.size = {19, 6, 5};
    start.values.resize(static_cast<std::size_t>(start.count()));
    for (auto& v : start.values) {
      const bool target = random() % 5 == 0;
      v = !target     ? std::numeric_limits<double>::infinity()
          : kind == 0 ? 0.0
          : kind == 1 ? static_cast<double>(random() % 40)
                      : 0.25 * (random() % 160);
    }
    for (std::int64_t i = 0; i < start.size[0]; ++i) start.values[start.index(i, 2, 2)] = 0;  // an all-zero row
    for (std::int64_t i = 0; i < start.size[0]; ++i)
      start.values[start.index(i, 3, 3)] = std::numeric_limits<double>::infinity();
    Grid3<double> d = start;
    squared_distance_transform_in_place(d, 2);
    for (std::int64_t k = 0; k < start.size[2]; ++k)
      for (std::int64_t j = 0; j < start.size[1]; ++j)
        for (std::int64_t i = 0; i < start.size[0]; ++i) {
          ASSERT_EQ(d.values[d.index(i, j, k)], brute_force(start, i, j, k))
              << kind << " " << i << " " << j << " " << k;
        }
  }
}

TEST(DistanceTransform, ZeroSurroundingsAsInAMoleculesGrid) {
  // Zeros (probe centres) around nonzero blobs, as in a molecule's grid: whole blocks of lines and whole
  // planes without a nonzero sample are skipped, and lines are gathered only around their nonzero part;
  // one blob touches the grid's border (no zero beyond it).
  std::mt19937 random(17);
  Grid3<double> start;
  start.size = {45, 13, 12};  // three blocks of 16 lines along x, the last one partial
  start.values.assign(static_cast<std::size_t>(start.count()), 0.0);
  auto blob = [&](double ci, double cj, double ck, double radius) {
    for (std::int64_t k = 0; k < start.size[2]; ++k)
      for (std::int64_t j = 0; j < start.size[1]; ++j)
        for (std::int64_t i = 0; i < start.size[0]; ++i) {
          const double d2 = (i - ci) * (i - ci) + (j - cj) * (j - cj) + (k - ck) * (k - ck);
          if (d2 < radius * radius)
            start.values[start.index(i, j, k)] =
                random() % 3 == 0 ? static_cast<double>(random() % 30 + 1) : std::numeric_limits<double>::infinity();
        }
  };
  blob(7, 6, 5, 4.5);
  blob(40, 0, 11, 3.5);  // at the borders of axes 1 and 2
  ASSERT_NO_FATAL_FAILURE(expect_in_place_matches_brute_force(start));
}

TEST(DistanceTransform, NoTargetGivesInfinity) {
  Grid3<std::uint8_t> empty;
  empty.size = {3, 3, 3};
  empty.values.assign(27, 0);
  for (double d : squared_distance_transform(empty).values) EXPECT_TRUE(std::isinf(d));
}

}  // namespace
}  // namespace spheremap
