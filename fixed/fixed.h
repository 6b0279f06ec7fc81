// Fixed: a Q32.32 number in an int64_t. 1 ulp = 2^-32 (about 2.3e-10); the
// range is [-2^31, 2^31 - 2^-32]. No implicit conversion from or to any
// floating-point type exists; exact values come from integers, ratios of
// integers, the `_fx` literal or decimal text (fixed/decimal.h).
//
// + and - wrap (two's complement); * and / round to nearest, ties to even, and
// saturate; x / 0 saturates (0 / 0 = 0). BITSTEP_CHECKED aborts instead.
#pragma once

#include <compare>
#include <cstdint>

#include "fixed/raw_arith.h"

namespace bitstep {

class Fixed {
 public:
  constexpr Fixed() = default;

  static constexpr Fixed from_raw(int64_t raw) {
    Fixed f;
    f.raw_ = raw;
    return f;
  }
  // Every int32_t is exactly representable.
  static constexpr Fixed from_int(int32_t value) {
    return from_raw(static_cast<int64_t>(static_cast<uint64_t>(static_cast<int64_t>(value)) << 32));
  }
  // numerator / denominator rounded once (ties to even); saturates.
  static constexpr Fixed from_ratio(int64_t numerator, int64_t denominator) {
    bool saturated = false;
    const int64_t r = raw::divide_magnitudes((numerator < 0) != (denominator < 0),
                                             Wide{magnitude(numerator)} << raw::fraction_bits,
                                             magnitude(denominator), saturated);
    BITSTEP_FAULT_IF(saturated || denominator == 0, "from_ratio", "out of range or zero denominator", numerator,
                     denominator);
    return from_raw(r);
  }

  static constexpr Fixed max() { return from_raw(raw::max_raw); }
  static constexpr Fixed lowest() { return from_raw(raw::min_raw); }
  static constexpr Fixed ulp() { return from_raw(1); }
  static constexpr Fixed one() { return from_int(1); }

  constexpr int64_t raw() const { return raw_; }

  friend constexpr Fixed operator+(Fixed a, Fixed b) { return from_raw(raw::add(a.raw_, b.raw_)); }
  friend constexpr Fixed operator-(Fixed a, Fixed b) { return from_raw(raw::sub(a.raw_, b.raw_)); }
  friend constexpr Fixed operator-(Fixed a) { return from_raw(raw::sub(0, a.raw_)); }
  friend constexpr Fixed operator*(Fixed a, Fixed b) { return from_raw(raw::mul<Wide>(a.raw_, b.raw_)); }
  friend constexpr Fixed operator/(Fixed a, Fixed b) { return from_raw(raw::div<Wide>(a.raw_, b.raw_)); }
  constexpr Fixed& operator+=(Fixed b) { return *this = *this + b; }
  constexpr Fixed& operator-=(Fixed b) { return *this = *this - b; }
  constexpr Fixed& operator*=(Fixed b) { return *this = *this * b; }
  constexpr Fixed& operator/=(Fixed b) { return *this = *this / b; }

  friend constexpr bool operator==(Fixed a, Fixed b) = default;
  friend constexpr std::strong_ordering operator<=>(Fixed a, Fixed b) = default;

 private:
  int64_t raw_ = 0;
};

// |a|; |lowest()| saturates to max().
constexpr Fixed abs(Fixed a) {
  BITSTEP_FAULT_IF(a.raw() == raw::min_raw, "abs", "abs(lowest) saturated", a.raw(), 0);
  if (a.raw() == raw::min_raw) return Fixed::max();
  return a.raw() < 0 ? -a : a;
}
constexpr Fixed min(Fixed a, Fixed b) { return b < a ? b : a; }
constexpr Fixed max(Fixed a, Fixed b) { return a < b ? b : a; }
constexpr Fixed clamp(Fixed v, Fixed lo, Fixed hi) { return v < lo ? lo : (hi < v ? hi : v); }

// Largest integer <= a. Exact for every input.
constexpr Fixed floor(Fixed a) {
  return Fixed::from_raw(static_cast<int64_t>(static_cast<uint64_t>(a.raw()) & ~uint64_t{0xFFFFFFFF}));
}
// Smallest integer >= a; above 2^31 - 1 it saturates to max().
constexpr Fixed ceil(Fixed a) {
  constexpr int64_t largest_integer = int64_t{0x7FFFFFFF} << 32;
  BITSTEP_FAULT_IF(a.raw() > largest_integer, "ceil", "result out of range, saturated", a.raw(), 0);
  if (a.raw() > largest_integer) return Fixed::max();
  return floor(Fixed::from_raw(a.raw() + 0xFFFFFFFF));
}
// Nearest integer, ties to even (like every rounding in bitstep).
constexpr Fixed round(Fixed a) {
  const Fixed down = floor(a);
  const int64_t fraction = a.raw() - down.raw();  // 0 .. 2^32 - 1
  constexpr int64_t half = int64_t{1} << 31;
  const bool down_is_even = (static_cast<uint64_t>(down.raw()) & (uint64_t{1} << 32)) == 0;
  if (fraction < half || (fraction == half && down_is_even)) return down;
  return ceil(a);
}

// a * b + c, a * b / c: exact products, one rounding.
constexpr Fixed mul_add(Fixed a, Fixed b, Fixed c) { return Fixed::from_raw(raw::mul_add<Wide>(a.raw(), b.raw(), c.raw())); }
constexpr Fixed mul_div(Fixed a, Fixed b, Fixed c) { return Fixed::from_raw(raw::mul_div<Wide>(a.raw(), b.raw(), c.raw())); }

// The solver's forms: a * b and sum_i a_i b_i rounded once, without the
// saturation test, for operands the world envelope keeps far inside the
// range (raw::sum_products_in_range; the checked build still faults).
constexpr Fixed mul_in_range(Fixed a, Fixed b) { return Fixed::from_raw(raw::mul_in_range<Wide>(a.raw(), b.raw())); }
template <size_t N>
constexpr Fixed sum_products_in_range(const Fixed (&a)[N], const Fixed (&b)[N]) {
  raw::InRangeSum<Wide> sum;
  for (size_t i = 0; i < N; ++i) sum.add(a[i].raw(), b[i].raw());
  return Fixed::from_raw(sum.rounded());
}

// Square root, correctly rounded. sqrt of a negative value is 0.
Fixed sqrt(Fixed a);
// 1 / sqrt(a) within 1 ulp; a <= 0 saturates to max().
Fixed rsqrt(Fixed a);
// Angles in radians. sin, cos: within 1 ulp for every input (exact argument
// reduction with a 128-bit pi). tan: sin / cos from 62-bit intermediates.
Fixed sin(Fixed a);
Fixed cos(Fixed a);
Fixed tan(Fixed a);
// atan2 in [-pi, pi], atan2(0, 0) = 0; asin, acos clamp their input to [-1, 1].
Fixed atan2(Fixed y, Fixed x);
Fixed asin(Fixed a);
Fixed acos(Fixed a);

}  // namespace bitstep
