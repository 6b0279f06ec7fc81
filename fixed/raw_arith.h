// Raw Q32.32 arithmetic on int64_t, written once over a 128-bit backend `U`
// (NativeU128 or PortableU128). A raw value R stands for R * 2^-32.
//
// Every operation here is exact up to one final rounding (to nearest, ties to
// even) and saturates to INT64_MAX / INT64_MIN when the rounded result does not
// fit. Nothing here has undefined behaviour: signed values are handled as
// sign + unsigned magnitude, or as two's complement in unsigned words.
#pragma once

#include <cstddef>
#include <cstdint>
#include <type_traits>

#include "fixed/checked.h"
#include "fixed/u128.h"

namespace bitstep::raw {

inline constexpr int64_t max_raw = INT64_MAX;
inline constexpr int64_t min_raw = INT64_MIN;
inline constexpr int fraction_bits = 32;

// magnitude >> shift, rounded to nearest with ties to even. 0 < shift < 128.
template <class U>
constexpr U round_shift(U magnitude, int shift) {
  const U one{1};
  const U half = one << (shift - 1);
  const U remainder = magnitude & ((one << shift) - one);
  U quotient = magnitude >> shift;
  if (remainder > half || (remainder == half && (quotient.lo() & 1u) != 0)) quotient = quotient + one;
  return quotient;
}

// A signed result given as sign + magnitude, saturated into int64_t.
template <class U>
constexpr int64_t signed_saturate(bool negative, U magnitude, bool& saturated) {
  constexpr uint64_t limit_positive = uint64_t{1} << 63;  // exclusive
  if (negative) {
    if (magnitude.hi() != 0 || magnitude.lo() > limit_positive) {
      saturated = true;
      return min_raw;
    }
    return static_cast<int64_t>(uint64_t{0} - magnitude.lo());
  }
  if (magnitude.hi() != 0 || magnitude.lo() >= limit_positive) {
    saturated = true;
    return max_raw;
  }
  return static_cast<int64_t>(magnitude.lo());
}

// a * b exactly, as a two's complement 128-bit value (|a*b| <= 2^126 fits).
template <class U>
constexpr U signed_product(int64_t a, int64_t b) {
  const U p = U::mul(magnitude(a), magnitude(b));
  return (a < 0) != (b < 0) ? -p : p;
}

#if defined(BITSTEP_HAS_NATIVE_128)
// The native backend's fast path: signed 128-bit sums of products, rounded
// straight from two's complement. floor((s + 2^31 - 1 + lsb) / 2^32), where
// lsb is bit 32 of s (the parity of floor(s / 2^32)), is s / 2^32 rounded to
// nearest with ties to even; >> on a signed value is a floor in C++20.
// Bit-identical to the generic path (tests/fixed/u128_tests.cpp compares them).
__extension__ typedef __int128 native_i128;
__extension__ typedef unsigned __int128 native_u128;

// hi:lo + 2^31 - 1 + lsb in place, the carry into hi.
constexpr void bias_q64_parts(uint64_t& hi, uint64_t& lo) {
  const uint64_t biased = lo + ((uint64_t{1} << 31) - 1) + ((lo >> 32) & 1u);
  if (biased < lo) ++hi;  // carry
  lo = biased;
}

// On x86-64 (GCC, Clang) each signed 64 x 64 product is one widening `imul`
// (rdx:rax = rax * src, signed 128-bit) and the rounding four instructions;
// the plain C++ stays for constant evaluation and every other target. The
// compilers turned about half of the solver's __int128 products into a
// `mul` and two correcting `imul`s once they had hoisted the sign word of a
// shared factor (an impulse times each component of a row). Same bits:
// tests/fixed/u128_tests.cpp compares both forms and the portable backend.

// a b, the exact signed 128-bit product (|a b| <= 2^126).
constexpr native_i128 wide_product(int64_t a, int64_t b) {
#if defined(__x86_64__)
  if (!std::is_constant_evaluated()) {
    uint64_t hi = 0, lo = 0;
    __asm__("imulq %[b]" : "=a"(lo), "=d"(hi) : "a"(a), [b] "rm"(b) : "cc");
    return static_cast<native_i128>((native_u128{hi} << 64) | lo);
  }
#endif
  return native_i128{a} * b;
}

// The low 64 bits of (hi:lo + 2^31 - 1 + lsb) >> 32, hi left biased (its
// carry added): bias_q64_parts and the shift. On x86-64 `bt` puts the lsb
// (bit 32 of lo) in the carry flag, `adc` adds it and the bias to lo and
// `adc` the carry to hi, and `shrd` shifts the pair.
constexpr uint64_t bias_shift_q64_parts(uint64_t& hi, uint64_t lo) {
#if defined(__x86_64__)
  if (!std::is_constant_evaluated()) {
    __asm__("btq $32, %[lo]\n\t"
            "adcq $0x7fffffff, %[lo]\n\t"
            "adcq $0, %[hi]\n\t"
            "shrdq $32, %[hi], %[lo]"
            : [lo] "+r"(lo), [hi] "+r"(hi)
            :
            : "cc");
    return lo;
  }
#endif
  bias_q64_parts(hi, lo);
  return (hi << 32) | (lo >> 32);
}

constexpr int64_t round_q64_parts(uint64_t hi, uint64_t lo, bool& saturated) {
  const uint64_t shifted = bias_shift_q64_parts(hi, lo);
  // floor((hi:lo) / 2^32) = hi 2^32 + (lo >> 32) fits in int64 iff hi is in [-2^31, 2^31).
  const int64_t top = static_cast<int64_t>(hi);
  if ((top >> 31) != 0 && (top >> 31) != -1) {
    saturated = true;
    return top < 0 ? min_raw : max_raw;
  }
  return static_cast<int64_t>(shifted);
}

constexpr int64_t round_q64_native(native_i128 s, bool& saturated) {
  const auto u = static_cast<native_u128>(s);
  return round_q64_parts(static_cast<uint64_t>(u >> 64), static_cast<uint64_t>(u), saturated);
}

// a b as the signed 128-bit product (one imul on x86-64), rounded.
constexpr int64_t mul_native(int64_t a, int64_t b, bool& saturated) {
  return round_q64_native(wide_product(a, b), saturated);
}

// a0 b0 + a1 b1 + a2 b2 (terms with zero factors allowed), false when the
// 128-bit sum overflows (only near |operands| = 2^63; the caller falls back).
constexpr bool sum_products_native(int64_t a0, int64_t b0, int64_t a1, int64_t b1, int64_t a2, int64_t b2,
                                   native_i128& sum) {
  const native_i128 p0 = wide_product(a0, b0), p1 = wide_product(a1, b1), p2 = wide_product(a2, b2);
  native_i128 partial = 0;
  const bool o1 = __builtin_add_overflow(p0, p1, &partial);
  const bool o2 = __builtin_add_overflow(partial, p2, &sum);
  return !(o1 || o2);
}

template <class U>
inline constexpr bool use_native_fast_path = std::is_same_v<U, NativeU128>;
#else
template <class U>
inline constexpr bool use_native_fast_path = false;
#endif

// An exact signed sum of 128-bit terms. Signed overflow of the 128-bit sum is
// counted, so the sum is exact for any number of terms: true value =
// sum + wraps * 2^128. Only a final `wraps != 0` makes the result saturate.
// The native backend forms its terms as __int128 products, counts a wrap
// from the compiler's signed overflow test, and rounds from two's
// complement (round_q64_parts): the same sum, wraps and bits as the generic
// path (tests/fixed/u128_tests.cpp compares them), a third of the work.
template <class U>
struct Accumulator {
  U sum{};
  int wraps = 0;

  constexpr void add(U term) {
    const U next = sum + term;
    const bool term_negative = top_bit(term);
    if (top_bit(sum) == term_negative && top_bit(next) != term_negative) wraps += term_negative ? -1 : 1;
    sum = next;
  }
  constexpr void add_product(int64_t a, int64_t b) {
#if defined(BITSTEP_HAS_NATIVE_128)
    if constexpr (use_native_fast_path<U>) return add_native(wide_product(a, b));
#endif
    add(signed_product<U>(a, b));
  }
  constexpr void sub_product(int64_t a, int64_t b) {
#if defined(BITSTEP_HAS_NATIVE_128)
    if constexpr (use_native_fast_path<U>) return add_native(-wide_product(a, b));  // |a b| <= 2^126
#endif
    add(-signed_product<U>(a, b));
  }
  // A raw Q32.32 value c joins a sum of raw products (Q64.64) as c << 32.
  constexpr void add_raw(int64_t c) {
#if defined(BITSTEP_HAS_NATIVE_128)
    if constexpr (use_native_fast_path<U>) return add_native(native_i128{c} * (int64_t{1} << fraction_bits));
#endif
    const U wide = U{magnitude(c)} << fraction_bits;
    add(c < 0 ? -wide : wide);
  }

  // The sum of Q64.64 products rounded once to Q32.32.
  constexpr int64_t to_raw(bool& saturated) const {
    if (wraps != 0) {
      saturated = true;
      return wraps > 0 ? max_raw : min_raw;
    }
#if defined(BITSTEP_HAS_NATIVE_128)
    if constexpr (use_native_fast_path<U>) return round_q64_parts(sum.hi(), sum.lo(), saturated);
#endif
    const bool negative = top_bit(sum);
    const U magnitude = negative ? -sum : sum;
    return signed_saturate(negative, round_shift(magnitude, fraction_bits), saturated);
  }

#if defined(BITSTEP_HAS_NATIVE_128)
 private:
  // sum += term with a wrap counted in the direction of the term's sign,
  // as add() counts it.
  constexpr void add_native(native_i128 term) {
    const auto before = static_cast<native_i128>((native_u128{sum.hi()} << 64) | sum.lo());
    native_i128 next = 0;
    if (__builtin_add_overflow(before, term, &next)) wraps += term < 0 ? -1 : 1;
    const auto bits = static_cast<native_u128>(next);
    sum = U{static_cast<uint64_t>(bits >> 64), static_cast<uint64_t>(bits)};
  }
#endif
};

template <class U>
constexpr int64_t mul(int64_t a, int64_t b) {
  bool saturated = false;
  int64_t r = 0;
#if defined(BITSTEP_HAS_NATIVE_128)
  if constexpr (use_native_fast_path<U>) {
    r = mul_native(a, b, saturated);
  } else
#endif
  {
    const U product = U::mul(magnitude(a), magnitude(b));
    r = signed_saturate((a < 0) != (b < 0), round_shift(product, fraction_bits), saturated);
  }
  BITSTEP_FAULT_IF(saturated, "mul", "result out of range, saturated", a, b);
  return r;
}

// round(numerator / divisor) for magnitudes, ties to even, then signed and
// saturated. A zero divisor saturates (0 / 0 = 0).
template <class U>
constexpr int64_t divide_magnitudes(bool negative, U numerator, uint64_t divisor, bool& saturated) {
  if (divisor == 0) {
    if (numerator == U{0}) return 0;
    saturated = true;
    return negative ? min_raw : max_raw;
  }
  if (numerator.hi() >= divisor) {  // quotient >= 2^64
    saturated = true;
    return negative ? min_raw : max_raw;
  }
  uint64_t remainder = 0;
  uint64_t quotient = numerator.divrem(divisor, remainder);
  const uint64_t rest = divisor - remainder;  // remainder < divisor, so 2r vs d is r vs d - r
  if (remainder > rest || (remainder == rest && (quotient & 1u) != 0)) {
    if (quotient == UINT64_MAX) {
      saturated = true;
      return negative ? min_raw : max_raw;
    }
    ++quotient;
  }
  return signed_saturate(negative, U{quotient}, saturated);
}

// (a << 32) / b: the numerator is at most 2^95, exact in 128 bits.
template <class U>
constexpr int64_t div(int64_t a, int64_t b) {
  bool saturated = false;
  const int64_t r =
      divide_magnitudes((a < 0) != (b < 0), U{magnitude(a)} << fraction_bits, magnitude(b), saturated);
  BITSTEP_FAULT_IF(b == 0, "div", "division by zero", a, b);
  BITSTEP_FAULT_IF(saturated, "div", "result out of range, saturated", a, b);
  return r;
}

// a * b / c with the exact 128-bit product, rounded once.
template <class U>
constexpr int64_t mul_div(int64_t a, int64_t b, int64_t c) {
  bool saturated = false;
  const bool negative = ((a < 0) != (b < 0)) != (c < 0);
  const int64_t r = divide_magnitudes(negative, U::mul(magnitude(a), magnitude(b)), magnitude(c), saturated);
  BITSTEP_FAULT_IF(c == 0, "mul_div", "division by zero", a, c);
  BITSTEP_FAULT_IF(saturated, "mul_div", "result out of range, saturated", a, b);
  return r;
}

// a * b + c rounded once.
template <class U>
constexpr int64_t mul_add(int64_t a, int64_t b, int64_t c) {
  Accumulator<U> sum;
  sum.add_product(a, b);
  sum.add_raw(c);
  bool saturated = false;
  const int64_t r = sum.to_raw(saturated);
  BITSTEP_FAULT_IF(saturated, "mul_add", "result out of range, saturated", a, b);
  return r;
}

// dot3 through the exact accumulator: any operands.
template <class U>
[[gnu::noinline]] constexpr int64_t dot3_accumulated(int64_t a0, int64_t b0, int64_t a1, int64_t b1, int64_t a2,
                                                     int64_t b2) {
  Accumulator<U> sum;
  sum.add_product(a0, b0);
  sum.add_product(a1, b1);
  sum.add_product(a2, b2);
  bool saturated = false;
  const int64_t r = sum.to_raw(saturated);
  BITSTEP_FAULT_IF(saturated, "dot", "result out of range, saturated", a0, b0);
  return r;
}

// a0 b0 + a1 b1 + a2 b2 rounded once. With native 128-bit products the
// common case (no 128-bit overflow) is inlined always: out of line, the
// call's register saves cost about what its three products do; the rare
// rest goes through the accumulator out of line.
template <class U>
[[gnu::always_inline]] constexpr int64_t dot3(int64_t a0, int64_t b0, int64_t a1, int64_t b1, int64_t a2, int64_t b2) {
#if defined(BITSTEP_HAS_NATIVE_128)
  if constexpr (use_native_fast_path<U>) {
    native_i128 s = 0;
    if (sum_products_native(a0, b0, a1, b1, a2, b2, s)) {
      bool saturated = false;
      const int64_t r = round_q64_native(s, saturated);
      BITSTEP_FAULT_IF(saturated, "dot", "result out of range, saturated", a0, b0);
      return r;
    }
  }
#endif
  return dot3_accumulated<U>(a0, b0, a1, b1, a2, b2);
}

// a b - c d rounded once (one component of a cross product).
template <class U>
constexpr int64_t mul_sub_mul(int64_t a, int64_t b, int64_t c, int64_t d) {
#if defined(BITSTEP_HAS_NATIVE_128)
  if constexpr (use_native_fast_path<U>) {
    // The 128-bit difference never overflows: a product of two int64 lies
    // in [-2^126 + 2^63, 2^126], so a b - c d lies in
    // [-2^127 + 2^63, 2^127 - 2^63], inside the signed 128-bit range, for
    // every operand (INT64_MIN included).
    bool saturated = false;
    const int64_t r = round_q64_native(wide_product(a, b) - wide_product(c, d), saturated);
    BITSTEP_FAULT_IF(saturated, "cross", "result out of range, saturated", a, b);
    return r;
  }
#endif
  Accumulator<U> sum;
  sum.add_product(a, b);
  sum.sub_product(c, d);
  bool saturated = false;
  const int64_t r = sum.to_raw(saturated);
  BITSTEP_FAULT_IF(saturated, "cross", "result out of range, saturated", a, b);
  return r;
}

// The solver's forms (core/solver_rows.h): sum_i a_i b_i rounded once like
// dot3 (and a b like mul), without the saturation test, for operands that
// the world envelope keeps far inside the range. In range the result is
// bit-identical to dot3 / mul. Out of range it is the low 64 bits of the
// rounded sum (every backend the same bits), and the checked build faults.
// Products are added one at a time, so callers pass them straight from their
// own fields (an array copied in first went through the stack).
template <class U>
class InRangeSum {
 public:
  constexpr void add(int64_t a, int64_t b) {
#if defined(BITSTEP_HAS_NATIVE_128)
    if constexpr (use_native_fast_path<U>) {
      // Two's complement mod 2^128: each product fits (|a b| <= 2^126), the
      // sum wraps without undefined behaviour in unsigned arithmetic.
      native_ += static_cast<native_u128>(wide_product(a, b));
    } else
#endif
    {
      sum_ = sum_ + signed_product<U>(a, b);
    }
    if constexpr (checked_build) {
      if (terms_++ == 0) {
        first_a_ = a;
        first_b_ = b;
      }
      exact_.add_product(a, b);
    }
  }

  constexpr int64_t rounded() const {
    uint64_t result = 0;
#if defined(BITSTEP_HAS_NATIVE_128)
    if constexpr (use_native_fast_path<U>) {
      // (sum + bias) >> 32 in 64-bit words: the low word biased, its carry
      // into the high word, and the low 64 bits of the shifted result.
      uint64_t hi = static_cast<uint64_t>(native_ >> 64);
      result = bias_shift_q64_parts(hi, static_cast<uint64_t>(native_));
    } else
#endif
    {
      const uint64_t bias = ((uint64_t{1} << 31) - 1) + ((sum_.lo() >> 32) & 1u);
      result = ((sum_ + U{bias}) >> fraction_bits).lo();
    }
    if constexpr (checked_build) {
      bool saturated = false;
      exact_.to_raw(saturated);
      BITSTEP_FAULT_IF(saturated, "sum_products_in_range", "result out of range", first_a_, first_b_);
    }
    return static_cast<int64_t>(result);
  }

 private:
#if defined(BITSTEP_HAS_NATIVE_128)
  native_u128 native_ = 0;
#endif
  U sum_{};
  // The checked build's exact sum and first operands (for the fault report).
  Accumulator<U> exact_;
  int terms_ = 0;
  int64_t first_a_ = 0, first_b_ = 0;
};

template <class U, size_t N>
constexpr int64_t sum_products_in_range(const int64_t (&a)[N], const int64_t (&b)[N]) {
  InRangeSum<U> sum;
  for (size_t i = 0; i < N; ++i) sum.add(a[i], b[i]);
  return sum.rounded();
}

template <class U>
constexpr int64_t mul_in_range(int64_t a, int64_t b) {
  InRangeSum<U> sum;
  sum.add(a, b);
  return sum.rounded();
}

// a + b and a - b wrap modulo 2^64 (two's complement), computed in uint64_t.
constexpr int64_t add(int64_t a, int64_t b) {
  const int64_t r = static_cast<int64_t>(static_cast<uint64_t>(a) + static_cast<uint64_t>(b));
  BITSTEP_FAULT_IF((a < 0) == (b < 0) && (r < 0) != (a < 0), "add", "overflow, wrapped", a, b);
  return r;
}
constexpr int64_t sub(int64_t a, int64_t b) {
  const int64_t r = static_cast<int64_t>(static_cast<uint64_t>(a) - static_cast<uint64_t>(b));
  BITSTEP_FAULT_IF((a < 0) != (b < 0) && (r < 0) != (a < 0), "sub", "overflow, wrapped", a, b);
  return r;
}

}  // namespace bitstep::raw
