// sin, cos, tan, atan2, asin, acos in integer arithmetic only.
//
// Intermediates are Q2.62 (an int64 v stands for v * 2^-62; angles up to pi
// are kept as unsigned magnitudes), 30 bits finer than the Q32.32 result, so
// the one final rounding dominates the error. Series coefficients (1/n!, 1/n)
// are computed at compile time by integer division; pi comes from its
// hexadecimal expansion.
#include <array>
#include <cstddef>

#include "fixed/fixed.h"
#include "fixed/raw_math.h"

namespace bitstep::raw {

namespace {

constexpr int q62 = 62;
constexpr uint64_t one_q62 = uint64_t{1} << q62;

// pi * 2^126 from pi = 3.243F6A88 85A308D3 13198A2E 03707344 A409... (hex):
// the fraction's first 128 bits shifted right by 2 drop the bits "00" followed
// by A4.., so truncating is rounding to nearest.
constexpr PortableU128 pi_q126{(uint64_t{3} << 62) | (uint64_t{0x243F6A8885A308D3} >> 2),
                               (uint64_t{3} << 62) | (uint64_t{0x13198A2E03707344} >> 2)};
constexpr uint64_t pi_q62 = round_shift(pi_q126, 64).lo();
constexpr uint64_t half_pi_q62 = round_shift(pi_q126, 65).lo();
constexpr uint64_t quarter_pi_q62 = round_shift(pi_q126, 66).lo();
constexpr PortableU128 half_pi_q96 = round_shift(pi_q126, 31);
// 2/pi * 2^64 = 2^127 / (pi 2^62); only used to pick the quadrant, so its
// 2^-64 precision is plenty (the remainder itself uses half_pi_q96).
constexpr uint64_t two_over_pi_q64 = [] {
  uint64_t remainder = 0;
  return PortableU128{uint64_t{1} << 63, 0}.divrem(pi_q62, remainder);
}();
// tan(pi/8) = sqrt(2) - 1, the switch point of the atan reduction (any value
// near it works; both branches converge there).
constexpr uint64_t tan_pi_8_q62 = uint64_t{0x1A827999FCEF3242};

// Coefficients of the Taylor series in Q62: 1/n! for n = 0..18, 1/n for odd n <= 45.
constexpr std::array<uint64_t, 19> make_inverse_factorials() {
  std::array<uint64_t, 19> c{};
  uint64_t factorial = 1;
  for (size_t n = 0; n < c.size(); ++n) {
    if (n > 0) factorial *= uint64_t{n};
    c[n] = (one_q62 + factorial / 2) / factorial;
  }
  return c;
}
constexpr std::array<uint64_t, 19> inverse_factorial = make_inverse_factorials();

constexpr std::array<uint64_t, 46> make_inverse_integers() {
  std::array<uint64_t, 46> c{};
  for (size_t n = 1; n < c.size(); ++n) c[n] = (one_q62 + uint64_t{n} / 2) / uint64_t{n};
  return c;
}
constexpr std::array<uint64_t, 46> inverse_integer = make_inverse_integers();

// round(a * b / 2^62) for signed Q62 values.
template <class U>
constexpr int64_t mul_q62(int64_t a, int64_t b) {
  const uint64_t m = round_shift(U::mul(magnitude(a), magnitude(b)), q62).lo();
  return (a < 0) != (b < 0) ? static_cast<int64_t>(uint64_t{0} - m) : static_cast<int64_t>(m);
}

// A Q62 magnitude with a sign, rounded once to raw Q32.32.
template <class U>
int64_t q62_to_raw(bool negative, uint64_t magnitude_q62) {
  bool saturated = false;
  return signed_saturate(negative, round_shift(U{magnitude_q62}, q62 - fraction_bits), saturated);
}
template <class U>
int64_t q62_to_raw(int64_t v) {
  return q62_to_raw<U>(v < 0, magnitude(v));
}

// |x| = k pi/2 + r with |r| <= pi/4 (+ a hair): r in Q62 and k mod 4.
struct Reduced {
  int64_t r_q62;
  unsigned quadrant;
};

template <class U>
Reduced reduce_quarter_turns(uint64_t x) {
  // k = round(x 2/pi): x is Q32, 2/pi Q64, the product Q96.
  const uint64_t k = round_shift(U::mul(x, two_over_pi_q64), 96).lo();
  // r = x - k pi/2 in Q96, exactly up to pi/2's last bit: k < 2^31 and
  // pi/2 2^96 < 2^97, so k pi/2 < 2^128 and the error is < k 2^-97 < 2^-66.
  // The difference is small, so wrapping arithmetic gives it exactly.
  const U k_half_pi = U::mul(k, half_pi_q96.lo()) + (U{k * half_pi_q96.hi()} << 64);
  const U r_q96 = (U{x} << 64) - k_half_pi;
  const bool negative = top_bit(r_q96);
  const uint64_t r = round_shift(negative ? -r_q96 : r_q96, 96 - q62).lo();
  return {negative ? static_cast<int64_t>(uint64_t{0} - r) : static_cast<int64_t>(r),
          static_cast<unsigned>(k & 3u)};
}

// sin r = r (1 - r^2/3! + r^4/5! - ...), Horner in z = r^2 up to r^17/17!;
// the first term left out, r^19/19!, is < 2^-63 for |r| <= 0.79.
template <class U>
int64_t sin_q62(int64_t r) {
  const int64_t z = mul_q62<U>(r, r);
  int64_t sum = static_cast<int64_t>(inverse_factorial[17]);
  for (int n = 15; n >= 1; n -= 2) {
    sum = static_cast<int64_t>(inverse_factorial[static_cast<size_t>(n)]) - mul_q62<U>(z, sum);
  }
  return mul_q62<U>(r, sum);
}

// cos r = 1 - r^2/2! + r^4/4! - ... up to r^18/18! (next term < 2^-68).
template <class U>
int64_t cos_q62(int64_t r) {
  const int64_t z = mul_q62<U>(r, r);
  int64_t sum = static_cast<int64_t>(inverse_factorial[18]);
  for (int n = 16; n >= 0; n -= 2) {
    sum = static_cast<int64_t>(inverse_factorial[static_cast<size_t>(n)]) - mul_q62<U>(z, sum);
  }
  return sum;
}

// sin of |x| (cosine = false) or cos of |x| (cosine = true) in Q62: with
// |x| = k pi/2 + r, sin |x| = sin r, cos r, -sin r, -cos r for k mod 4 = 0..3
// and cos |x| is sin shifted by one quarter turn. Only one series is evaluated.
template <class U>
int64_t sin_or_cos_q62(uint64_t x, bool cosine) {
  const Reduced reduced = reduce_quarter_turns<U>(x);
  const unsigned quadrant = (reduced.quadrant + (cosine ? 1u : 0u)) & 3u;
  const int64_t v = (quadrant & 1u) != 0 ? cos_q62<U>(reduced.r_q62) : sin_q62<U>(reduced.r_q62);
  return quadrant >= 2 ? -v : v;
}

// atan u = u - u^3/3 + u^5/5 - ... for u >= 0, up to u^top/top (top odd).
template <class U>
constexpr uint64_t atan_series_q62(uint64_t u, int top) {
  const int64_t z = mul_q62<U>(static_cast<int64_t>(u), static_cast<int64_t>(u));
  int64_t sum = static_cast<int64_t>(inverse_integer[static_cast<size_t>(top)]);
  for (int n = top - 2; n >= 1; n -= 2) {
    sum = static_cast<int64_t>(inverse_integer[static_cast<size_t>(n)]) - mul_q62<U>(z, sum);
  }
  return static_cast<uint64_t>(mul_q62<U>(static_cast<int64_t>(u), sum));
}

// atan t for t in [0, 1] the slow way, for the compile-time table only:
// atan t = pi/4 - atan((1 - t) / (1 + t)) above tan(pi/8) ~ 0.4142, then the
// series to u^45/45 (the next term is < 2^-65).
constexpr uint64_t atan_reference_q62(uint64_t t) {
  if (t <= tan_pi_8_q62) return atan_series_q62<PortableU128>(t, 45);
  uint64_t remainder = 0;
  const uint64_t u = (PortableU128{one_q62 - t} << q62).divrem(one_q62 + t, remainder);
  return quarter_pi_q62 - atan_series_q62<PortableU128>(u, 45);
}

// atan(j/8) for j = 0..8 in Q62.
constexpr std::array<uint64_t, 9> atan_eighths = [] {
  std::array<uint64_t, 9> table{};
  for (size_t j = 0; j < table.size(); ++j) table[j] = atan_reference_q62(uint64_t{j} << (q62 - 3));
  return table;
}();

// atan t for t in [0, 1] (Q62), in [0, pi/4]: with c = j/8 the nearest
// eighth, atan t = atan c + atan u, u = (t - c) / (1 + t c), |u| <= 1/16, so
// the series to u^15/15 suffices (the next term is < 2^-72).
template <class U>
uint64_t atan_unit_q62(uint64_t t) {
  const size_t j = static_cast<size_t>((t + (uint64_t{1} << (q62 - 4))) >> (q62 - 3));  // round(8 t), 0..8
  const uint64_t c = uint64_t{j} << (q62 - 3);
  const int64_t tc = mul_q62<U>(static_cast<int64_t>(t), static_cast<int64_t>(c));
  const uint64_t denominator = one_q62 + static_cast<uint64_t>(tc);
  uint64_t remainder = 0;
  const uint64_t u = (U{t >= c ? t - c : c - t} << q62).divrem(denominator, remainder);
  const uint64_t a = atan_series_q62<U>(u, 15);
  return t >= c ? atan_eighths[j] + a : atan_eighths[j] - a;
}

// atan2 of two magnitudes in the same units, in [0, pi/2] (Q62).
template <class U>
uint64_t atan2_magnitudes_q62(uint64_t y, uint64_t x) {
  uint64_t remainder = 0;
  if (y == 0) return 0;
  if (y <= x) return atan_unit_q62<U>((U{y} << q62).divrem(x, remainder));  // (y << 62) >> 64 < x
  return half_pi_q62 - atan_unit_q62<U>((U{x} << q62).divrem(y, remainder));
}

// asin |a| in Q62 for |a| <= 1 (raw), as atan2(a, sqrt(1 - a^2)) with
// 1 - a^2 = (1 - a)(1 + a) formed exactly, so acos near 1 keeps its precision.
template <class U>
uint64_t asin_magnitude_q62(uint64_t a) {
  constexpr uint64_t one_raw = uint64_t{1} << fraction_bits;
  const U one_minus_square_q124 = U::mul(one_raw - a, one_raw + a) << 60;  // Q64 -> Q124
  const uint64_t cosine_q62 = isqrt_floor(one_minus_square_q124);
  return atan2_magnitudes_q62<U>(a << (q62 - fraction_bits), cosine_q62);
}

uint64_t clamp_unit(int64_t a) {
  constexpr uint64_t one_raw = uint64_t{1} << fraction_bits;
  const uint64_t m = magnitude(a);
  return m > one_raw ? one_raw : m;
}

}  // namespace

template <class U>
int64_t sin(int64_t a) {
  const int64_t s = sin_or_cos_q62<U>(magnitude(a), false);
  return q62_to_raw<U>(a < 0 ? -s : s);  // sin(-x) = -sin x
}

template <class U>
int64_t cos(int64_t a) {
  return q62_to_raw<U>(sin_or_cos_q62<U>(magnitude(a), true));  // cos(-x) = cos x
}

template <class U>
int64_t tan(int64_t a) {
  const int64_t s = sin_or_cos_q62<U>(magnitude(a), false);
  const int64_t c = sin_or_cos_q62<U>(magnitude(a), true);
  // Q62 / Q62 -> Q32: (s << 32) / c, rounded once; saturates near the poles.
  bool saturated = false;
  const bool negative = (a < 0) != ((s < 0) != (c < 0));
  const int64_t r = divide_magnitudes(negative, U{magnitude(s)} << fraction_bits, magnitude(c), saturated);
  BITSTEP_FAULT_IF(saturated, "tan", "result out of range, saturated", a, 0);
  return r;
}

template <class U>
int64_t atan2(int64_t y, int64_t x) {
  uint64_t angle = atan2_magnitudes_q62<U>(magnitude(y), magnitude(x));
  if (x < 0) angle = pi_q62 - angle;
  return q62_to_raw<U>(y < 0, angle);
}

template <class U>
int64_t asin(int64_t a) {
  BITSTEP_FAULT_IF(magnitude(a) > (uint64_t{1} << fraction_bits), "asin", "argument outside [-1, 1]", a, 0);
  return q62_to_raw<U>(a < 0, asin_magnitude_q62<U>(clamp_unit(a)));
}

template <class U>
int64_t acos(int64_t a) {
  BITSTEP_FAULT_IF(magnitude(a) > (uint64_t{1} << fraction_bits), "acos", "argument outside [-1, 1]", a, 0);
  // acos a = pi/2 - asin a.
  const uint64_t asin_magnitude = asin_magnitude_q62<U>(clamp_unit(a));
  return q62_to_raw<U>(false, a < 0 ? half_pi_q62 + asin_magnitude : half_pi_q62 - asin_magnitude);
}

#define BITSTEP_INSTANTIATE_TRIG(U)                \
  template int64_t sin<U>(int64_t);                \
  template int64_t cos<U>(int64_t);                \
  template int64_t tan<U>(int64_t);                \
  template int64_t atan2<U>(int64_t, int64_t);     \
  template int64_t asin<U>(int64_t);               \
  template int64_t acos<U>(int64_t);

BITSTEP_INSTANTIATE_TRIG(PortableU128)
#if defined(BITSTEP_HAS_NATIVE_128)
BITSTEP_INSTANTIATE_TRIG(NativeU128)
#endif

}  // namespace bitstep::raw

namespace bitstep {

Fixed sin(Fixed a) { return Fixed::from_raw(raw::sin<Wide>(a.raw())); }
Fixed cos(Fixed a) { return Fixed::from_raw(raw::cos<Wide>(a.raw())); }
Fixed tan(Fixed a) { return Fixed::from_raw(raw::tan<Wide>(a.raw())); }
Fixed atan2(Fixed y, Fixed x) { return Fixed::from_raw(raw::atan2<Wide>(y.raw(), x.raw())); }
Fixed asin(Fixed a) { return Fixed::from_raw(raw::asin<Wide>(a.raw())); }
Fixed acos(Fixed a) { return Fixed::from_raw(raw::acos<Wide>(a.raw())); }

}  // namespace bitstep
