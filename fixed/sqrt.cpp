// Integer square roots without floating point: a table seed, Newton's method
// from above in 64 bits, one 128/64 Newton step, and an exact repair. Every
// result is then rounded from exact integer remainders.
#include <array>
#include <cstddef>

#include "fixed/fixed.h"
#include "fixed/raw_math.h"

namespace bitstep::raw {

namespace {

// Bit-by-bit floor(sqrt(n)) for the compile-time seed table only.
constexpr uint64_t isqrt_bitwise(uint64_t n) {
  uint64_t root = 0;
  for (uint64_t bit = uint64_t{1} << 62; bit != 0; bit >>= 2) {
    if (n >= root + bit) {
      n -= root + bit;
      root = (root >> 1) + bit;
    } else {
      root >>= 1;
    }
  }
  return root;
}

// For t in [2^62, 2^64) and i = t >> 55 (128..511): an upper bound of
// sqrt(t), ceil(sqrt((i + 1) 2^55)), good to 1/256 (sqrt((i + 1) / i) - 1
// <= 1 / 2i; 8 bits), in 3 KiB.
constexpr std::array<uint64_t, 384> make_sqrt_seeds() {
  std::array<uint64_t, 384> seeds{};
  for (size_t i = 128; i < 512; ++i) {
    if (i == 511) {
      seeds[i - 128] = uint64_t{1} << 32;  // sqrt(2^64)
      continue;
    }
    const uint64_t top = (uint64_t{i} + 1) << 55;
    const uint64_t root = isqrt_bitwise(top);
    seeds[i - 128] = root * root == top ? root : root + 1;
  }
  return seeds;
}
constexpr std::array<uint64_t, 384> sqrt_seeds = make_sqrt_seeds();

}  // namespace

template <class U>
uint64_t isqrt_floor(U n) {
  if (n == U{0}) return 0;
  // Scale by an even power of two so that m >= 2^126; sqrt scales by half the power.
  const int shift = count_leading_zeros(n) & ~1;
  const U m = n << shift;
  const uint64_t t = m.hi();  // >= 2^62

  // 64-bit Newton from above: relative error 2^-8 -> 2^-17 -> 2^-35 (each
  // step squares it and halves it), so g is floor(sqrt(t)) or one above, as
  // three steps from a 6-bit seed gave; g stays >= floor(sqrt(t)) from any
  // seed. (The result is floor(sqrt(n)) whatever the seed: a seed's accuracy
  // only decides how many repairs below run. Two divisions, not three.)
  uint64_t g = sqrt_seeds[static_cast<size_t>(t >> 55) - 128];
  for (int i = 0; i < 2; ++i) g = (g + t / g) >> 1;

  // (g + 1) 2^32 >= sqrt(m), since (g + 1)^2 > t. One 128/64 Newton step takes
  // the relative error from ~2^-31 to ~2^-63, i.e. within a few units.
  uint64_t y = g + 1 >= (uint64_t{1} << 32) ? UINT64_MAX : (g + 1) << 32;
  // m / y >= 2^64 > y can only happen with y capped at 2^64 - 1, and then
  // m >= (2^64 - 1) 2^64 > y^2, so y already is floor(sqrt(m)).
  if (m.hi() < y) {
    uint64_t unused_remainder = 0;
    const uint64_t q = m.divrem(y, unused_remainder);
    y = (y >> 1) + (q >> 1) + (y & q & 1u);  // floor((y + q) / 2) without overflow
    while (U::mul(y, y) > m) --y;          // Newton from above never undershoots
  }
  return y >> (shift / 2);
}

template <class U>
int64_t sqrt(int64_t a) {
  BITSTEP_FAULT_IF(a < 0, "sqrt", "negative argument", a, 0);
  if (a <= 0) return 0;
  // sqrt(A 2^-32) = sqrt(A 2^32) 2^-32: the raw result is sqrt(A << 32).
  const U n = U{static_cast<uint64_t>(a)} << fraction_bits;
  const uint64_t root = isqrt_floor(n);
  // Round up iff n > (root + 1/2)^2 = root^2 + root + 1/4, i.e. n - root^2 > root.
  const U excess = n - U::mul(root, root);
  return static_cast<int64_t>(excess > U{root} ? root + 1 : root);
}

template <class U>
int64_t rsqrt(int64_t a) {
  BITSTEP_FAULT_IF(a <= 0, "rsqrt", "non-positive argument", a, 0);
  if (a <= 0) return max_raw;
  // 1 / sqrt(A 2^-32) = 2^16 / sqrt(A): the raw result is 2^48 / sqrt(A).
  // With m = A 4^k in [2^126, 2^128) and T = floor(sqrt(m)) (64 bits, relative
  // error < 2^-63) it is 2^(48+k) / T, rounded once: error <= 0.5 + 2^-15 ulp.
  const U wide{static_cast<uint64_t>(a)};
  const int shift = count_leading_zeros(wide) & ~1;
  const uint64_t root = isqrt_floor(wide << shift);
  bool saturated = false;
  return divide_magnitudes(false, U{1} << (48 + shift / 2), root, saturated);
}

template <class U>
int64_t length3(int64_t x, int64_t y, int64_t z) {
  uint64_t rounded = 0;
  if ((x == 0 ? 1 : 0) + (y == 0 ? 1 : 0) + (z == 0 ? 1 : 0) >= 2) {
    // Along an axis (gravity, say) the sum is one exact square, X^2, and
    // its root |X| exactly: no remainder to round.
    rounded = magnitude(x) + magnitude(y) + magnitude(z);  // two are 0
  } else {
    // The raw length is sqrt(X^2 + Y^2 + Z^2); the sum is < 3 2^126 < 2^128.
    const U sum = U::mul(magnitude(x), magnitude(x)) + U::mul(magnitude(y), magnitude(y)) +
                  U::mul(magnitude(z), magnitude(z));
    const uint64_t root = isqrt_floor(sum);
    const U excess = sum - U::mul(root, root);
    rounded = excess > U{root} ? root + 1 : root;
  }
  BITSTEP_FAULT_IF(rounded > uint64_t{INT64_MAX}, "length", "result out of range, saturated", x, y);
  return rounded > uint64_t{INT64_MAX} ? max_raw : static_cast<int64_t>(rounded);
}

template <class U>
bool normalize(const int64_t* in, int64_t* out, int n) {
  // S = sum of squares, saturating at 2^128 - 1 (reachable only with four
  // components of magnitude 2^63, where it changes T by one part in 2^64).
  U sum{0};
  for (int i = 0; i < n; ++i) {
    const U next = sum + U::mul(magnitude(in[i]), magnitude(in[i]));
    sum = next < sum ? U{UINT64_MAX, UINT64_MAX} : next;
  }
  if (sum == U{0}) {
    for (int i = 0; i < n; ++i) out[i] = 0;
    return false;
  }
  // out_i = V_i / sqrt(S) = V_i 2^(32+k) / sqrt(S 4^k) in raw units, with
  // T = floor(sqrt(S 4^k)) in [2^63, 2^64). |V_i| 2^k <= T keeps the quotient
  // <= 2^32; T's relative error < 2^-63 adds < 2^-31 ulp to the rounding.
  const int shift = count_leading_zeros(sum) & ~1;
  const uint64_t root = isqrt_floor(sum << shift);
  for (int i = 0; i < n; ++i) {
    bool saturated = false;
    const U numerator = U{magnitude(in[i])} << (fraction_bits + shift / 2);
    out[i] = divide_magnitudes(in[i] < 0, numerator, root, saturated);
  }
  return true;
}

#define BITSTEP_INSTANTIATE_SQRT(U)                              \
  template uint64_t isqrt_floor<U>(U);                           \
  template int64_t sqrt<U>(int64_t);                             \
  template int64_t rsqrt<U>(int64_t);                            \
  template int64_t length3<U>(int64_t, int64_t, int64_t);        \
  template bool normalize<U>(const int64_t*, int64_t*, int);

BITSTEP_INSTANTIATE_SQRT(PortableU128)
#if defined(BITSTEP_HAS_NATIVE_128)
BITSTEP_INSTANTIATE_SQRT(NativeU128)
#endif

}  // namespace bitstep::raw

namespace bitstep {

Fixed sqrt(Fixed a) { return Fixed::from_raw(raw::sqrt<Wide>(a.raw())); }
Fixed rsqrt(Fixed a) { return Fixed::from_raw(raw::rsqrt<Wide>(a.raw())); }

}  // namespace bitstep
