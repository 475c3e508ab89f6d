#include <gtest/gtest.h>

#include <cmath>
#include <random>

#include "../../src/util/rounding.hpp"

namespace spheremap {
namespace {

TEST(Rounding, AgreesWithTheLibraryEverywhereItIsUsed) {
  std::mt19937_64 random(3);
  std::uniform_real_distribution<double> wide(-1e12, 1e12), narrow(-4, 4);
  for (int trial = 0; trial < 100000; ++trial) {
    const double x = trial % 2 ? wide(random) : narrow(random);
    ASSERT_EQ(detail::floor_to_int(x), static_cast<std::int64_t>(std::floor(x))) << x;
    ASSERT_EQ(detail::ceil_to_int(x), static_cast<std::int64_t>(std::ceil(x))) << x;
    ASSERT_EQ(detail::round_to_int(x), std::llround(x)) << x;
  }
  for (const double x :
       {-2.5, -1.5, -0.5, -0.0, 0.0, 0.5, 1.5, 2.5, -3.0, 3.0, 0.49999999999999994, -0.49999999999999994}) {
    EXPECT_EQ(detail::floor_to_int(x), static_cast<std::int64_t>(std::floor(x))) << x;
    EXPECT_EQ(detail::ceil_to_int(x), static_cast<std::int64_t>(std::ceil(x))) << x;
    EXPECT_EQ(detail::round_to_int(x), std::llround(x)) << x;  // halves away from zero
  }
}

}  // namespace
}  // namespace spheremap
