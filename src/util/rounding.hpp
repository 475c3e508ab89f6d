// Private to the library (util/): floor, ceil and round to integers without a libm call (a default x86-64
// build has no SSE4.1 rounding instruction, and these sit in the surface stage's inner loops).
#pragma once

#include <cstdint>

namespace spheremap::detail {

/// std::floor as an integer, for |x| < 2^62.
inline std::int64_t floor_to_int(double x) {
  const auto t = static_cast<std::int64_t>(x);
  return static_cast<double>(t) > x ? t - 1 : t;
}

/// std::ceil as an integer, for |x| < 2^62.
inline std::int64_t ceil_to_int(double x) {
  const auto t = static_cast<std::int64_t>(x);
  return static_cast<double>(t) < x ? t + 1 : t;
}

/// std::llround (half away from zero), for |x| < 2^52.
inline std::int64_t round_to_int(double x) {
  const auto t = static_cast<std::int64_t>(x);  // towards zero; x - t is exact
  const double rest = x - static_cast<double>(t);
  return rest >= 0.5 ? t + 1 : rest <= -0.5 ? t - 1 : t;
}

}  // namespace spheremap::detail
