// A small fixed-capacity unsigned big integer on 32-bit limbs, constexpr, for
// exact decimal parsing (fixed/decimal.h) and the exact inverse of 3x3
// matrices (fixed/mat33.cpp). Cold paths only: simple, not fast.
#pragma once

#include <cstddef>
#include <cstdint>

namespace bitstep {

template <int Limbs>
struct BigUint {
  uint32_t limb[static_cast<size_t>(Limbs)] = {};  // little-endian
  bool overflow = false;               // set when a result exceeded the capacity

  static constexpr BigUint from_u64(uint64_t v) {
    BigUint r;
    r.limb[0] = static_cast<uint32_t>(v);
    r.limb[1] = static_cast<uint32_t>(v >> 32);
    return r;
  }

  constexpr bool is_zero() const {
    for (uint32_t l : limb) {
      if (l != 0) return false;
    }
    return true;
  }

  // Number of significant bits (0 for zero).
  constexpr int bit_length() const {
    for (int i = Limbs - 1; i >= 0; --i) {
      if (limb[i] != 0) {
        int bits = 32;
        while ((limb[i] >> (bits - 1)) == 0) --bits;
        return i * 32 + bits;
      }
    }
    return 0;
  }

  constexpr void mul_small(uint32_t m) {
    uint64_t carry = 0;
    for (uint32_t& l : limb) {
      const uint64_t t = uint64_t{l} * m + carry;
      l = static_cast<uint32_t>(t);
      carry = t >> 32;
    }
    if (carry != 0) overflow = true;
  }

  constexpr void add_small(uint32_t a) {
    uint64_t carry = a;
    for (uint32_t& l : limb) {
      if (carry == 0) break;
      const uint64_t t = uint64_t{l} + carry;
      l = static_cast<uint32_t>(t);
      carry = t >> 32;
    }
    if (carry != 0) overflow = true;
  }

  constexpr void mul_pow10(int n) {
    for (int i = 0; i < n; ++i) mul_small(10);
  }

  constexpr void shift_left(int bits) {
    if (bits >= Limbs * 32) {
      if (!is_zero()) overflow = true;
      for (uint32_t& l : limb) l = 0;
      return;
    }
    if (bit_length() + bits > Limbs * 32) overflow = true;
    const int words = bits / 32, rest = bits % 32;
    for (int i = Limbs - 1; i >= 0; --i) {
      const int from = i - words;
      uint64_t v = from >= 0 ? uint64_t{limb[from]} << rest : 0;
      if (rest != 0 && from - 1 >= 0) v |= uint64_t{limb[from - 1]} >> (32 - rest);
      limb[i] = static_cast<uint32_t>(v);
    }
  }

  constexpr void shift_right_one() {
    for (int i = 0; i < Limbs; ++i) {
      const uint32_t high = i + 1 < Limbs ? limb[i + 1] << 31 : 0;
      limb[i] = (limb[i] >> 1) | high;
    }
  }

  // -1, 0, 1 as this <, ==, > other.
  constexpr int compare(const BigUint& other) const {
    for (int i = Limbs - 1; i >= 0; --i) {
      if (limb[i] != other.limb[i]) return limb[i] < other.limb[i] ? -1 : 1;
    }
    return 0;
  }

  // this -= other; precondition this >= other.
  constexpr void subtract(const BigUint& other) {
    int64_t borrow = 0;
    for (int i = 0; i < Limbs; ++i) {
      int64_t t = int64_t{limb[i]} - int64_t{other.limb[i]} - borrow;
      borrow = t < 0 ? 1 : 0;
      if (t < 0) t += int64_t{1} << 32;
      limb[i] = static_cast<uint32_t>(t);
    }
  }

  constexpr void add(const BigUint& other) {
    uint64_t carry = 0;
    for (int i = 0; i < Limbs; ++i) {
      const uint64_t t = uint64_t{limb[i]} + other.limb[i] + carry;
      limb[i] = static_cast<uint32_t>(t);
      carry = t >> 32;
    }
    if (carry != 0) overflow = true;
  }

  // Product truncated to the capacity (overflow flagged).
  friend constexpr BigUint operator*(const BigUint& a, const BigUint& b) {
    BigUint r;
    r.overflow = a.overflow || b.overflow;
    for (int i = 0; i < Limbs; ++i) {
      if (a.limb[i] == 0) continue;
      uint64_t carry = 0;
      for (int j = 0; j < Limbs; ++j) {
        if (i + j >= Limbs) {
          if (b.limb[j] != 0) r.overflow = true;
          continue;
        }
        const uint64_t t = uint64_t{a.limb[i]} * b.limb[j] + r.limb[i + j] + carry;
        r.limb[i + j] = static_cast<uint32_t>(t);
        carry = t >> 32;
      }
      if (carry != 0) r.overflow = true;
    }
    return r;
  }
};

// The quotient of numerator / denominator, which the caller knows to be below
// 2^quotient_bits (quotient_bits <= 64), by restoring binary long division;
// `remainder` receives what is left. The denominator must be non-zero.
template <int Limbs>
constexpr uint64_t divide_small_quotient(const BigUint<Limbs>& numerator, const BigUint<Limbs>& denominator,
                                         int quotient_bits, BigUint<Limbs>& remainder) {
  remainder = numerator;
  uint64_t quotient = 0;
  for (int bit = quotient_bits - 1; bit >= 0; --bit) {
    BigUint<Limbs> shifted = denominator;
    shifted.shift_left(bit);
    if (remainder.compare(shifted) >= 0) {
      remainder.subtract(shifted);
      quotient |= uint64_t{1} << bit;
    }
  }
  return quotient;
}

}  // namespace bitstep
