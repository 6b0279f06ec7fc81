// Vec3, Quat and Mat33.
//
// Exact properties are asserted exactly (fused dot products round once, ties
// to even is symmetric under negation, so e.g. anticommutativity of cross
// holds bit for bit). Everything else has a tolerance in ulps (1 ulp = 2^-32)
// derived next to the assertion from the per-operation rounding: every fused
// sum rounds once (<= 1/2 ulp), sqrt/length are correctly rounded, normalize
// and sin/cos are within 1 ulp per component. The worst error seen is printed
// next to its bound.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <string>
#include <vector>

#include "fixed/big_uint.h"
#include "fixed/checked.h"
#include "fixed/decimal.h"
#include "fixed/mat33.h"
#include "fixed/quat.h"
#include "fixed/u128.h"
#include "fixed/vec3.h"
#include "fixed/splitmix64.h"
#include "tests/test_support.h"

namespace {

using bitstep::Fixed;
using bitstep::Mat33;
using bitstep::Quat;
using bitstep::Vec3;
using U = bitstep::PortableU128;
using namespace bitstep::literals;

constexpr int64_t one_raw = int64_t{1} << 32;

using bitstep::SplitMix64;

// Uniform raw value in [-limit, limit].
int64_t in_range(SplitMix64& rng, int64_t limit) {
  const uint64_t span = 2 * static_cast<uint64_t>(limit) + 1;
  return static_cast<int64_t>(rng.next() % span) - limit;
}

uint64_t mag(int64_t v) { return bitstep::magnitude(v); }
Fixed raw(int64_t r) { return Fixed::from_raw(r); }
Fixed int_(int32_t v) { return Fixed::from_int(v); }
Vec3 vec(int32_t x, int32_t y, int32_t z) { return {int_(x), int_(y), int_(z)}; }

// Random vector with components in [-limit, limit] (raw).
Vec3 random_vec(SplitMix64& rng, int64_t limit) {
  return {raw(in_range(rng, limit)), raw(in_range(rng, limit)), raw(in_range(rng, limit))};
}
// A random unit quaternion: normalize of a random one with components in [-1, 1].
Quat random_unit_quat(SplitMix64& rng) {
  for (;;) {
    const Quat q{raw(in_range(rng, one_raw)), raw(in_range(rng, one_raw)), raw(in_range(rng, one_raw)),
                 raw(in_range(rng, one_raw))};
    // Keep |q| >= 1/4 so the direction is well defined.
    if (mag(q.w.raw()) + mag(q.x.raw()) + mag(q.y.raw()) + mag(q.z.raw()) < static_cast<uint64_t>(one_raw / 2))
      continue;
    return normalize(q);
  }
}

uint64_t ulps(Fixed a, Fixed b) {
  return a.raw() < b.raw() ? static_cast<uint64_t>(b.raw()) - static_cast<uint64_t>(a.raw())
                           : static_cast<uint64_t>(a.raw()) - static_cast<uint64_t>(b.raw());
}
uint64_t ulps(Vec3 a, Vec3 b) { return std::max({ulps(a.x, b.x), ulps(a.y, b.y), ulps(a.z, b.z)}); }
uint64_t ulps(Quat a, Quat b) { return std::max({ulps(a.w, b.w), ulps(a.x, b.x), ulps(a.y, b.y), ulps(a.z, b.z)}); }
uint64_t ulps(const Mat33& a, const Mat33& b) {
  return std::max({ulps(a.rows[0], b.rows[0]), ulps(a.rows[1], b.rows[1]), ulps(a.rows[2], b.rows[2])});
}
// |q|^2 as the exact sum of squares rounded once.
Fixed norm_sq(Quat q) { return (q * conjugate(q)).w; }
// ||q|^2 - 1| in ulps, from the exact sum of squares, rounded up.
uint64_t norm_error_ulps(Quat q) {
  const U square_sum = U::mul(mag(q.w.raw()), mag(q.w.raw())) + U::mul(mag(q.x.raw()), mag(q.x.raw())) +
                       U::mul(mag(q.y.raw()), mag(q.y.raw())) + U::mul(mag(q.z.raw()), mag(q.z.raw()));
  const U unit{1, 0};  // 1.0^2 in raw^2 units
  const U e = square_sum > unit ? square_sum - unit : unit - square_sum;
  return ((e + U{0xFFFFFFFFu}) >> 32).lo();
}
// Sum of |v_i| in whole units, rounded up (for bounds proportional to |v|).
uint64_t units_l1(Vec3 v) {
  const uint64_t sum = mag(v.x.raw()) + mag(v.y.raw()) + mag(v.z.raw());
  return (sum + static_cast<uint64_t>(one_raw) - 1) >> 32;
}

std::string show(Fixed f) { return bitstep::to_string(f); }
// Built with += (gcc 12 at -O3 warns falsely, -Wrestrict, on "(" + std::string).
std::string show(Vec3 v) {
  std::string s = "(";
  s += show(v.x);
  s += ", ";
  s += show(v.y);
  s += ", ";
  s += show(v.z);
  s += ")";
  return s;
}
std::string show(Quat q) {
  std::string s = "(";
  s += show(q.w);
  s += "; ";
  s += show(q.x);
  s += ", ";
  s += show(q.y);
  s += ", ";
  s += show(q.z);
  s += ")";
  return s;
}
std::string show(const Mat33& m) {
  std::string s = "[";
  s += show(m.rows[0]);
  s += ", ";
  s += show(m.rows[1]);
  s += ", ";
  s += show(m.rows[2]);
  s += "]";
  return s;
}

// The sample closest to its bound (error / bound largest).
struct Worst {
  uint64_t error = 0, bound = 1;
  void add(uint64_t e, uint64_t b) {
    if (e * bound > error * b) error = e, bound = b;
  }
};

void report(const char* what, uint64_t worst, uint64_t bound) {
  std::printf("[geometry] %-58s worst %6" PRIu64 " ulp, bound %6" PRIu64 " ulp\n", what, worst, bound);
}

// Signed 128-bit helpers for exact references.
using bitstep::test::wide;
U product(int64_t a, int64_t b) {
  const U p = U::mul(mag(a), mag(b));
  return (a < 0) != (b < 0) ? -p : p;
}
bool negative(U v) { return (v.hi() >> 63) != 0; }
// r == round(n / 2^32), ties to even.
bool rounds_q64_correctly(int64_t r, U n) {
  const U e = (wide(r) << 32) - n;
  const U abs_e = negative(e) ? -e : e;
  const U half{uint64_t{1} << 31};
  return abs_e < half || (abs_e == half && (r & 1) == 0);
}

}  // namespace

// ===========================================================================
// Vec3

static_assert(dot(Vec3{Fixed::from_int(1), Fixed::from_int(2), Fixed::from_int(3)},
                  Vec3{Fixed::from_int(4), Fixed::from_int(5), Fixed::from_int(6)}) == Fixed::from_int(32));
static_assert(cross(Vec3{Fixed::one(), {}, {}}, Vec3{{}, Fixed::one(), {}}) == Vec3{{}, {}, Fixed::one()});

TEST_CASE("dot and cross sum exact products and round once", "[geometry]") {
  CHECK(dot(vec(1, 2, 3), vec(4, -5, 6)) == int_(12));
  CHECK(cross(vec(1, 0, 0), vec(0, 1, 0)) == vec(0, 0, 1));
  CHECK(cross(vec(0, 1, 0), vec(0, 0, 1)) == vec(1, 0, 0));
  CHECK(cross(vec(0, 0, 1), vec(1, 0, 0)) == vec(0, 1, 0));
  CHECK(cross(vec(2, 3, 4), vec(5, 6, 7)) == vec(-3, 6, -3));
  CHECK(length_sq(vec(1, 2, 2)) == int_(9));
  // (raw 1)(1/2) twice: the exact sum is 1 ulp; rounding each product first
  // (1/2 ulp, a tie, to even 0) would give 0.
  const Fixed half = Fixed::from_ratio(1, 2);
  CHECK(dot(Vec3{raw(1), raw(1), Fixed{}}, Vec3{half, half, Fixed{}}) == raw(1));
  CHECK(raw(1) * half + raw(1) * half == Fixed{});
  // Terms out of range, exact sum in range.
  CHECK(dot(vec(65536, 65536, 1), vec(65536, -65536, 7)) == int_(7));

  SplitMix64 rng{0xD07};
  for (int i = 0; i < 100000; ++i) {
    const int64_t limit = int64_t{1} << (20 + i % 27);  // |components| < 2^46 raw: |dot| < 3 2^60, in range
    const Vec3 a = random_vec(rng, limit), b = random_vec(rng, limit);
    const Fixed d = dot(a, b);
    const U exact = product(a.x.raw(), b.x.raw()) + product(a.y.raw(), b.y.raw()) + product(a.z.raw(), b.z.raw());
    REQUIRE_QUIETLY(rounds_q64_correctly(d.raw(), exact), show(a) << " . " << show(b) << " = " << show(d));
    REQUIRE_QUIETLY(dot(b, a) == d, show(a) << ", " << show(b));
    const Vec3 c = cross(a, b);
    const U cz = product(a.x.raw(), b.y.raw()) - product(a.y.raw(), b.x.raw());
    REQUIRE_QUIETLY(rounds_q64_correctly(c.z.raw(), cz), show(a) << " x " << show(b) << " = " << show(c));
  }
}

TEST_CASE("cross is exactly anticommutative and orthogonal to its operands within (|a|_1 + 1)/2 ulp", "[geometry]") {
  SplitMix64 rng{0xC05};
  uint64_t worst = 0;
  for (int i = 0; i < 100000; ++i) {
    // a in [-2, 2]^3, b up to 1000: the bound below depends on |a| only.
    const Vec3 a = random_vec(rng, 2 * one_raw);
    const Vec3 b = random_vec(rng, (i % 2 == 0 ? 1000 : 1) * one_raw);
    const Vec3 c = cross(a, b);
    REQUIRE_QUIETLY(cross(b, a) == -c, show(a) << ", " << show(b));
    REQUIRE_QUIETLY(cross(a, a) == Vec3{}, show(a));
    // cross(a, b) = exact + e with |e_i| <= 1/2 ulp; the exact cross product
    // is orthogonal to a, so dot(c, a) = e . a rounded: |.| <= |a|_1 / 2 + 1/2
    // ulp, i.e. <= 3.5 ulp for |a_i| <= 2.
    const uint64_t error = mag(dot(c, a).raw());
    const uint64_t bound = (units_l1(a) + 1) / 2 + 1;
    worst = std::max(worst, error);
    REQUIRE_QUIETLY(error <= bound, show(a) << " x " << show(b) << " = " << show(c) << ", dot with a " << error);
  }
  report("dot(cross(a, b), a), |a_i| <= 2", worst, 4);
  CHECK(worst <= 4);
}

TEST_CASE("length is correctly rounded: 3-4-5 exact, 2^30-scale and tiny vectors", "[geometry]") {
  CHECK(length(vec(3, 4, 0)) == int_(5));
  CHECK(length(vec(0, -3, 4)) == int_(5));
  CHECK(length(vec(2, 3, 6)) == int_(7));
  CHECK(length(vec(-1, 4, 8)) == int_(9));
  CHECK(length(vec(0, 0, 0)) == Fixed{});
  CHECK(length(vec(1 << 30, 0, 0)) == int_(1 << 30));
  CHECK(length(vec(3 << 28, 4 << 28, 0)) == int_(5 << 28));
  CHECK(length(Vec3{0.5_fx, 1_fx, -1_fx}) == 1.5_fx);
  CHECK(length(Vec3{0.25_fx, -0.5_fx, 0.5_fx}) == 0.75_fx);
  // Tiny: raw (3, 4, 0) -> raw 5; raw 1 -> 1; raw (1, 1, 0) -> round(sqrt 2) = 1; (1, 1, 1) -> round(sqrt 3) = 2.
  CHECK(length(Vec3{raw(3), raw(4), Fixed{}}) == raw(5));
  CHECK(length(Vec3{raw(1), Fixed{}, Fixed{}}) == raw(1));
  CHECK(length(Vec3{raw(1), raw(1), Fixed{}}) == raw(1));
  CHECK(length(Vec3{raw(1), raw(1), raw(1)}) == raw(2));
  CHECK(length(Vec3{raw(-1), raw(-1), raw(-1)}) == raw(2));

  // r = round(sqrt(S)) with S = X^2 + Y^2 + Z^2 (raw) iff r^2 - r < S <= r^2 + r
  // ((r +- 1/2)^2 is never an integer, so there are no ties).
  SplitMix64 rng{0x1E7};
  for (int i = 0; i < 100000; ++i) {
    // Scales from tiny (2^0 raw) to 2^30 units (2^62 raw).
    const Vec3 v = random_vec(rng, int64_t{1} << (i % 63));
    const int64_t r = length(v).raw();
    const U s = U::mul(mag(v.x.raw()), mag(v.x.raw())) + U::mul(mag(v.y.raw()), mag(v.y.raw())) +
                U::mul(mag(v.z.raw()), mag(v.z.raw()));
    const U r2 = U::mul(static_cast<uint64_t>(r), static_cast<uint64_t>(r));
    const U ru{static_cast<uint64_t>(r)};
    REQUIRE_QUIETLY(r >= 0, show(v));
    REQUIRE_QUIETLY(s <= r2 + ru, show(v) << " -> " << r);
    REQUIRE_QUIETLY((r == 0 || s > r2 - ru), show(v) << " -> " << r);
  }
}

TEST_CASE("length_exceeds answers length(v) > limit exactly, at the rounding boundary and the range's ends",
          "[geometry]") {
  // Around each vector's own length, where the rounding decides: r - 1, r, r + 1.
  SplitMix64 rng{0x1E8};
  for (int i = 0; i < 100000; ++i) {
    const Vec3 v = random_vec(rng, int64_t{1} << (i % 63));
    const int64_t r = length(v).raw();
    for (const int64_t limit : {r - 1, r, r + 1}) {
      REQUIRE_QUIETLY(length_exceeds(v, raw(limit)) == (length(v) > raw(limit)), show(v) << " vs raw " << limit);
    }
  }
  // Raw (1, 1, 0) rounds to 1: not beyond 1, beyond 0; (3, 4, 0) is exactly 5.
  CHECK_FALSE(length_exceeds(Vec3{raw(1), raw(1), Fixed{}}, raw(1)));
  CHECK(length_exceeds(Vec3{raw(1), raw(1), Fixed{}}, Fixed{}));
  CHECK_FALSE(length_exceeds(vec(3, 4, 0), int_(5)));
  CHECK(length_exceeds(vec(3, 4, 0), int_(5) - raw(1)));
  CHECK_FALSE(length_exceeds(Vec3{}, Fixed{}));
  CHECK(length_exceeds(Vec3{}, -raw(1)));  // a length is never negative
  // The largest components: length saturates at max(), which nothing exceeds.
  const Vec3 huge{Fixed::max(), Fixed::max(), Fixed::max()};
  CHECK_FALSE(length_exceeds(huge, Fixed::max()));
  CHECK(length_exceeds(huge, Fixed::max() - raw(1)));
}

TEST_CASE("normalize: each component within 1 ulp of v/|v|, unit length within 2 ulp, zero stays zero", "[geometry]") {
  CHECK(normalize(vec(0, 0, 0)) == Vec3{});
  CHECK(normalize(vec(3, 0, 0)) == vec(1, 0, 0));
  CHECK(normalize(vec(0, -7, 0)) == vec(0, -1, 0));
  CHECK(normalize(vec(3, 4, 0)) == Vec3{Fixed::from_ratio(3, 5), Fixed::from_ratio(4, 5), Fixed{}});
  CHECK(normalize(Vec3{raw(1), Fixed{}, Fixed{}}) == vec(1, 0, 0));
  CHECK(normalize(Vec3{Fixed{}, Fixed{}, Fixed::lowest()}) == vec(0, 0, -1));
  CHECK(normalize_or(vec(0, 0, 0), vec(0, 1, 0)) == vec(0, 1, 0));
  CHECK(normalize_or(vec(0, 0, 5), vec(0, 1, 0)) == vec(0, 0, 1));
  CHECK(normalize_or(Vec3{raw(1), Fixed{}, Fixed{}}, vec(0, 1, 0)) == vec(1, 0, 0));

  // Within 1 ulp: (|n_i| - 1)^2 S <= V_i^2 2^64 <= (|n_i| + 1)^2 S, with the
  // same sign, where S = sum of V_j^2 (exact, 256-bit).
  using Big = bitstep::BigUint<8>;
  auto sq = [](uint64_t m) { return Big::from_u64(m) * Big::from_u64(m); };
  SplitMix64 rng{0x404};
  uint64_t worst_length = 0;
  for (int i = 0; i < 100000; ++i) {
    const Vec3 v = random_vec(rng, int64_t{1} << (i % 63));
    if (v == Vec3{}) continue;
    const Vec3 n = normalize(v);
    REQUIRE_QUIETLY(normalize_or(v, vec(1, 2, 3)) == n, show(v));
    Big s = sq(mag(v.x.raw()));
    s.add(sq(mag(v.y.raw())));
    s.add(sq(mag(v.z.raw())));
    const Fixed in[3] = {v.x, v.y, v.z}, out[3] = {n.x, n.y, n.z};
    for (int k = 0; k < 3; ++k) {
      const int64_t vi = in[k].raw(), ni = out[k].raw();
      REQUIRE_QUIETLY((vi == 0 ? ni == 0 : (ni == 0 || (vi < 0) == (ni < 0))), show(v) << " -> " << show(n));
      Big target = sq(mag(vi));
      target.shift_left(64);
      const uint64_t m = mag(ni);
      const Big low = sq(m == 0 ? 0 : m - 1) * s, high = sq(m + 1) * s;
      REQUIRE_QUIETLY((m == 0 || low.compare(target) <= 0), show(v) << " -> " << show(n) << " component " << k);
      REQUIRE_QUIETLY(target.compare(high) <= 0, show(v) << " -> " << show(n) << " component " << k);
    }
    // Each component within 1 ulp of the exact unit vector u, so |n| is within
    // |n - u| <= sqrt(3) ulp of 1, and length rounds once more: < 2 ulp.
    const uint64_t error = ulps(length(n), Fixed::one());
    worst_length = std::max(worst_length, error);
    REQUIRE_QUIETLY(error <= 2, show(v) << " -> " << show(n));
  }
  report("|normalize(v)| - 1", worst_length, 2);
}

// ===========================================================================
// Quat

TEST_CASE("quaternion product: identity, exact conjugate rules, associativity within 3 ulp", "[geometry]") {
  const Quat i{Fixed{}, Fixed::one(), Fixed{}, Fixed{}};
  const Quat j{Fixed{}, Fixed{}, Fixed::one(), Fixed{}};
  const Quat k{Fixed{}, Fixed{}, Fixed{}, Fixed::one()};
  const Quat minus_one{-Fixed::one(), Fixed{}, Fixed{}, Fixed{}};
  CHECK(i * i == minus_one);
  CHECK(j * j == minus_one);
  CHECK(k * k == minus_one);
  CHECK(i * j == k);
  CHECK(j * k == i);
  CHECK(k * i == j);
  CHECK(j * i == conjugate(k));
  CHECK(conjugate(Quat{int_(1), int_(2), int_(3), int_(4)}) == Quat{int_(1), int_(-2), int_(-3), int_(-4)});

  SplitMix64 rng{0x0A55};
  uint64_t worst_assoc = 0, worst_norm = 0;
  for (int n = 0; n < 20000; ++n) {
    const Quat a = random_unit_quat(rng), b = random_unit_quat(rng), c = random_unit_quat(rng);
    REQUIRE_QUIETLY(a * Quat::identity() == a, show(a));
    REQUIRE_QUIETLY(Quat::identity() * a == a, show(a));
    REQUIRE_QUIETLY(conjugate(conjugate(a)) == a, show(a));
    // Each component of a product is one exact sum rounded once, and
    // conj(a b) = conj(b) conj(a) term by term: equal bit for bit.
    REQUIRE_QUIETLY(conjugate(a * b) == conjugate(b) * conjugate(a), show(a) << ", " << show(b));
    // q q* = (|q|^2, 0): the vector part's exact sum is 0.
    const Quat qq = a * conjugate(a);
    REQUIRE_QUIETLY((qq.x == Fixed{} && qq.y == Fixed{} && qq.z == Fixed{}), show(a) << " -> " << show(qq));
    // normalize leaves each component within 1 ulp of the unit quaternion,
    // so |q|^2 is within 2 |q||e| + |e|^2 <= 2 * 2 ulp of 1 (|e| <= sqrt(4) ulp)
    // plus the final rounding: <= 5 ulp.
    worst_norm = std::max(worst_norm, ulps(qq.w, Fixed::one()));
    REQUIRE_QUIETLY(ulps(qq.w, Fixed::one()) <= 5, show(a) << " -> " << show(qq));
    // (a b) c vs a (b c): a b carries <= 1/2 ulp per component; multiplied by
    // c (sum of |c_i| <= 2 for a unit c) that is <= 1 ulp, plus the product's
    // own 1/2 ulp: 1.5 ulp on each side, so they differ by <= 3 ulp.
    const uint64_t error = ulps((a * b) * c, a * (b * c));
    worst_assoc = std::max(worst_assoc, error);
    REQUIRE_QUIETLY(error <= 3, show(a) << ", " << show(b) << ", " << show(c));
  }
  report("(a b) c - a (b c), unit quaternions", worst_assoc, 3);
  report("|q q*| - 1 after normalize", worst_norm, 5);
}

TEST_CASE("from_axis_angle and rotate give the known rotations: 90 deg about y maps x to -z", "[geometry]") {
  const Fixed quarter_turn = Fixed::from_raw(6746518852);  // pi/2, correctly rounded
  const Fixed half_turn = Fixed::from_raw(13493037705);    // pi
  const Fixed third_turn = Fixed::from_raw(8995358470);    // 2 pi / 3 (8995358469.68)
  // from_axis_angle: sin, cos within 1 ulp, times a unit axis; rotate adds a
  // few half-ulp roundings: a unit vector lands within 4 ulp per component.
  constexpr uint64_t tolerance = 4;
  const Quat about_y = from_axis_angle(vec(0, 1, 0), quarter_turn);
  CHECK(ulps(rotate(about_y, vec(1, 0, 0)), vec(0, 0, -1)) <= tolerance);
  CHECK(ulps(rotate(about_y, vec(0, 0, 1)), vec(1, 0, 0)) <= tolerance);
  CHECK(ulps(rotate(about_y, vec(0, 1, 0)), vec(0, 1, 0)) <= tolerance);
  const Quat about_z = from_axis_angle(vec(0, 0, 1), quarter_turn);
  CHECK(ulps(rotate(about_z, vec(1, 0, 0)), vec(0, 1, 0)) <= tolerance);
  CHECK(ulps(rotate(about_z, vec(0, 1, 0)), vec(-1, 0, 0)) <= tolerance);
  const Quat about_x = from_axis_angle(vec(1, 0, 0), half_turn);
  CHECK(ulps(rotate(about_x, vec(0, 1, 0)), vec(0, -1, 0)) <= tolerance);
  CHECK(ulps(rotate(about_x, vec(0, 0, 1)), vec(0, 0, -1)) <= tolerance);
  // 120 deg about (1, 1, 1)/sqrt 3 cycles the axes.
  const Quat cycle = from_axis_angle(normalize(vec(1, 1, 1)), third_turn);
  CHECK(ulps(rotate(cycle, vec(1, 0, 0)), vec(0, 1, 0)) <= tolerance);
  CHECK(ulps(rotate(cycle, vec(0, 1, 0)), vec(0, 0, 1)) <= tolerance);
  CHECK(ulps(rotate(cycle, vec(0, 0, 1)), vec(1, 0, 0)) <= tolerance);
  // Scaled vectors scale the error: (100, 0, 0) within 100 * 4 ulp.
  CHECK(ulps(rotate(about_y, vec(100, 0, 0)), vec(0, 0, -100)) <= 100 * tolerance);
  CHECK(rotate(Quat::identity(), vec(3, -4, 5)) == vec(3, -4, 5));
  CHECK(ulps(rotate_inverse(about_y, vec(0, 0, -1)), vec(1, 0, 0)) <= tolerance);
  CHECK(from_axis_angle(vec(0, 1, 0), Fixed{}) == Quat::identity());
}

TEST_CASE("rotate agrees with rotation(q) * v, and rotate_inverse undoes rotate, over 10^4 random unit quaternions",
          "[geometry]") {
  SplitMix64 rng{0x507};
  Worst worst_matrix, worst_inverse, worst_length;
  for (int n = 0; n < 10000; ++n) {
    const Quat q = random_unit_quat(rng);
    const Vec3 v = random_vec(rng, (n % 2 == 0 ? 1 : 100) * one_raw);
    const uint64_t scale = units_l1(v);
    const Vec3 r = rotate(q, v);
    // Both evaluate R v with R = I + 2 w [u]x + 2 [u]x^2 (the same formula,
    // also for a slightly non-unit q). rotation(q) rounds each entry once
    // (1/2 ulp), so R v is off by <= |v|_1 / 2 + 1/2 ulp. rotate rounds
    // u x v (1/2 ulp), doubles it (1), multiplies by w (|w| 1 + 1/2 <= 1.5)
    // and forms u x t (|u|_1 1 + 1/2 <= 2.3): < 4 ulp whatever |v|.
    // Bound: |v|_1 / 2 + 5 ulp.
    const uint64_t bound = scale / 2 + 5;
    const uint64_t matrix_error = ulps(r, rotation(q) * v);
    worst_matrix.add(matrix_error, bound);
    REQUIRE_QUIETLY(matrix_error <= bound, show(q) << ", " << show(v) << ": " << matrix_error << " ulp");
    // rotate then rotate back. With s = |q|^2 = 1 + e, rotate(q) applies
    // R = (1 - s) I + s R' (R' the exact rotation) and rotate_inverse R^T, so
    // R^T R = I + e (2 I - R' - R'^T) moves v by <= 4 |e| |v|_inf ulp; the
    // first rotate's < 4 ulp error goes through R^T (<= 4 sqrt 3 < 7), the
    // second adds < 4: 4 |e| |v|_1 + 11 ulp, with e measured for this q.
    const uint64_t e = norm_error_ulps(q);
    const uint64_t inverse_error = ulps(rotate_inverse(q, r), v);
    worst_inverse.add(inverse_error, 4 * e * scale + 11);
    REQUIRE_QUIETLY(inverse_error <= 4 * e * scale + 11, show(q) << ", " << show(v) << ": " << inverse_error << " ulp");
    // Length: R scales |v| by at most 1 + 2|e|; rotate's < 4 ulp per
    // component change the length by < 4 sqrt 3 < 7; two length roundings.
    const uint64_t length_error = ulps(length(r), length(v));
    worst_length.add(length_error, 2 * e * scale + 8);
    REQUIRE_QUIETLY(length_error <= 2 * e * scale + 8, show(q) << ", " << show(v) << ": " << length_error << " ulp");
  }
  report("rotate(q, v) - rotation(q) v (closest to bound)", worst_matrix.error, worst_matrix.bound);
  report("rotate_inverse(q, rotate(q, v)) - v (closest to bound)", worst_inverse.error, worst_inverse.bound);
  report("|rotate(q, v)| - |v| (closest to bound)", worst_length.error, worst_length.bound);
}

TEST_CASE("integrate: constant omega over 1 s at dt = 1/60 matches from_axis_angle(axis, |omega| 1 s) and stays unit",
          "[geometry]") {
  const Fixed dt = Fixed::from_ratio(1, 60);
  // One step is q + dt/2 (0, w) q renormalised: exactly a rotation by
  // 2 atan(|w| dt / 2) about w, which falls short of |w| dt by
  // |w|^3 dt^3 / 12. Over T = 1 s (60 steps) the angle is short by
  // |w|^3 dt^2 T / 12, i.e. each quaternion component (half angle) by at most
  // |w|^3 dt^2 / 24; for |w| = 1.5 rad/s: 3.375 / 86400 = 3.9e-5 (~168000 ulp).
  // The tolerance adds 1% and 200 ulp for 60 steps of rounding.
  struct Case {
    Vec3 axis;  // unit
    Fixed speed;
  };
  const Case cases[] = {
      {vec(0, 1, 0), 1.5_fx},
      {Vec3{0.6_fx, Fixed{}, 0.8_fx}, 1.5_fx},
      {Vec3{Fixed{}, -0.28_fx, 0.96_fx}, 0.5_fx},
      {vec(1, 0, 0), 3_fx},
  };
  for (const Case& c : cases) {
    const Vec3 omega = c.axis * c.speed;
    Quat q = Quat::identity();
    uint64_t worst_unit = 0;
    for (int step = 0; step < 60; ++step) {
      q = integrate(q, omega, dt);
      worst_unit = std::max(worst_unit, ulps(norm_sq(q), Fixed::one()));
    }
    const Quat expected = from_axis_angle(c.axis, c.speed * Fixed::one());
    const Fixed cube = c.speed * c.speed * c.speed;
    const Fixed deficit = cube * dt * dt / int_(24);
    const uint64_t tolerance = static_cast<uint64_t>(deficit.raw()) * 101 / 100 + 200;
    const uint64_t error = ulps(q, expected);
    INFO("omega " << show(omega) << ": integrated " << show(q) << ", from_axis_angle " << show(expected));
    report(("integrate 60 x 1/60 s at |w| = " + show(c.speed) + " rad/s").c_str(), error, tolerance);
    CHECK(error <= tolerance);
    // The deficit is real (first-order step): the error is not far below it.
    CHECK(error * 2 >= static_cast<uint64_t>(deficit.raw()));
    // Renormalised every step: |q|^2 within 5 ulp of 1 (see the product test).
    CHECK(worst_unit <= 5);
  }
  // Long runs do not drift off the unit sphere.
  Quat q = Quat::identity();
  const Vec3 omega{2_fx, -3_fx, 5_fx};
  uint64_t worst = 0;
  for (int step = 0; step < 6000; ++step) {
    q = integrate(q, omega, dt);
    worst = std::max(worst, ulps(norm_sq(q), Fixed::one()));
  }
  report("|q|^2 - 1 over 6000 steps of integrate", worst, 5);
  CHECK(worst <= 5);
}

// ===========================================================================
// Mat33

namespace {
Mat33 random_mat(SplitMix64& rng, int64_t limit) {
  return {{random_vec(rng, limit), random_vec(rng, limit), random_vec(rng, limit)}};
}
}  // namespace

TEST_CASE("Mat33 product and transpose identities hold bit for bit", "[geometry]") {
  static_assert(Mat33::identity() * Mat33::identity() == Mat33::identity());
  static_assert(transpose(Mat33::diagonal(Vec3{Fixed::one(), Fixed{}, Fixed{}})) ==
                Mat33::diagonal(Vec3{Fixed::one(), Fixed{}, Fixed{}}));
  const Mat33 m{{vec(1, 2, 3), vec(4, 5, 6), vec(7, 8, 10)}};
  CHECK(transpose(m) == Mat33{{vec(1, 4, 7), vec(2, 5, 8), vec(3, 6, 10)}});
  CHECK(m * vec(1, 0, -1) == vec(-2, -2, -3));
  CHECK(m * m == Mat33{{vec(30, 36, 45), vec(66, 81, 102), vec(109, 134, 169)}});
  CHECK(Mat33::diagonal(vec(2, 3, 4)) * vec(1, 1, 1) == vec(2, 3, 4));
  CHECK(m.column(2) == vec(3, 6, 10));
  SplitMix64 rng{0x3A7};
  for (int n = 0; n < 20000; ++n) {
    const Mat33 a = random_mat(rng, 4 * one_raw), b = random_mat(rng, 4 * one_raw);
    const Vec3 v = random_vec(rng, 4 * one_raw);
    REQUIRE_QUIETLY(Mat33::identity() * a == a, show(a));
    REQUIRE_QUIETLY(a * Mat33::identity() == a, show(a));
    REQUIRE_QUIETLY(Mat33::identity() * v == v, show(v));
    REQUIRE_QUIETLY(transpose(transpose(a)) == a, show(a));
    // (a b)^T_ij and (b^T a^T)_ij are the same exact dot product rounded once.
    REQUIRE_QUIETLY(transpose(a * b) == transpose(b) * transpose(a), show(a) << ", " << show(b));
    REQUIRE_QUIETLY((a * v).y == dot(a.rows[1], v), show(a) << ", " << show(v));
    REQUIRE_QUIETLY((a + b) - b == a, show(a) << ", " << show(b));
    REQUIRE_QUIETLY(a * Fixed::one() == a, show(a));
    // Column j of a b is a times column j of b.
    REQUIRE_QUIETLY((a * b).column(1) == a * b.column(1), show(a) << ", " << show(b));
  }
}

TEST_CASE("rotation(q) is orthonormal: R R^T = I within 4 ||q|^2 - 1| + 3 ulp, and rotation(-q) = rotation(q)",
          "[geometry]") {
  CHECK(rotation(Quat::identity()) == Mat33::identity());
  const Quat about_y = from_axis_angle(vec(0, 1, 0), Fixed::from_raw(6746518852));
  CHECK(ulps(rotation(about_y), Mat33{{vec(0, 0, 1), vec(0, 1, 0), vec(-1, 0, 0)}}) <= 4);
  SplitMix64 rng{0x0E7};
  uint64_t worst = 0, worst_compose = 0, worst_e = 0;
  for (int n = 0; n < 10000; ++n) {
    const Quat q = random_unit_quat(rng);
    const Mat33 r = rotation(q);
    REQUIRE_QUIETLY(rotation(Quat{-q.w, -q.x, -q.y, -q.z}) == r, show(q));
    REQUIRE_QUIETLY(rotation(conjugate(q)) == transpose(r), show(q));
    // With s = |q|^2 = 1 + e the formula gives R = (1 - s) I + s R' for the
    // rotation R' of q/|q|, so R R^T = I + e (2 I - R' - R'^T) + O(e^2):
    // entries off by up to 4|e|. Each entry of R is rounded once (1/2 ulp)
    // and enters a row dot twice with |R|_1 <= sqrt 3, plus the dot's own
    // 1/2 ulp: 4|e| + 3 ulp, with e measured exactly for this q.
    const uint64_t e_ulps = norm_error_ulps(q);
    const uint64_t bound = 4 * e_ulps + 3;
    const uint64_t error = ulps(r * transpose(r), Mat33::identity());
    worst = std::max(worst, error);
    worst_e = std::max(worst_e, e_ulps);
    REQUIRE_QUIETLY(error <= bound, show(q) << ": R R^T = " << show(r * transpose(r)) << ", |q|^2 - 1 <= " << e_ulps);
    // rotation(p q) vs rotation(p) rotation(q): p q is off by <= 1/2 ulp per
    // component, and R's entries have gradient <= 4 in q: 4 ulp; the rounding
    // of R (1/2) and of R_p R_q (1/2 ulp times |R|_1 <= sqrt 3 twice, plus
    // 1/2): 2.3 ulp; non-unit p, q (R = (1 - s) I + s R' for s = |q|^2)
    // differ by e_p (I - R'_q) + e_q (I - R'_p): 2 (|e_p| + |e_q|).
    const Quat p = random_unit_quat(rng);
    const uint64_t compose_bound = 2 * (norm_error_ulps(p) + e_ulps) + 7;
    const uint64_t compose = ulps(rotation(p * q), rotation(p) * rotation(q));
    worst_compose = std::max(worst_compose, compose);
    REQUIRE_QUIETLY(compose <= compose_bound, show(p) << ", " << show(q));
  }
  report("R R^T - I (bound 4 |e| + 3 with |e| = ||q|^2 - 1|)", worst, 4 * worst_e + 3);
  CHECK(worst_e <= 4);  // normalize: 4 components within 1 ulp each
  report("rotation(p q) - rotation(p) rotation(q) (bound 2(|e_p| + |e_q|) + 7)", worst_compose, 4 * worst_e + 7);
}

namespace {

// Moments of inertia (kg m^2) in Fixed arithmetic, from decimal text.
Vec3 solid_sphere(Fixed mass, Fixed radius) {
  const Fixed i = mass * radius * radius * int_(2) / int_(5);
  return {i, i, i};
}
Vec3 solid_box(Fixed mass, Fixed hx, Fixed hy, Fixed hz) {
  const Fixed x = hx * int_(2), y = hy * int_(2), z = hz * int_(2);  // side lengths
  return {mass * (y * y + z * z) / int_(12), mass * (x * x + z * z) / int_(12), mass * (x * x + y * y) / int_(12)};
}
struct Inertia {
  const char* name;
  Vec3 diagonal;
};
std::vector<Inertia> inertia_cases() {
  return {
      {"sphere 0.01 kg r 0.01 m", solid_sphere(0.01_fx, 0.01_fx)},
      {"box 0.01 kg 0.02 m cube", solid_box(0.01_fx, 0.01_fx, 0.01_fx, 0.01_fx)},
      {"box 1 kg 1 x 2 x 3 m", solid_box(1_fx, 0.5_fx, 1_fx, 1.5_fx)},
      {"sphere 1e5 kg r 50 m", solid_sphere(100000_fx, 50_fx)},
      {"box 1e5 kg 100 m cube", solid_box(100000_fx, 50_fx, 50_fx, 50_fx)},
      {"box 1e5 kg 100 x 0.02 x 0.02 m rod", solid_box(100000_fx, 50_fx, 0.01_fx, 0.01_fx)},
      {"box 0.01 kg 100 x 0.02 x 0.02 m rod", solid_box(0.01_fx, 50_fx, 0.01_fx, 0.01_fx)},
  };
}

// round(2^64 / d), ties to even: the raw value of 1 / (d 2^-32).
int64_t reciprocal_raw(int64_t d) {
  uint64_t remainder = 0;
  uint64_t q = U{1, 0}.divrem(static_cast<uint64_t>(d), remainder);  // 1 < d
  const uint64_t rest = static_cast<uint64_t>(d) - remainder;
  if (remainder > rest || (remainder == rest && (q & 1u) != 0)) ++q;
  return static_cast<int64_t>(q);
}

// |(inverse(m) m - I)_ij| <= (sum_k |m_kj|) / 2 + 1 ulp: each entry of the
// inverse is the exact one within 1/2 ulp, that error is multiplied by
// column j of m, and the product rounds once more. Returns the worst excess
// error/bound in per mille and checks every entry.
void check_inverse_residual(const Mat33& m, const Mat33& inv, const char* name) {
  const Mat33 product = inv * m;
  for (int j = 0; j < 3; ++j) {
    const Vec3 column = m.column(j);
    const uint64_t bound = units_l1(column) / 2 + 1;
    const Vec3 got = product.column(j);
    const Fixed want[3] = {j == 0 ? Fixed::one() : Fixed{}, j == 1 ? Fixed::one() : Fixed{},
                           j == 2 ? Fixed::one() : Fixed{}};
    const uint64_t error = std::max({ulps(got.x, want[0]), ulps(got.y, want[1]), ulps(got.z, want[2])});
    INFO(name << ": column " << j << " of inverse(m) m = " << show(got) << ", off by " << error << " ulp, bound "
              << bound);
    CHECK(error <= bound);
  }
}

}  // namespace

TEST_CASE(
    "inverse of diagonal inertia tensors (0.01 kg 0.01 m sphere .. 1e5 kg 50 m box) is exact and inverse(m) m = I "
    "within |m| / 2 ulp",
    "[geometry]") {
  for (const Inertia& c : inertia_cases()) {
    const Mat33 m = Mat33::diagonal(c.diagonal);
    const Mat33 inv = inverse(m);
    INFO(c.name << ": " << show(m) << " -> " << show(inv));
    // A diagonal inverse is 1/d_i correctly rounded, zeros elsewhere.
    CHECK(inv == Mat33::diagonal(Vec3{raw(reciprocal_raw(c.diagonal.x.raw())), raw(reciprocal_raw(c.diagonal.y.raw())),
                                      raw(reciprocal_raw(c.diagonal.z.raw()))}));
    check_inverse_residual(m, inv, c.name);
    std::printf("[geometry] %-38s I = %s, inverse = %s\n", c.name, show(c.diagonal).c_str(),
                show(Vec3{inv.rows[0].x, inv.rows[1].y, inv.rows[2].z}).c_str());
  }
  CHECK(inverse(Mat33::identity()) == Mat33::identity());
  CHECK(inverse(Mat33::diagonal(vec(2, -4, 8))) == Mat33::diagonal(Vec3{0.5_fx, -0.25_fx, 0.125_fx}));
  const Mat33 m{{vec(2, 0, 0), vec(1, 1, 0), vec(0, 0, 4)}};
  CHECK(inverse(m) == Mat33{{Vec3{0.5_fx, 0_fx, 0_fx}, Vec3{-0.5_fx, 1_fx, 0_fx}, Vec3{0_fx, 0_fx, 0.25_fx}}});
}

TEST_CASE("the inverse of a rotated tensor R D R^T equals R D^-1 R^T within its perturbation bound", "[geometry]") {
  SplitMix64 rng{0x1E27};
  for (const Inertia& c : inertia_cases()) {
    const Vec3 d = c.diagonal;
    const int64_t d_min = std::min({d.x.raw(), d.y.raw(), d.z.raw()});
    // |1/d_min| in ulps: round(2^64 / d_min).
    const uint64_t inverse_scale = static_cast<uint64_t>(reciprocal_raw(d_min));
    uint64_t worst = 0, worst_bound = 0;
    for (int n = 0; n < 200; ++n) {
      const Quat q = random_unit_quat(rng);
      const Mat33 r = rotation(q);
      const Mat33 m = (r * Mat33::diagonal(d)) * transpose(r);
      const Mat33 expected = (r * inverse(Mat33::diagonal(d))) * transpose(r);
      const Mat33 inv = inverse(m);
      // Bound, in ulps:
      //  - m is R D R^T plus E with |E_ij| <= 1/2 ulp (R D rounded) times
      //    |R|_1 <= sqrt 3, plus 1/2: < 1.4 ulp, ||E||_2 < 3 * 1.4 = 4.2 ulp;
      //    inverting moves the result by ||M^-1||^2 ||E|| = 4.2 / d_min^2,
      //    which is 4.2 (2^64 / D_min) / D_min ulps for raw D_min;
      //  - R is orthogonal only to R R^T = I + F, |F_ij| <= 4|e| + 3 ulp
      //    (|e| <= 4, previous test), ||F||_2 <= 3 * 19 ulp: R D^-1 R^T is off
      //    from (R D R^T)^-1 by 2 ||F|| relative, i.e. 114 * 2^-32 |D^-1|;
      //  - expected's own roundings (D^-1, R D^-1, then R^T): <= 3 ulp,
      //    inverse's: 1/2 ulp.
      const uint64_t perturbation = inverse_scale / static_cast<uint64_t>(d_min) * 42 / 10 + 1;
      const uint64_t orthogonality = ((U::mul(inverse_scale, 114) + U{0xFFFFFFFFu}) >> 32).lo();
      const uint64_t bound = perturbation + orthogonality + 4;
      const uint64_t error = ulps(inv, expected);
      if (error * 1000 / bound > (worst * 1000) / std::max<uint64_t>(worst_bound, 1)) {
        worst = error;
        worst_bound = bound;
      }
      INFO(c.name << ", q = " << show(q) << ": inverse " << show(inv) << ", R D^-1 R^T " << show(expected));
      REQUIRE(error <= bound);
      if (n < 20) check_inverse_residual(m, inv, c.name);
    }
    report((std::string("inverse(R D R^T) - R D^-1 R^T, ") + c.name).c_str(), worst, worst_bound);
  }
}

TEST_CASE("the inverse of a singular matrix is the zero matrix (unchecked build)", "[geometry]") {
  if constexpr (!bitstep::checked_build) {
    CHECK(inverse(Mat33{}) == Mat33{});
    CHECK(inverse(Mat33{{vec(1, 2, 3), vec(2, 4, 6), vec(0, 1, 0)}}) == Mat33{});
    CHECK(inverse(Mat33{{vec(1, 0, 0), vec(0, 1, 0), vec(0, 0, 0)}}) == Mat33{});
    // Singular by one ulp is not singular: the inverse saturates instead.
    const Mat33 almost{{Vec3{raw(1), Fixed{}, Fixed{}}, vec(0, 1, 0), vec(0, 0, 1)}};
    CHECK(inverse(almost).rows[0].x == Fixed::max());
  } else {
    SUCCEED("in the checked build a singular matrix aborts (checked_tests.cpp asserts that)");
  }
}
