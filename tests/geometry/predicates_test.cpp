#include "spheremap/geometry/predicates.hpp"

#include <gtest/gtest.h>

#include <cmath>
#include <cstdint>
#include <random>

#include "spheremap/geometry/vec.hpp"

namespace spheremap {
namespace {

__extension__ typedef __int128 Int128;

// Reference: points with integer coordinates (|n| < 2^38) scaled by 2^-38 are exact doubles, and the
// determinant of the integers is exact in 128 bits (products < 2^114, six of them).
using IntVec = std::array<std::int64_t, 3>;
constexpr int kGridBits = 38;

int reference_sign(const IntVec& a, const IntVec& b, const IntVec& c) {
  const auto m = [](std::int64_t x, std::int64_t y, std::int64_t z) { return Int128{x} * y * z; };
  const Int128 det = m(a[0], b[1], c[2]) - m(a[0], b[2], c[1]) + m(a[1], b[2], c[0]) - m(a[1], b[0], c[2]) +
                     m(a[2], b[0], c[1]) - m(a[2], b[1], c[0]);
  return det > 0 ? 1 : (det < 0 ? -1 : 0);
}

Vec3 to_double(const IntVec& v, int row_exponent = 0, const std::array<int, 3>& column_exponents = {0, 0, 0}) {
  Vec3 result;
  for (int i = 0; i < 3; ++i)
    result[i] = std::ldexp(static_cast<double>(v[i]), row_exponent + column_exponents[i] - kGridBits);
  return result;
}

int naive_sign(const Vec3& a, const Vec3& b, const Vec3& c) {
  const double det =
      a[0] * (b[1] * c[2] - b[2] * c[1]) + a[1] * (b[2] * c[0] - b[0] * c[2]) + a[2] * (b[0] * c[1] - b[1] * c[0]);
  return det > 0 ? 1 : (det < 0 ? -1 : 0);
}

IntVec random_int_vec(std::mt19937_64& rng, std::int64_t bound) {
  std::uniform_int_distribution<std::int64_t> coordinate(-bound, bound);
  return {coordinate(rng), coordinate(rng), coordinate(rng)};
}

// a and b = a + (a few grid steps) nearly parallel, c = a + b (exactly coplanar with the origin)
// nudged by -1, 0 or +1 grid step in one coordinate: the true determinant is at most ~2^41 against
// products of size 2^112, far below what double rounding can resolve.
struct NearlyCoplanar {
  IntVec a, b, c;
};
NearlyCoplanar nearly_coplanar(std::mt19937_64& rng) {
  NearlyCoplanar t;
  t.a = random_int_vec(rng, (std::int64_t{1} << (kGridBits - 1)) - 16);
  const IntVec offset = random_int_vec(rng, 8);
  for (int i = 0; i < 3; ++i) t.b[i] = t.a[i] + offset[i];
  for (int i = 0; i < 3; ++i) t.c[i] = t.a[i] + t.b[i];
  t.c[std::uniform_int_distribution<int>(0, 2)(rng)] += std::uniform_int_distribution<int>(0, 2)(rng) - 1;
  return t;
}

TEST(Predicate, WellConditionedRandomCasesAgreeWithIntegerReferenceThroughTheFilter) {
  std::mt19937_64 rng(1);
  const std::int64_t bound = (std::int64_t{1} << kGridBits) - 1;
  for (int trial = 0; trial < 20000; ++trial) {
    const auto a = random_int_vec(rng, bound), b = random_int_vec(rng, bound), c = random_int_vec(rng, bound);
    const int expected = reference_sign(a, b, c);
    bool decided_exactly = true;
    EXPECT_EQ(orientation_sign(to_double(a), to_double(b), to_double(c), &decided_exactly), expected);
    // Random determinants are of the order of the permanent, far above the filter's error bound.
    EXPECT_FALSE(decided_exactly);
  }
}

TEST(Predicate, NearlyCoplanarCasesAreExactWhereNaiveDoubleFails) {
  std::mt19937_64 rng(2);
  int naive_wrong = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    const auto [ia, ib, ic] = nearly_coplanar(rng);
    const Vec3 a = to_double(ia), b = to_double(ib), c = to_double(ic);
    const int expected = reference_sign(ia, ib, ic);
    bool decided_exactly = false;
    ASSERT_EQ(orientation_sign(a, b, c, &decided_exactly), expected) << "trial " << trial;
    EXPECT_TRUE(decided_exactly);
    if (naive_sign(a, b, c) != expected) ++naive_wrong;
  }
  EXPECT_GT(naive_wrong, 1000) << "the cases should be hard for plain double arithmetic";
}

TEST(Predicate, OneUlpOffAGreatCircleIsExact) {
  // a, b with 20-bit coordinates; c0 = t a + (1 - t) b with dyadic t is exact and exactly coplanar with
  // the origin; moving one coordinate of c0 by one ulp changes det by δ (a × b)_k, whose sign is exact.
  std::mt19937_64 rng(3);
  std::uniform_int_distribution<int> coordinate(-(1 << 20), 1 << 20), weight(1, 255), axis(0, 2), up(0, 1);
  int naive_wrong = 0;
  for (int trial = 0; trial < 20000; ++trial) {
    Vec3 a, b, c;
    for (int i = 0; i < 3; ++i) {
      a[i] = std::ldexp(coordinate(rng), -20);
      b[i] = std::ldexp(coordinate(rng), -20);
    }
    const double t = std::ldexp(weight(rng), -8);
    for (int i = 0; i < 3; ++i) c[i] = t * a[i] + (1 - t) * b[i];
    ASSERT_EQ(orientation_sign(a, b, c), 0);
    const int k = axis(rng);
    const bool increase = up(rng) == 1;
    c[k] = std::nextafter(c[k], increase ? INFINITY : -INFINITY);
    const double normal_component = cross(a, b)[k];  // exact: 40-bit products of a 2^-40 grid
    const int expected = (normal_component > 0 ? 1 : normal_component < 0 ? -1 : 0) * (increase ? 1 : -1);
    ASSERT_EQ(orientation_sign(a, b, c), expected) << "trial " << trial;
    if (naive_sign(a, b, c) != expected) ++naive_wrong;
  }
  EXPECT_GT(naive_wrong, 100);
}

TEST(Predicate, ExactlyDegenerateGivesZero) {
  bool decided_exactly = false;
  const Vec3 a{0.1, 0.7, -0.3}, b{1.0 / 3, 2.0 / 7, 5.0 / 11};
  EXPECT_EQ(orientation_sign(a, b, a, &decided_exactly), 0);
  EXPECT_TRUE(decided_exactly);
  EXPECT_EQ(orientation_sign(a, b, {0, 0, 0}), 0);
  EXPECT_EQ(orientation_sign(a, b, 0.5 * a), 0);
  EXPECT_EQ(orientation_sign(a, b, -1024.0 * b), 0);
  EXPECT_EQ(orientation_sign({0, 0, 0}, {0, 0, 0}, {0, 0, 0}), 0);
}

TEST(Predicate, SignsOfTheBasisAndPermutations) {
  const Vec3 x{1, 0, 0}, y{0, 1, 0}, z{0, 0, 1};
  EXPECT_EQ(orientation_sign(x, y, z), 1);
  EXPECT_EQ(orientation_sign(y, z, x), 1);
  EXPECT_EQ(orientation_sign(y, x, z), -1);
  EXPECT_EQ(orientation_sign(x, z, y), -1);
}

TEST(Predicate, ExtremeExponentsTakeTheBigIntegerPathAndStayExact) {
  // Scaling rows and columns by powers of two keeps the sign of det. Scales 2^±600 on the columns make
  // each row span ~2^1200, beyond what expansions can take without underflow.
  std::mt19937_64 rng(4);
  const std::array<int, 3> column_exponents{-600, 0, 600};
  for (int trial = 0; trial < 2000; ++trial) {
    const auto [ia, ib, ic] = nearly_coplanar(rng);
    const int expected = reference_sign(ia, ib, ic);
    ASSERT_EQ(orientation_sign(to_double(ia, -300, column_exponents), to_double(ib, 300, column_exponents),
                               to_double(ic, 0, column_exponents)),
              expected)
        << "trial " << trial;
  }
  // Subnormal and huge entries side by side.
  const double tiny = std::ldexp(1.0, -1070), huge = std::ldexp(1.0, 1020);
  EXPECT_EQ(orientation_sign({huge, 0, 0}, {0, huge, 0}, {1, 1, tiny}), 1);
  EXPECT_EQ(orientation_sign({huge, 0, 0}, {0, huge, 0}, {1, 1, -tiny}), -1);
  EXPECT_EQ(orientation_sign({huge, huge, 0}, {tiny, tiny, 0}, {1, 2, 3}), 0);
  EXPECT_EQ(orientation_sign({tiny, 0, 0}, {0, tiny, 0}, {0, 0, tiny}), 1);
  // Products that overflow in double: the filter must not trust an infinite permanent.
  const double big = std::ldexp(1.0, 1000);
  EXPECT_EQ(orientation_sign({big, big, big}, {big, big, big + std::ldexp(1.0, 948)}, {big, -big, big}), 1);
}

TEST(Predicate, TwoDimensionalNearlyCollinearAgreesWithIntegerReference) {
  // Shewchuk's classic example: a within 256 ulps of (0.5, 0.5) against b = (12, 12), c = (24, 24).
  // With the ulp 2^-53 as unit every coordinate is an integer below 2^58, so the determinant is exact
  // in 128 bits, while the differences bx - ax etc. already round in double.
  const double ulp = std::ldexp(1.0, -53);
  const std::int64_t half = std::int64_t{1} << 52, twelve = 12 * (std::int64_t{1} << 53), twenty_four = 2 * twelve;
  int naive_wrong = 0;
  for (int i = 0; i < 256; ++i) {
    for (int j = 0; j < 256; ++j) {
      const double ax = 0.5 + i * ulp, ay = 0.5 + j * ulp;
      const std::int64_t ix = half + i, iy = half + j;
      const Int128 det = Int128{twelve - ix} * (twenty_four - iy) - Int128{twelve - iy} * (twenty_four - ix);
      const int expected = det > 0 ? 1 : (det < 0 ? -1 : 0);
      ASSERT_EQ(orientation_sign_2d(ax, ay, 12, 12, 24, 24), expected) << i << ", " << j;
      const double naive = (12 - ax) * (24 - ay) - (12 - ay) * (24 - ax);
      if ((naive > 0 ? 1 : naive < 0 ? -1 : 0) != expected) ++naive_wrong;
    }
  }
  EXPECT_GT(naive_wrong, 1000);
  EXPECT_EQ(orientation_sign_2d(0, 0, 1, 0, 0, 1), 1);
  EXPECT_EQ(orientation_sign_2d(0, 0, 0, 1, 1, 0), -1);
  EXPECT_EQ(orientation_sign_2d(1, 1, 2, 2, 3, 3), 0);
}

}  // namespace
}  // namespace spheremap
