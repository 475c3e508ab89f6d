// The SAS arcs' quick coverage test (src/surface/circle_cover.hpp) against the exact union of the
// covered parts of the circle.
#include <gtest/gtest.h>

#include <algorithm>
#include <cmath>
#include <numbers>
#include <random>
#include <utility>
#include <vector>

#include "../../src/surface/circle_cover.hpp"

namespace spheremap::detail {
namespace {

constexpr double kPi = std::numbers::pi;

// A part covered by another sphere: the angles θ with |θ - phi| > half (mod 2π), as probe_centres.cpp writes it
// for a circle of radius rho and a sphere centre at distance m from the circle's axis, in direction phi.
struct Part {
  double phi, half;
};

CoverTerm term_of(const Part& part, double rho, double m) {
  const double spread = 2 * rho * m;
  return {m * std::cos(part.phi), m * std::sin(part.phi), spread * std::cos(part.half), spread, 0};
}

// The longest run of angles that no part covers (0 when they cover the whole circle): the covered
// intervals [phi + half, phi + 2π - half], started in [0, 2π) and sorted, swept once from angle 0.
double largest_gap(const std::vector<Part>& parts) {
  if (parts.empty()) return 2 * kPi;
  std::vector<std::pair<double, double>> spans;
  double reached = 0;  // [0, reached) is covered by the parts that run past 2π
  for (const Part& part : parts) {
    double start = std::fmod(part.phi + part.half, 2 * kPi);
    if (start < 0) start += 2 * kPi;
    const double end = start + 2 * (kPi - part.half);
    spans.push_back({start, end});
    reached = std::max(reached, end - 2 * kPi);
  }
  std::sort(spans.begin(), spans.end());
  const double from_zero = reached;
  double gap = 0, first_gap = -1;  // first_gap: the gap that starts at angle 0, if any
  for (const auto& [start, end] : spans) {
    if (start > reached) {
      if (reached == 0 && first_gap < 0)
        first_gap = start;
      else
        gap = std::max(gap, start - reached);
    }
    reached = std::max(reached, end);
  }
  const double last_gap = std::max(0.0, 2 * kPi - reached);
  // A gap that ends the turn goes on past angle 0 when nothing covers angle 0.
  gap = std::max(gap, from_zero == 0 ? last_gap + std::max(0.0, first_gap) : last_gap);
  return gap;
}

std::vector<CoverTerm> terms_of(const std::vector<Part>& parts, std::mt19937& random) {
  std::uniform_real_distribution<double> rho(0.2, 3.5), m(0.05, 6.0);
  std::vector<CoverTerm> terms;
  for (const Part& part : parts) terms.push_back(term_of(part, rho(random), m(random)));
  return terms;
}

TEST(CircleCover, NeverCallsACircleWithAGapCovered) {
  // Random parts, mostly wide, so that many circles are covered or miss it by a little.
  std::mt19937 random(23);
  std::uniform_real_distribution<double> angle(0, 2 * kPi), unit(0, 1);
  std::uniform_int_distribution<int> count(1, 9);
  CoverScratch scratch;
  int certain = 0, near_misses = 0, near_misses_called_unsure = 0;
  for (int trial = 0; trial < 40000; ++trial) {
    std::vector<Part> parts;
    const int n = count(random);
    for (int p = 0; p < n; ++p) parts.push_back({angle(random), 0.02 + (kPi / 2) * std::pow(unit(random), 3)});
    const double gap = largest_gap(parts);
    const bool said = certainly_covered(terms_of(parts, random), scratch);
    if (said) {
      ++certain;
      ASSERT_LE(gap, 1e-9) << "trial " << trial << ": a gap of " << gap << " rad called covered";
    }
    if (gap > 0 && gap < 0.2) near_misses_called_unsure += !said, ++near_misses;
  }
  // The trials do reach both answers, and circles missing coverage by less than 0.2 rad.
  EXPECT_GT(certain, 4000);
  EXPECT_GT(near_misses, 2000);
  EXPECT_EQ(near_misses_called_unsure, near_misses);
}

TEST(CircleCover, CoveredWithRoomToSpareIsCertain) {
  // n parts evenly around the circle, each overlapping its neighbours by 0.12 rad (every angle is 0.06
  // rad or more inside some part: more than the buckets' width, at most 1.8°), plus a few random parts.
  std::mt19937 random(29);
  std::uniform_real_distribution<double> angle(0, 2 * kPi), half(0.05, kPi - 0.05);
  CoverScratch scratch;
  for (int trial = 0; trial < 5000; ++trial) {
    const int n = 2 + trial % 11;
    const double turn = angle(random);
    std::vector<Part> parts;
    for (int p = 0; p < n; ++p) parts.push_back({turn + 2 * kPi * p / n, kPi - (kPi / n + 0.06)});
    for (int extra = 0; extra < trial % 4; ++extra) parts.push_back({angle(random), half(random)});
    std::shuffle(parts.begin(), parts.end(), random);
    ASSERT_EQ(largest_gap(parts), 0.0) << "trial " << trial << ", " << n << " parts";
    EXPECT_TRUE(certainly_covered(terms_of(parts, random), scratch)) << "trial " << trial << ", " << n << " parts";
  }
}

TEST(CircleCover, NothingAndSliversCoverNothing) {
  CoverScratch scratch;
  EXPECT_FALSE(certainly_covered({}, scratch));
  // A sphere touching the circle at one angle only (room = -spread): left out.
  EXPECT_FALSE(certainly_covered({{1.0, 0.0, -2.0, 2.0, 0}}, scratch));
  // One part covering all but 0.01 rad.
  EXPECT_FALSE(certainly_covered({term_of({0.3, 0.005}, 1.0, 1.0)}, scratch));
}

}  // namespace
}  // namespace spheremap::detail
