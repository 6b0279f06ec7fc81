// A signed big integer, sign and magnitude over BigUint (fixed/big_uint.h),
// for the exact sums of cold paths: the inverse of a 3x3 matrix
// (fixed/mat33.cpp) and a hull's mass properties (core/convex_hull.cpp).
// Zero may carry either sign. Simple, not fast.
#pragma once

#include <cstdint>

#include "fixed/big_uint.h"

namespace bitstep {

template <int Limbs>
struct BigInt {
  BigUint<Limbs> magnitude;
  bool negative = false;

  static constexpr BigInt from_i64(int64_t v) {
    const uint64_t m = v < 0 ? uint64_t{0} - static_cast<uint64_t>(v) : static_cast<uint64_t>(v);
    return {BigUint<Limbs>::from_u64(m), v < 0};
  }

  friend constexpr BigInt operator-(BigInt a) {
    a.negative = !a.negative;
    return a;
  }
  friend constexpr BigInt operator+(BigInt a, BigInt b) {
    if (a.negative == b.negative) {
      a.magnitude.add(b.magnitude);
      return a;
    }
    if (a.magnitude.compare(b.magnitude) >= 0) {
      a.magnitude.subtract(b.magnitude);
      return a;
    }
    b.magnitude.subtract(a.magnitude);
    return b;
  }
  friend constexpr BigInt operator-(const BigInt& a, const BigInt& b) { return a + -b; }
  friend constexpr BigInt operator*(const BigInt& a, const BigInt& b) {
    return {a.magnitude * b.magnitude, a.negative != b.negative};
  }
};

}  // namespace bitstep
