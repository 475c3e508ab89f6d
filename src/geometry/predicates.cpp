// Exact sign of det[a; b; c] in three tiers, fastest first:
//  1. a floating-point filter with a rigorous forward error bound (Shewchuk 1997, stage A);
//  2. exact expansion arithmetic (Two-Sum, Two-Product with Dekker splitting) after scaling each row
//     by a power of two, valid when no partial product can underflow;
//  3. big-integer arithmetic on the binary mantissas, for inputs whose dynamic range would make the
//     expansions underflow (e.g. a coordinate 1e-100 next to 1). Needed only to keep the promise of
//     exactness for *any* finite doubles; real meshes never get here.
#include "spheremap/geometry/predicates.hpp"

#include <algorithm>
#include <array>
#include <cmath>
#include <cstdint>
#include <limits>
#include <vector>

namespace spheremap {
namespace {

constexpr double kEpsilon = std::numeric_limits<double>::epsilon() / 2;  // unit roundoff 2^-53

// Forward error of the straightforward evaluation below, relative to the permanent (the same sum with
// every product replaced by its absolute value). Rounding analysis gives (5 + O(ε))ε: 3ε for each
// cofactor-times-entry term, 2ε for the two additions. 8ε leaves room for the O(ε²) terms, for the
// rounding of the permanent itself and for the absolute error of products that underflow (at most a
// few 2^-1074, negligible against ε·kSmallestTrustedPermanent).
constexpr double kFilterErrorBound = 8 * kEpsilon;
// Below this permanent, underflow could dominate the rounding errors: leave such cases to exact code.
const double kSmallestTrustedPermanent = std::ldexp(1.0, -900);

// After row scaling every entry is in (-1, 1). Entries at least 2^-kMaxRowDynamicRange keep every
// partial product of the expansion path at least 2^-970 or so, so that Two-Product stays exact.
constexpr int kMaxRowDynamicRange = 250;

// ---------------------------------------------------------------------------------------------
// Expansion arithmetic (Shewchuk 1997). Relies on round-to-nearest IEEE doubles, no contraction
// (the library is compiled with -ffp-contract=off).

struct TwoDoubles {
  double high;
  double low;  // exact error: high + low == true result
};

TwoDoubles two_sum(double a, double b) {
  const double sum = a + b;
  const double b_virtual = sum - a;
  const double a_virtual = sum - b_virtual;
  return {sum, (a - a_virtual) + (b - b_virtual)};
}

TwoDoubles split(double a) {
  constexpr double kSplitter = 134217729.0;  // 2^27 + 1
  const double c = kSplitter * a;
  const double high = c - (c - a);
  return {high, a - high};
}

TwoDoubles two_product(double a, double b) {
  const double product = a * b;
  const auto [a_high, a_low] = split(a);
  const auto [b_high, b_low] = split(b);
  const double error = product - a_high * b_high - a_low * b_high - a_high * b_low;
  return {product, a_low * b_low - error};
}

// Adds `value` to a nonoverlapping expansion kept in increasing magnitude (Grow-Expansion with zero
// elimination); the result is again nonoverlapping, so its sign is that of its last component.
void grow_expansion(std::vector<double>& expansion, double value) {
  std::size_t kept = 0;
  for (const double component : expansion) {
    const auto [sum, error] = two_sum(value, component);
    value = sum;
    if (error != 0) expansion[kept++] = error;
  }
  expansion.resize(kept);
  if (value != 0) expansion.push_back(value);
}

// The six signed triple products of the cofactor expansion of det[rows].
using Matrix3 = std::array<Vec3, 3>;
struct TripleProduct {
  int sign;
  int row0_column, row1_column, row2_column;
};
constexpr std::array<TripleProduct, 6> kDeterminantTerms{
    {{+1, 0, 1, 2}, {-1, 0, 2, 1}, {+1, 1, 2, 0}, {-1, 1, 0, 2}, {+1, 2, 0, 1}, {-1, 2, 1, 0}}};

int sign_of_last_component(const std::vector<double>& expansion) {
  if (expansion.empty()) return 0;
  return expansion.back() > 0 ? 1 : -1;
}

// Precondition: every entry is 0 or has magnitude in [2^-kMaxRowDynamicRange, 1).
int determinant_sign_by_expansion(const Matrix3& m) {
  std::vector<double> sum;
  sum.reserve(32);
  for (const auto& term : kDeterminantTerms) {
    const double x = term.sign * m[0][term.row0_column];
    const double y = m[1][term.row1_column];
    const double z = m[2][term.row2_column];
    const auto xy = two_product(x, y);
    for (const double part : {xy.low, xy.high}) {
      const auto xyz = two_product(part, z);
      grow_expansion(sum, xyz.low);
      grow_expansion(sum, xyz.high);
    }
  }
  return sign_of_last_component(sum);
}

// ---------------------------------------------------------------------------------------------
// Unsigned big integers, little-endian 32-bit limbs. Only what the sign of a sum of products needs.

using BigUnsigned = std::vector<std::uint32_t>;

BigUnsigned multiply(const BigUnsigned& a, const BigUnsigned& b) {
  BigUnsigned product(a.size() + b.size(), 0);
  for (std::size_t i = 0; i < a.size(); ++i) {
    std::uint64_t carry = 0;
    for (std::size_t j = 0; j < b.size(); ++j) {
      const std::uint64_t t = std::uint64_t{a[i]} * b[j] + product[i + j] + carry;
      product[i + j] = static_cast<std::uint32_t>(t);
      carry = t >> 32;
    }
    product[i + b.size()] = static_cast<std::uint32_t>(carry);
  }
  return product;
}

// accumulator += value * 2^shift
void add_shifted(BigUnsigned& accumulator, const BigUnsigned& value, std::int64_t shift) {
  const auto limb_shift = static_cast<std::size_t>(shift / 32);
  const auto bit_shift = static_cast<unsigned>(shift % 32);
  const std::size_t needed = limb_shift + value.size() + 2;
  if (accumulator.size() < needed) accumulator.resize(needed, 0);
  std::uint64_t carry = 0;
  for (std::size_t i = 0; i < value.size() + 1 || carry != 0; ++i) {
    std::uint64_t shifted = 0;
    if (i < value.size()) shifted |= std::uint64_t{value[i]} << bit_shift;
    if (i > 0 && i - 1 < value.size() && bit_shift != 0) shifted |= std::uint64_t{value[i - 1]} >> (32 - bit_shift);
    shifted &= 0xffffffffu;
    if (limb_shift + i >= accumulator.size()) accumulator.push_back(0);
    const std::uint64_t t = std::uint64_t{accumulator[limb_shift + i]} + shifted + carry;
    accumulator[limb_shift + i] = static_cast<std::uint32_t>(t);
    carry = t >> 32;
  }
}

int compare(const BigUnsigned& a, const BigUnsigned& b) {
  const std::size_t length = std::max(a.size(), b.size());
  for (std::size_t i = length; i-- > 0;) {
    const std::uint32_t x = i < a.size() ? a[i] : 0;
    const std::uint32_t y = i < b.size() ? b[i] : 0;
    if (x != y) return x > y ? 1 : -1;
  }
  return 0;
}

// |x| = mantissa * 2^exponent with an integer mantissa < 2^53; exact for every finite double,
// subnormals included.
struct BinaryDouble {
  BigUnsigned mantissa;
  std::int64_t exponent;
};

BinaryDouble decompose(double x) {
  int exponent = 0;
  const double fraction = std::frexp(std::fabs(x), &exponent);
  const auto mantissa = static_cast<std::uint64_t>(std::ldexp(fraction, 53));
  return {{static_cast<std::uint32_t>(mantissa), static_cast<std::uint32_t>(mantissa >> 32)}, exponent - 53};
}

int determinant_sign_by_big_integers(const Matrix3& m) {
  struct Term {
    bool negative;
    BigUnsigned magnitude;
    std::int64_t exponent;
  };
  std::vector<Term> terms;
  for (const auto& term : kDeterminantTerms) {
    const double x = m[0][term.row0_column];
    const double y = m[1][term.row1_column];
    const double z = m[2][term.row2_column];
    if (x == 0 || y == 0 || z == 0) continue;
    const bool negative = (term.sign < 0) != ((x < 0) != ((y < 0) != (z < 0)));
    const auto bx = decompose(x), by = decompose(y), bz = decompose(z);
    terms.push_back(
        {negative, multiply(multiply(bx.mantissa, by.mantissa), bz.mantissa), bx.exponent + by.exponent + bz.exponent});
  }
  if (terms.empty()) return 0;
  std::int64_t lowest_exponent = terms.front().exponent;
  for (const auto& term : terms) lowest_exponent = std::min(lowest_exponent, term.exponent);
  BigUnsigned positive_sum, negative_sum;
  for (const auto& term : terms)
    add_shifted(term.negative ? negative_sum : positive_sum, term.magnitude, term.exponent - lowest_exponent);
  return compare(positive_sum, negative_sum);
}

// ---------------------------------------------------------------------------------------------

int exact_determinant_sign(const Matrix3& m) {
  // Multiplying a row by a power of two is exact unless it pushes an entry into the subnormal range,
  // and never changes the sign of the determinant. Bringing each row's largest entry into [0.5, 1)
  // rules out overflow; the dynamic-range test rules out underflow.
  Matrix3 scaled{};
  bool expansions_are_exact = true;
  for (int row = 0; row < 3; ++row) {
    const double largest = std::max({std::fabs(m[row][0]), std::fabs(m[row][1]), std::fabs(m[row][2])});
    if (largest == 0) return 0;
    const int row_exponent = std::ilogb(largest) + 1;
    for (int column = 0; column < 3; ++column) {
      const double entry = m[row][column];
      if (entry != 0 && std::ilogb(entry) + 1 - row_exponent < -kMaxRowDynamicRange) expansions_are_exact = false;
      scaled[row][column] = std::ldexp(entry, -row_exponent);
    }
  }
  return expansions_are_exact ? determinant_sign_by_expansion(scaled) : determinant_sign_by_big_integers(m);
}

}  // namespace

int orientation_sign(const Vec3& a, const Vec3& b, const Vec3& c, bool* decided_exactly) {
  const double bycz = b[1] * c[2], bzcy = b[2] * c[1];
  const double bzcx = b[2] * c[0], bxcz = b[0] * c[2];
  const double bxcy = b[0] * c[1], bycx = b[1] * c[0];
  const double determinant = a[0] * (bycz - bzcy) + a[1] * (bzcx - bxcz) + a[2] * (bxcy - bycx);
  const double permanent = std::fabs(a[0]) * (std::fabs(bycz) + std::fabs(bzcy)) +
                           std::fabs(a[1]) * (std::fabs(bzcx) + std::fabs(bxcz)) +
                           std::fabs(a[2]) * (std::fabs(bxcy) + std::fabs(bycx));
  // The comparisons are false for an infinite (overflowed) permanent, which falls through as well.
  if (permanent >= kSmallestTrustedPermanent && permanent <= std::numeric_limits<double>::max()) {
    const double error_bound = kFilterErrorBound * permanent;
    if (determinant > error_bound || -determinant > error_bound) {
      if (decided_exactly != nullptr) *decided_exactly = false;
      return determinant > 0 ? 1 : -1;
    }
  }
  if (decided_exactly != nullptr) *decided_exactly = true;
  return exact_determinant_sign({a, b, c});
}

int orientation_sign_2d(double ax, double ay, double bx, double by, double cx, double cy) {
  // The 2D orientation is det[[ax, ay, 1], [bx, by, 1], [cx, cy, 1]], so the 3D predicate answers it
  // exactly; its filter is looser than a translated 2D one, which only costs speed.
  return orientation_sign({ax, ay, 1.0}, {bx, by, 1.0}, {cx, cy, 1.0});
}

}  // namespace spheremap
