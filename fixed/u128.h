// Unsigned 128-bit integers with wrapping arithmetic, in two interchangeable
// implementations: `NativeU128` on the compiler's `unsigned __int128` and
// `PortableU128` on 32-bit limbs (schoolbook multiply, Knuth's algorithm D for
// 128/64 division, after Hacker's Delight `divlu`). Both expose the same
// operations, every algorithm in fixed/ is written once as a template over
// them, and tests/fixed/u128_tests.cpp proves them equal bit for bit.
//
// `Wide` is the one the library uses: native where the compiler has it,
// portable when BITSTEP_PORTABLE_128 is defined or on targets without __int128
// (i686, 32-bit ARM).
#pragma once

#include <bit>
#include <cstdint>
#include <type_traits>

namespace bitstep {

class PortableU128 {
 public:
  constexpr PortableU128() = default;
  constexpr PortableU128(uint64_t value) : lo_(value) {}  // NOLINT: widening is lossless
  constexpr PortableU128(uint64_t hi, uint64_t lo) : hi_(hi), lo_(lo) {}

  constexpr uint64_t hi() const { return hi_; }
  constexpr uint64_t lo() const { return lo_; }

  // Full 64 x 64 -> 128 product from four 32 x 32 -> 64 partial products.
  static constexpr PortableU128 mul(uint64_t a, uint64_t b) {
    const uint64_t a0 = a & 0xFFFFFFFFu, a1 = a >> 32;
    const uint64_t b0 = b & 0xFFFFFFFFu, b1 = b >> 32;
    const uint64_t p00 = a0 * b0, p01 = a0 * b1, p10 = a1 * b0, p11 = a1 * b1;
    // The middle column can carry: (2^32-1) + 2 (2^32-1) < 2^34, no overflow.
    const uint64_t middle = (p00 >> 32) + (p01 & 0xFFFFFFFFu) + (p10 & 0xFFFFFFFFu);
    return {p11 + (p01 >> 32) + (p10 >> 32) + (middle >> 32), (middle << 32) | (p00 & 0xFFFFFFFFu)};
  }

  // Quotient and remainder of this / divisor. Precondition: hi() < divisor, so
  // that the quotient fits in 64 bits (callers check it and saturate first).
  // Knuth's algorithm D with two 32-bit quotient digits (Hacker's Delight, divlu).
  constexpr uint64_t divrem(uint64_t divisor, uint64_t& remainder) const {
    constexpr uint64_t base = uint64_t{1} << 32;
    const int shift = std::countl_zero(divisor);  // normalise: top bit of v set
    const uint64_t v = divisor << shift;
    const uint64_t vn1 = v >> 32, vn0 = v & 0xFFFFFFFFu;
    const uint64_t un32 = shift == 0 ? hi_ : (hi_ << shift) | (lo_ >> (64 - shift));
    const uint64_t un10 = lo_ << shift;
    const uint64_t un1 = un10 >> 32, un0 = un10 & 0xFFFFFFFFu;

    uint64_t q1 = un32 / vn1;
    uint64_t rhat = un32 - q1 * vn1;
    while (q1 >= base || q1 * vn0 > base * rhat + un1) {
      --q1;
      rhat += vn1;
      if (rhat >= base) break;
    }
    const uint64_t un21 = un32 * base + un1 - q1 * v;  // wraps: only the low 64 bits are live

    uint64_t q0 = un21 / vn1;
    rhat = un21 - q0 * vn1;
    while (q0 >= base || q0 * vn0 > base * rhat + un0) {
      --q0;
      rhat += vn1;
      if (rhat >= base) break;
    }
    remainder = (un21 * base + un0 - q0 * v) >> shift;
    return q1 * base + q0;
  }

  friend constexpr PortableU128 operator+(PortableU128 a, PortableU128 b) {
    const uint64_t lo = a.lo_ + b.lo_;
    return {a.hi_ + b.hi_ + (lo < a.lo_ ? 1u : 0u), lo};
  }
  friend constexpr PortableU128 operator-(PortableU128 a, PortableU128 b) {
    return {a.hi_ - b.hi_ - (a.lo_ < b.lo_ ? 1u : 0u), a.lo_ - b.lo_};
  }
  friend constexpr PortableU128 operator-(PortableU128 a) { return PortableU128{} - a; }
  // Shifts take 0 <= n < 128.
  friend constexpr PortableU128 operator<<(PortableU128 a, int n) {
    if (n == 0) return a;
    if (n >= 64) return {a.lo_ << (n - 64), 0};
    return {(a.hi_ << n) | (a.lo_ >> (64 - n)), a.lo_ << n};
  }
  friend constexpr PortableU128 operator>>(PortableU128 a, int n) {
    if (n == 0) return a;
    if (n >= 64) return {0, a.hi_ >> (n - 64)};
    return {a.hi_ >> n, (a.lo_ >> n) | (a.hi_ << (64 - n))};
  }
  friend constexpr PortableU128 operator&(PortableU128 a, PortableU128 b) {
    return {a.hi_ & b.hi_, a.lo_ & b.lo_};
  }
  friend constexpr PortableU128 operator|(PortableU128 a, PortableU128 b) {
    return {a.hi_ | b.hi_, a.lo_ | b.lo_};
  }
  friend constexpr bool operator==(PortableU128 a, PortableU128 b) = default;
  friend constexpr bool operator<(PortableU128 a, PortableU128 b) {
    return a.hi_ != b.hi_ ? a.hi_ < b.hi_ : a.lo_ < b.lo_;
  }
  friend constexpr bool operator>(PortableU128 a, PortableU128 b) { return b < a; }
  friend constexpr bool operator<=(PortableU128 a, PortableU128 b) { return !(b < a); }
  friend constexpr bool operator>=(PortableU128 a, PortableU128 b) { return !(a < b); }

 private:
  uint64_t hi_ = 0;
  uint64_t lo_ = 0;
};

#if defined(__SIZEOF_INT128__)
#define BITSTEP_HAS_NATIVE_128 1

class NativeU128 {
 public:
  __extension__ typedef unsigned __int128 u128;

  constexpr NativeU128() = default;
  constexpr NativeU128(uint64_t value) : v_(value) {}  // NOLINT: widening is lossless
  constexpr NativeU128(uint64_t hi, uint64_t lo) : v_((u128{hi} << 64) | lo) {}

  constexpr uint64_t hi() const { return static_cast<uint64_t>(v_ >> 64); }
  constexpr uint64_t lo() const { return static_cast<uint64_t>(v_); }

  static constexpr NativeU128 mul(uint64_t a, uint64_t b) { return from(u128{a} * b); }

  // Precondition: hi() < divisor. The remainder fits in 64 bits, so its low
  // word is all of it.
  //
  // On x86-64 one `div` instruction divides the 128-bit rdx:rax by a 64-bit
  // divisor when the quotient fits in 64 bits, which is exactly hi() <
  // divisor; the compiler's u128 / u64 instead calls __udivti3 (a general
  // 128/128 routine). Same quotient and remainder; the plain division stays
  // for constant evaluation and for any operand outside the precondition
  // (where `div` would fault).
  constexpr uint64_t divrem(uint64_t divisor, uint64_t& remainder) const {
#if defined(__x86_64__)
    if (!std::is_constant_evaluated() && hi() < divisor) {
      uint64_t quotient = 0;
      __asm__("divq %[divisor]"
              : "=a"(quotient), "=d"(remainder)
              : "a"(lo()), "d"(hi()), [divisor] "rm"(divisor)
              : "cc");
      return quotient;
    }
#endif
    const uint64_t quotient = static_cast<uint64_t>(v_ / divisor);
    remainder = lo() - quotient * divisor;
    return quotient;
  }

  friend constexpr NativeU128 operator+(NativeU128 a, NativeU128 b) { return from(a.v_ + b.v_); }
  friend constexpr NativeU128 operator-(NativeU128 a, NativeU128 b) { return from(a.v_ - b.v_); }
  friend constexpr NativeU128 operator-(NativeU128 a) { return from(-a.v_); }
  friend constexpr NativeU128 operator<<(NativeU128 a, int n) { return from(a.v_ << n); }
  friend constexpr NativeU128 operator>>(NativeU128 a, int n) { return from(a.v_ >> n); }
  friend constexpr NativeU128 operator&(NativeU128 a, NativeU128 b) { return from(a.v_ & b.v_); }
  friend constexpr NativeU128 operator|(NativeU128 a, NativeU128 b) { return from(a.v_ | b.v_); }
  friend constexpr bool operator==(NativeU128 a, NativeU128 b) = default;
  friend constexpr bool operator<(NativeU128 a, NativeU128 b) { return a.v_ < b.v_; }
  friend constexpr bool operator>(NativeU128 a, NativeU128 b) { return a.v_ > b.v_; }
  friend constexpr bool operator<=(NativeU128 a, NativeU128 b) { return a.v_ <= b.v_; }
  friend constexpr bool operator>=(NativeU128 a, NativeU128 b) { return a.v_ >= b.v_; }

 private:
  static constexpr NativeU128 from(u128 v) {
    NativeU128 r;
    r.v_ = v;
    return r;
  }
  u128 v_ = 0;
};
#endif

#if defined(BITSTEP_PORTABLE_128) || !defined(BITSTEP_HAS_NATIVE_128)
using Wide = PortableU128;
inline constexpr const char* wide_backend_name = "portable";
#else
using Wide = NativeU128;
inline constexpr const char* wide_backend_name = "native";
#endif

// Helpers shared by both backends.

template <class U>
constexpr bool top_bit(U v) {
  return (v.hi() >> 63) != 0;
}

template <class U>
constexpr int count_leading_zeros(U v) {
  return v.hi() != 0 ? std::countl_zero(v.hi()) : 64 + std::countl_zero(v.lo());
}

// |v| of a signed 64-bit value as an unsigned magnitude; |INT64_MIN| = 2^63 fits.
constexpr uint64_t magnitude(int64_t v) {
  const uint64_t u = static_cast<uint64_t>(v);
  return v < 0 ? uint64_t{0} - u : u;
}

}  // namespace bitstep
