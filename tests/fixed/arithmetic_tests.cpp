// Fixed arithmetic: +, -, *, /, from_int, from_ratio, comparisons, abs, min,
// max, clamp, floor, ceil, round, mul_add, mul_div.
//
// Rounding is checked exactly, not against floating point: a result r of
// round(N / D) (D > 0) is correct iff e = r D - N satisfies 2|e| < D, or
// 2|e| = D and r is even (ties to even). N, D and e are formed exactly in
// 128-bit two's complement with PortableU128 (whose mul and divrem
// u128_tests.cpp proves against an independent bit-serial reference).
// Random operands come from a seeded SplitMix64 and are chosen so that the
// result is in range (saturation is covered by checked_tests.cpp).
#include <algorithm>
#include <bit>
#include <catch2/catch.hpp>
#include <compare>
#include <cstdint>
#include <string>
#include <utility>

#include "fixed/decimal.h"
#include "fixed/fixed.h"
#include "fixed/u128.h"
#include "fixed/splitmix64.h"
#include "tests/test_support.h"

namespace {

using bitstep::Fixed;
using U = bitstep::PortableU128;
using namespace bitstep::literals;

constexpr uint64_t random_count = 1'000'000;
constexpr int64_t one_raw = int64_t{1} << 32;
constexpr int64_t half_raw = int64_t{1} << 31;

using bitstep::SplitMix64;

// A random value with |v| < 2^bits (0 <= bits <= 63), random sign; with
// `exact_bits` the top bit is set, so |v| >= 2^(bits-1).
int64_t random_raw(SplitMix64& rng, int bits, bool exact_bits = false) {
  if (bits == 0) return 0;
  uint64_t m = rng.next() >> (64 - bits);
  if (exact_bits) m |= uint64_t{1} << (bits - 1);
  return (rng.next() & 1u) != 0 ? -static_cast<int64_t>(m) : static_cast<int64_t>(m);
}

Fixed raw(int64_t r) { return Fixed::from_raw(r); }
Fixed int_(int32_t v) { return Fixed::from_int(v); }
std::string show(Fixed f) { return bitstep::to_raw_string(f) + " (" + bitstep::to_string(f) + ")"; }

uint64_t mag(int64_t v) { return bitstep::magnitude(v); }
// v sign-extended to 128 bits.
using bitstep::test::wide;
// a * b exactly (both signed).
U product(int64_t a, int64_t b) {
  const U p = U::mul(mag(a), mag(b));
  return (a < 0) != (b < 0) ? -p : p;
}
bool negative(U v) { return (v.hi() >> 63) != 0; }

// r == round(n / d), ties to even, for d > 0 (all exact).
bool rounds_correctly(int64_t r, U n, uint64_t d) {
  const U rd = r < 0 ? -U::mul(mag(r), d) : U::mul(mag(r), d);
  const U e = rd - n;
  const U abs_e = negative(e) ? -e : e;
  if (abs_e > U{d}) return false;
  const U twice = abs_e << 1;
  if (twice < U{d}) return true;
  return twice == U{d} && (r & 1) == 0;
}

bool mul_correct(int64_t a, int64_t b, int64_t r) { return rounds_correctly(r, product(a, b), uint64_t{1} << 32); }
bool div_correct(int64_t a, int64_t b, int64_t r) {
  const U n = wide(a) << 32;
  return rounds_correctly(r, b < 0 ? -n : n, mag(b));
}
bool mul_div_correct(int64_t a, int64_t b, int64_t c, int64_t r) {
  const U n = product(a, b);
  return rounds_correctly(r, c < 0 ? -n : n, mag(c));
}
bool mul_add_correct(int64_t a, int64_t b, int64_t c, int64_t r) {
  return rounds_correctly(r, product(a, b) + (wide(c) << 32), uint64_t{1} << 32);
}

}  // namespace

// ---------------------------------------------------------------------------
// Compile-time evaluation.

static_assert(Fixed::from_int(3).raw() == int64_t{3} << 32);
static_assert(Fixed::from_int(-1).raw() == -(int64_t{1} << 32));
static_assert(Fixed::from_ratio(1, 2).raw() == int64_t{1} << 31);
static_assert(Fixed::from_ratio(1, 3).raw() == 1431655765);
static_assert(Fixed::from_int(2) + Fixed::from_int(3) == Fixed::from_int(5));
static_assert(Fixed::from_int(2) - Fixed::from_int(3) == Fixed::from_int(-1));
static_assert(Fixed::from_int(6) * Fixed::from_ratio(1, 2) == Fixed::from_int(3));
static_assert(Fixed::from_int(1) / Fixed::from_int(4) == Fixed::from_ratio(1, 4));
static_assert(Fixed::from_raw(1) * Fixed::from_ratio(1, 2) == Fixed{});             // tie -> even 0
static_assert(Fixed::from_raw(3) * Fixed::from_ratio(1, 2) == Fixed::from_raw(2));  // tie -> even 2
static_assert(Fixed::from_raw(3) / Fixed::from_int(2) == Fixed::from_raw(2));
static_assert(floor(Fixed::from_ratio(-1, 2)) == Fixed::from_int(-1));
static_assert(ceil(Fixed::from_ratio(-1, 2)) == Fixed{});
static_assert(round(Fixed::from_ratio(5, 2)) == Fixed::from_int(2));
static_assert(round(Fixed::from_ratio(-3, 2)) == Fixed::from_int(-2));
static_assert(abs(Fixed::from_int(-7)) == Fixed::from_int(7));
static_assert(min(Fixed::from_int(1), Fixed::from_int(2)) == Fixed::from_int(1));
static_assert(max(Fixed::from_int(1), Fixed::from_int(2)) == Fixed::from_int(2));
static_assert(clamp(Fixed::from_int(5), Fixed::from_int(-1), Fixed::from_int(1)) == Fixed::from_int(1));
static_assert(mul_add(Fixed::from_raw(1), Fixed::from_ratio(1, 2), Fixed::from_raw(1)) == Fixed::from_raw(2));
static_assert(mul_div(Fixed::from_int(3), Fixed::from_int(5), Fixed::from_int(15)) == Fixed::from_int(1));
static_assert(Fixed::from_int(1) < Fixed::from_int(2) && Fixed::from_int(-2) <= Fixed::from_int(-2));
static_assert(0.5_fx == Fixed::from_ratio(1, 2) && -2.25_fx == Fixed::from_ratio(-9, 4));
static_assert("1/60"_fx == Fixed::from_ratio(1, 60));

// ---------------------------------------------------------------------------

TEST_CASE("the exact rounding oracle accepts only the nearest value, ties to even", "[arithmetic]") {
  // Guards the oracle the random sweeps below rely on.
  CHECK(mul_correct(1, half_raw, 0));
  CHECK_FALSE(mul_correct(1, half_raw, 1));  // 0.5 ulp: tie, 0 is even
  CHECK(mul_correct(3, half_raw, 2));
  CHECK_FALSE(mul_correct(3, half_raw, 1));  // 1.5 ulp: tie, 2 is even
  CHECK_FALSE(mul_correct(3, half_raw, 3));
  CHECK(mul_correct(-3, half_raw, -2));
  CHECK_FALSE(mul_correct(-3, half_raw, -1));
  CHECK(mul_correct(3, one_raw, 3));
  CHECK_FALSE(mul_correct(3, one_raw, 4));
  CHECK(div_correct(one_raw, 3 * one_raw, 1431655765));
  CHECK_FALSE(div_correct(one_raw, 3 * one_raw, 1431655766));
  CHECK_FALSE(div_correct(one_raw, 3 * one_raw, -1431655765));
  CHECK(div_correct(3, -2 * one_raw, -2));
  CHECK_FALSE(div_correct(3, -2 * one_raw, -1));
  CHECK(mul_div_correct(1, half_raw, half_raw, 1));
  CHECK_FALSE(mul_div_correct(1, half_raw, half_raw, 0));
  CHECK(mul_add_correct(1, half_raw, 1, 2));
  CHECK_FALSE(mul_add_correct(1, half_raw, 1, 1));
}

TEST_CASE("from_int is exact over the whole int32 range and from_ratio rounds once to nearest even", "[arithmetic]") {
  CHECK(Fixed::from_int(0).raw() == 0);
  CHECK(Fixed::from_int(1).raw() == one_raw);
  CHECK(Fixed::from_int(-1).raw() == -one_raw);
  CHECK(Fixed::from_int(INT32_MAX).raw() == int64_t{0x7FFFFFFF00000000});
  CHECK(Fixed::from_int(INT32_MIN) == Fixed::lowest());
  CHECK(Fixed::one() == Fixed::from_int(1));
  CHECK(Fixed::ulp().raw() == 1);

  CHECK(Fixed::from_ratio(1, 3).raw() == 1431655765);  // 1431655765.33
  CHECK(Fixed::from_ratio(2, 3).raw() == 2863311531);  // 2863311530.67
  CHECK(Fixed::from_ratio(-2, 3).raw() == -2863311531);
  CHECK(Fixed::from_ratio(2, -3).raw() == -2863311531);
  CHECK(Fixed::from_ratio(-2, -3).raw() == 2863311531);
  // n / 2^33 is n/2 ulp: exact ties.
  const int64_t two_33 = int64_t{1} << 33;
  CHECK(Fixed::from_ratio(1, two_33).raw() == 0);
  CHECK(Fixed::from_ratio(3, two_33).raw() == 2);
  CHECK(Fixed::from_ratio(5, two_33).raw() == 2);
  CHECK(Fixed::from_ratio(7, two_33).raw() == 4);
  CHECK(Fixed::from_ratio(-3, two_33).raw() == -2);
  CHECK(Fixed::from_ratio(-1, two_33).raw() == 0);
  CHECK(Fixed::from_ratio(INT64_MAX, INT64_MAX) == Fixed::one());
  CHECK(Fixed::from_ratio(INT64_MIN, INT64_MIN) == Fixed::one());
  CHECK(Fixed::from_ratio(INT64_MIN, one_raw) == Fixed::from_int(INT32_MIN));

  SplitMix64 rng{0xF20};
  for (uint64_t i = 0; i < random_count; ++i) {
    const int32_t v = static_cast<int32_t>(static_cast<uint32_t>(rng.next()));
    REQUIRE_QUIETLY(Fixed::from_int(v).raw() == int64_t{v} * one_raw, "from_int(" << v << ")");
    // from_ratio(n, d) = round(n 2^32 / d): the same number as raw n / raw d.
    const int lb = 1 + rng.below(63);
    const int64_t d = random_raw(rng, lb, true);
    const int64_t n = random_raw(rng, rng.below(std::min(63, lb + 29) + 1));
    const Fixed q = Fixed::from_ratio(n, d);
    REQUIRE_QUIETLY(div_correct(n, d, q.raw()), "from_ratio(" << n << ", " << d << ") = " << show(q));
    REQUIRE_QUIETLY(q == raw(n) / raw(d), "from_ratio(" << n << ", " << d << ") = " << show(q));
  }
}

TEST_CASE("+ and - are exact in range, commutative, and inverse to each other", "[arithmetic]") {
  CHECK(int_(2) + int_(3) == int_(5));
  CHECK(int_(2) - int_(3) == int_(-1));
  CHECK(raw(1) + raw(-1) == Fixed{});
  CHECK(-int_(5) == int_(-5));
  CHECK(-Fixed{} == Fixed{});
  CHECK(Fixed::max() - Fixed::max() == Fixed{});
  CHECK(Fixed::lowest() + Fixed::max() == -Fixed::ulp());
  Fixed acc = int_(1);
  acc += int_(2);
  acc -= Fixed::ulp();
  CHECK(acc.raw() == 3 * one_raw - 1);
  SplitMix64 rng{0xADD};
  for (uint64_t i = 0; i < random_count; ++i) {
    const Fixed a = raw(random_raw(rng, rng.below(63)));
    const Fixed b = raw(random_raw(rng, rng.below(63)));
    REQUIRE_QUIETLY((a + b).raw() == a.raw() + b.raw(), show(a) << " , " << show(b));
    REQUIRE_QUIETLY(a + b == b + a, show(a) << " , " << show(b));
    REQUIRE_QUIETLY((a + b) - b == a, show(a) << " , " << show(b));
    REQUIRE_QUIETLY(a - b == -(b - a), show(a) << " , " << show(b));
    REQUIRE_QUIETLY(a - b == a + (-b), show(a) << " , " << show(b));
  }
}

TEST_CASE("* rounds exact midpoints to even: raw 1 * 0.5 = 0, raw 3 * 0.5 = 2, and mirrors under negation",
          "[arithmetic]") {
  const Fixed half = Fixed::from_ratio(1, 2);
  const Fixed quarter = Fixed::from_ratio(1, 4);
  CHECK(raw(1) * half == raw(0));
  CHECK(raw(3) * half == raw(2));
  CHECK(raw(5) * half == raw(2));
  CHECK(raw(7) * half == raw(4));
  CHECK(raw(-1) * half == raw(0));
  CHECK(raw(-3) * half == raw(-2));
  CHECK(raw(-5) * half == raw(-2));
  CHECK(half * raw(3) == raw(2));
  CHECK(raw(2) * quarter == raw(0));                    // 0.5 ulp
  CHECK(raw(6) * quarter == raw(2));                    // 1.5 ulp
  CHECK(raw(1) * quarter == raw(0));                    // 0.25 ulp
  CHECK(raw(3) * quarter == raw(1));                    // 0.75 ulp
  CHECK(raw(one_raw + 1) * half == raw(half_raw));      // 2^31 + 0.5 -> 2^31 (even)
  CHECK(raw(one_raw + 3) * half == raw(half_raw + 2));  // 2^31 + 1.5 -> 2^31 + 2
  CHECK(int_(3) * int_(-4) == int_(-12));
  CHECK(Fixed::max() * Fixed::one() == Fixed::max());
  CHECK(Fixed::lowest() * Fixed::one() == Fixed::lowest());
  CHECK(int_(46340) * int_(46340) == int_(2147395600));
  Fixed m = int_(3);
  m *= half;
  CHECK(m == Fixed::from_ratio(3, 2));

  SplitMix64 rng{0x3F1};
  for (uint64_t i = 0; i < random_count; ++i) {
    // |a| < 2^la, |b| < 2^lb with la + lb <= 94: |a b| < 2^62 raw, in range.
    const int la = rng.below(64);
    const int lb = rng.below(std::min(63, 94 - la) + 1);
    int64_t a = random_raw(rng, la), b = random_raw(rng, lb);
    if ((i & 1u) != 0) std::swap(a, b);
    const Fixed p = raw(a) * raw(b);
    REQUIRE_QUIETLY(mul_correct(a, b, p.raw()), show(raw(a)) << " * " << show(raw(b)) << " = " << show(p));
    REQUIRE_QUIETLY(p == raw(b) * raw(a), show(raw(a)) << " * " << show(raw(b)) << " = " << show(p));
    REQUIRE_QUIETLY((-raw(a)) * raw(b) == -p, show(raw(a)) << " * " << show(raw(b)) << " = " << show(p));
    REQUIRE_QUIETLY(raw(a) * (-raw(b)) == -p, show(raw(a)) << " * " << show(raw(b)) << " = " << show(p));
    REQUIRE_QUIETLY((-raw(a)) * (-raw(b)) == p, show(raw(a)) << " * " << show(raw(b)) << " = " << show(p));
  }
}

TEST_CASE("/ rounds exact midpoints to even, mirrors under negation, and satisfies |q b - a| <= |b|/2",
          "[arithmetic]") {
  CHECK(raw(1) / int_(2) == raw(0));
  CHECK(raw(3) / int_(2) == raw(2));
  CHECK(raw(5) / int_(2) == raw(2));
  CHECK(raw(7) / int_(2) == raw(4));
  CHECK(raw(-3) / int_(2) == raw(-2));
  CHECK(raw(3) / int_(-2) == raw(-2));
  CHECK(raw(1) / int_(-2) == raw(0));
  CHECK(int_(1) / int_(3) == Fixed::from_ratio(1, 3));
  CHECK(int_(-7) / int_(2) == Fixed::from_ratio(-7, 2));
  CHECK(int_(1) / raw(3) == raw(6148914691236517205));  // 2^64 / 3 = ...205.33
  Fixed d = int_(9);
  d /= int_(4);
  CHECK(d == Fixed::from_ratio(9, 4));

  SplitMix64 rng{0xD1F};
  for (uint64_t i = 0; i < random_count; ++i) {
    // |b| >= 2^(lb-1) and |a| < 2^(lb+29): |a / b| < 2^62 raw.
    const int lb = 1 + rng.below(63);
    const int64_t b = random_raw(rng, lb, true);
    const int64_t a = random_raw(rng, rng.below(std::min(63, lb + 29) + 1));
    const Fixed q = raw(a) / raw(b);
    REQUIRE_QUIETLY(div_correct(a, b, q.raw()), show(raw(a)) << " / " << show(raw(b)) << " = " << show(q));
    REQUIRE_QUIETLY((-raw(a)) / raw(b) == -q, show(raw(a)) << " / " << show(raw(b)) << " = " << show(q));
    REQUIRE_QUIETLY(raw(a) / (-raw(b)) == -q, show(raw(a)) << " / " << show(raw(b)) << " = " << show(q));
    REQUIRE_QUIETLY((-raw(a)) / (-raw(b)) == q, show(raw(a)) << " / " << show(raw(b)) << " = " << show(q));
  }
}

TEST_CASE("division identities: a / 1 = a, a / -1 = -a, a / a = 1, 0 / b = 0, (a b) / b within half a step",
          "[arithmetic]") {
  SplitMix64 rng{0x1D5};
  for (uint64_t i = 0; i < random_count; ++i) {
    const int64_t a = random_raw(rng, rng.below(64));
    if (a == INT64_MIN) continue;
    REQUIRE_QUIETLY(raw(a) / Fixed::one() == raw(a), show(raw(a)));
    REQUIRE_QUIETLY(raw(a) / -Fixed::one() == -raw(a), show(raw(a)));
    if (a != 0) REQUIRE_QUIETLY(raw(a) / raw(a) == Fixed::one(), show(raw(a)));
    if (a != 0) REQUIRE_QUIETLY(Fixed{} / raw(a) == Fixed{}, show(raw(a)));
    // mul_div(a, b, b) = a exactly; mul_div(a, b, 1) = a * b; mul_div(a, 1, b) = a / b.
    const int lb = 1 + rng.below(63);
    const int64_t b = random_raw(rng, lb, true);
    REQUIRE_QUIETLY(mul_div(raw(a), raw(b), raw(b)) == raw(a), show(raw(a)) << " | "
                                                                            << "b = " << show(raw(b)));
    if (64 - std::countl_zero(mag(a)) <= lb + 29)
      REQUIRE_QUIETLY(mul_div(raw(a), Fixed::one(), raw(b)) == raw(a) / raw(b), show(raw(a)) << " | "
                                                                                             << "b = " << show(raw(b)));
    const int64_t small = random_raw(rng, rng.below(std::min(63, 94 - std::max(lb, 1)) + 1));
    REQUIRE_QUIETLY(mul_div(raw(small), raw(b), Fixed::one()) == raw(small) * raw(b), show(raw(a))
                                                                                          << " | "
                                                                                          << "b = " << show(raw(b)));
    // (s * b) / b: the product's rounding error (<= 1/2 ulp) divided by |b|,
    // plus the quotient's own 1/2 ulp: within 1 ulp of s when |b| >= 1.
    if (b >= one_raw || b <= -one_raw) {
      const Fixed p = raw(small) * raw(b);
      const Fixed back = p / raw(b);
      REQUIRE_QUIETLY(mag(back.raw() - small) <= 1, show(raw(a)) << " | "
                                                                 << "b = " << show(raw(b)));
    }
  }
  CHECK(int_(10) / int_(5) == int_(2));
  CHECK(int_(1) / Fixed::from_ratio(1, 4) == int_(4));
  CHECK(Fixed::from_int(7) / Fixed::from_int(7) == Fixed::one());
  CHECK(Fixed::max() / Fixed::max() == Fixed::one());
  CHECK(Fixed::lowest() / Fixed::lowest() == Fixed::one());
}

TEST_CASE("mul_add and mul_div round once, where rounding twice would differ", "[arithmetic]") {
  const Fixed half = Fixed::from_ratio(1, 2);
  // raw 1 * 0.5 = 0.5 ulp exactly; + 1 ulp = 1.5 ulp -> 2. Separately: 0 + 1 = 1.
  CHECK(mul_add(raw(1), half, raw(1)) == raw(2));
  CHECK(raw(1) * half + raw(1) == raw(1));
  // raw 3 * 0.5 = 1.5 ulp; - 1 ulp = 0.5 ulp -> 0. Separately: 2 - 1 = 1.
  CHECK(mul_add(raw(3), half, raw(-1)) == raw(0));
  CHECK(raw(3) * half + raw(-1) == raw(1));
  // raw 1 * 0.5 / 0.5 = 1 ulp exactly. Separately: (0) / 0.5 = 0.
  CHECK(mul_div(raw(1), half, half) == raw(1));
  CHECK(raw(1) * half / half == raw(0));
  // The product 2^40 is out of range, the quotient is not.
  CHECK(mul_div(int_(1 << 20), int_(1 << 20), int_(1 << 20)) == int_(1 << 20));
  CHECK(mul_div(int_(100000), int_(-100000), int_(-50000)) == int_(200000));
  // mul_add whose product alone (2^31) is out of range.
  CHECK(mul_add(int_(65536), int_(32768), int_(-1)) == int_(INT32_MAX));
  // One third of 2: mul_div rounds 2/3 once; 2 * (1/3) rounds twice.
  CHECK(mul_div(int_(2), int_(1), int_(3)) == Fixed::from_ratio(2, 3));
  CHECK(int_(2) * (int_(1) / int_(3)) == raw(2863311530));  // 2 * 1431655765, one ulp low

  SplitMix64 rng{0xFA5};
  for (uint64_t i = 0; i < random_count; ++i) {
    const int la = rng.below(64);
    const int lb = rng.below(std::min(63, 93 - la) + 1);
    const int64_t a = random_raw(rng, la), b = random_raw(rng, lb);
    const int64_t c = random_raw(rng, rng.below(62));
    const Fixed r = mul_add(raw(a), raw(b), raw(c));
    REQUIRE_QUIETLY(mul_add_correct(a, b, c, r.raw()),
                    "mul_add(" << show(raw(a)) << ", " << show(raw(b)) << ", " << show(raw(c)) << ") = " << show(r));
    REQUIRE_QUIETLY(mul_add(-raw(a), raw(b), -raw(c)) == -r,
                    "mul_add(" << show(raw(a)) << ", " << show(raw(b)) << ", " << show(raw(c)) << ") = " << show(r));

    // mul_div: |a| < 2^la2, |b| < 2^lb2, |c| >= 2^(lc-1), la2 + lb2 <= lc + 61.
    const int lc = 1 + rng.below(63);
    const int la2 = rng.below(std::min(63, lc + 61) + 1);
    const int lb2 = rng.below(std::min(63, lc + 61 - la2) + 1);
    const int64_t x = random_raw(rng, la2), y = random_raw(rng, lb2), z = random_raw(rng, lc, true);
    const Fixed q = mul_div(raw(x), raw(y), raw(z));
    REQUIRE_QUIETLY(mul_div_correct(x, y, z, q.raw()),
                    "mul_div(" << show(raw(x)) << ", " << show(raw(y)) << ", " << show(raw(z)) << ") = " << show(q));
    REQUIRE_QUIETLY(mul_div(-raw(x), raw(y), raw(z)) == -q,
                    "mul_div(" << show(raw(x)) << ", " << show(raw(y)) << ", " << show(raw(z)) << ") = " << show(q));
    REQUIRE_QUIETLY(mul_div(raw(y), raw(x), -raw(z)) == -q,
                    "mul_div(" << show(raw(x)) << ", " << show(raw(y)) << ", " << show(raw(z)) << ") = " << show(q));
  }
}

TEST_CASE("comparisons order Fixed exactly as their raw values", "[arithmetic]") {
  CHECK(Fixed::lowest() < -Fixed::max());
  CHECK(-Fixed::ulp() < Fixed{});
  CHECK(Fixed{} < Fixed::ulp());
  CHECK(Fixed::max() > int_(INT32_MAX));
  CHECK(int_(1) == Fixed::one());
  CHECK(int_(1) != Fixed::one() + Fixed::ulp());
  CHECK((int_(1) <=> int_(2)) == std::strong_ordering::less);
  CHECK((int_(2) <=> int_(2)) == std::strong_ordering::equal);
  SplitMix64 rng{0xC0C};
  for (uint64_t i = 0; i < random_count; ++i) {
    const int64_t a = static_cast<int64_t>(rng.next());
    const int64_t b =
        (i & 3u) == 0 ? a : ((i & 3u) == 1 ? a + (a < INT64_MAX ? 1 : 0) : static_cast<int64_t>(rng.next()));
    REQUIRE_QUIETLY((raw(a) < raw(b)) == (a < b), a << " vs " << b);
    REQUIRE_QUIETLY((raw(a) <= raw(b)) == (a <= b), a << " vs " << b);
    REQUIRE_QUIETLY((raw(a) > raw(b)) == (a > b), a << " vs " << b);
    REQUIRE_QUIETLY((raw(a) >= raw(b)) == (a >= b), a << " vs " << b);
    REQUIRE_QUIETLY((raw(a) == raw(b)) == (a == b), a << " vs " << b);
    REQUIRE_QUIETLY((raw(a) != raw(b)) == (a != b), a << " vs " << b);
    REQUIRE_QUIETLY((raw(a) <=> raw(b)) == (a <=> b), a << " vs " << b);
  }
}

TEST_CASE("abs, min, max and clamp pick exact values", "[arithmetic]") {
  CHECK(abs(int_(-3)) == int_(3));
  CHECK(abs(int_(3)) == int_(3));
  CHECK(abs(Fixed{}) == Fixed{});
  CHECK(abs(-Fixed::ulp()) == Fixed::ulp());
  CHECK(abs(-Fixed::max()) == Fixed::max());
  CHECK(min(int_(-1), int_(1)) == int_(-1));
  CHECK(max(int_(-1), int_(1)) == int_(1));
  CHECK(min(Fixed::lowest(), Fixed::max()) == Fixed::lowest());
  CHECK(max(Fixed::lowest(), Fixed::max()) == Fixed::max());
  CHECK(clamp(int_(5), int_(0), int_(3)) == int_(3));
  CHECK(clamp(int_(-5), int_(0), int_(3)) == int_(0));
  CHECK(clamp(int_(2), int_(0), int_(3)) == int_(2));
  CHECK(clamp(int_(0), int_(0), int_(3)) == int_(0));
  CHECK(clamp(int_(3), int_(0), int_(3)) == int_(3));
  SplitMix64 rng{0xAB5};
  for (uint64_t i = 0; i < random_count; ++i) {
    const Fixed a = raw(static_cast<int64_t>(rng.next()));
    const Fixed b = raw(static_cast<int64_t>(rng.next()));
    const Fixed v = raw(static_cast<int64_t>(rng.next()));
    if (a != Fixed::lowest()) {
      REQUIRE_QUIETLY(abs(a) >= Fixed{}, show(a) << ", " << show(b) << ", " << show(v));
      REQUIRE_QUIETLY(abs(a) == abs(-a), show(a) << ", " << show(b) << ", " << show(v));
      REQUIRE_QUIETLY((abs(a) == a || abs(a) == -a), show(a) << ", " << show(b) << ", " << show(v));
    }
    REQUIRE_QUIETLY(min(a, b) <= a, show(a) << ", " << show(b) << ", " << show(v));
    REQUIRE_QUIETLY(min(a, b) <= b, show(a) << ", " << show(b) << ", " << show(v));
    REQUIRE_QUIETLY((min(a, b) == a || min(a, b) == b), show(a) << ", " << show(b) << ", " << show(v));
    REQUIRE_QUIETLY(max(a, b) >= a, show(a) << ", " << show(b) << ", " << show(v));
    REQUIRE_QUIETLY(max(a, b) >= b, show(a) << ", " << show(b) << ", " << show(v));
    REQUIRE_QUIETLY((max(a, b) == a || max(a, b) == b), show(a) << ", " << show(b) << ", " << show(v));
    const Fixed lo = min(a, b), hi = max(a, b);
    const Fixed c = clamp(v, lo, hi);
    REQUIRE_QUIETLY(c >= lo, show(a) << ", " << show(b) << ", " << show(v));
    REQUIRE_QUIETLY(c <= hi, show(a) << ", " << show(b) << ", " << show(v));
    REQUIRE_QUIETLY((c == v || (v < lo && c == lo) || (v > hi && c == hi)), show(a)
                                                                                << ", " << show(b) << ", " << show(v));
  }
}

TEST_CASE("floor, ceil and round: round takes ties to even (0.5 -> 0, 1.5 -> 2, -0.5 -> 0, -1.5 -> -2, -2.5 -> -2)",
          "[arithmetic]") {
  const auto r = [](int num, int den) { return Fixed::from_ratio(num, den); };
  CHECK(round(r(1, 2)) == int_(0));
  CHECK(round(r(3, 2)) == int_(2));
  CHECK(round(r(5, 2)) == int_(2));
  CHECK(round(r(7, 2)) == int_(4));
  CHECK(round(r(-1, 2)) == int_(0));
  CHECK(round(r(-3, 2)) == int_(-2));
  CHECK(round(r(-5, 2)) == int_(-2));
  CHECK(round(r(-7, 2)) == int_(-4));
  CHECK(round(raw(half_raw - 1)) == int_(0));
  CHECK(round(raw(half_raw + 1)) == int_(1));
  CHECK(round(raw(-half_raw - 1)) == int_(-1));
  CHECK(round(raw(-half_raw + 1)) == int_(0));
  CHECK(round(Fixed::lowest()) == Fixed::lowest());
  CHECK(floor(r(1, 2)) == int_(0));
  CHECK(floor(r(-1, 2)) == int_(-1));
  CHECK(floor(-Fixed::ulp()) == int_(-1));
  CHECK(floor(int_(-3)) == int_(-3));
  CHECK(floor(Fixed::lowest()) == Fixed::lowest());
  CHECK(floor(Fixed::max()) == int_(INT32_MAX));
  CHECK(ceil(r(1, 2)) == int_(1));
  CHECK(ceil(r(-1, 2)) == int_(0));
  CHECK(ceil(Fixed::ulp()) == int_(1));
  CHECK(ceil(int_(-3)) == int_(-3));
  CHECK(ceil(Fixed::lowest()) == Fixed::lowest());
  CHECK(ceil(int_(INT32_MAX)) == int_(INT32_MAX));

  SplitMix64 rng{0xF1C};
  const int64_t largest_integer = int64_t{0x7FFFFFFF} << 32;
  for (uint64_t i = 0; i < random_count; ++i) {
    int64_t a = static_cast<int64_t>(rng.next());
    if ((i & 3u) == 0) a = (a & ~int64_t{0xFFFFFFFF}) | half_raw;  // an exact tie
    if ((i & 3u) == 1) a >>= 20;                                   // small values
    const int64_t f = floor(raw(a)).raw();
    REQUIRE_QUIETLY((f & 0xFFFFFFFF) == 0, show(raw(a)));
    REQUIRE_QUIETLY(f <= a, show(raw(a)));
    REQUIRE_QUIETLY(a - f < one_raw, show(raw(a)));
    if (a <= largest_integer) {
      const int64_t c = ceil(raw(a)).raw();
      REQUIRE_QUIETLY((c & 0xFFFFFFFF) == 0, show(raw(a)));
      REQUIRE_QUIETLY(c >= a, show(raw(a)));
      REQUIRE_QUIETLY(c - a < one_raw, show(raw(a)));
      REQUIRE_QUIETLY(c == (f == a ? a : f + one_raw), show(raw(a)));
      const int64_t n = round(raw(a)).raw();
      const int64_t fraction = a - f;
      const bool f_even = ((f >> 32) & 1) == 0;
      REQUIRE_QUIETLY(n == ((fraction < half_raw || (fraction == half_raw && f_even)) ? f : c), show(raw(a)));
      if (a > -largest_integer) {  // -floor(a), -round(a) stay in range
        REQUIRE_QUIETLY(round(-raw(a)) == -round(raw(a)), show(raw(a)));
        REQUIRE_QUIETLY(ceil(-raw(a)) == -floor(raw(a)), show(raw(a)));
      }
    }
  }
}

// The solver's forms give the bits of * and of a fused sum wherever those
// do not saturate: operands up to 2^20 in value (raw < 2^52), as the world
// envelope bounds velocities, arms and impulses far below that.
TEST_CASE("mul_in_range and sum_products_in_range equal * and the fused sum in range", "[arithmetic]") {
  SplitMix64 rng{0x51A};
  for (uint64_t i = 0; i < random_count; ++i) {
    const int64_t a0 = random_raw(rng, 52), b0 = random_raw(rng, 40), a1 = random_raw(rng, 48);
    const int64_t b1 = random_raw(rng, 44), a2 = random_raw(rng, 36), b2 = random_raw(rng, 50);
    REQUIRE_QUIETLY(mul_in_range(raw(a0), raw(b0)) == raw(a0) * raw(b0), show(raw(a0)) + " * " + show(raw(b0)));
    const Fixed as[3] = {raw(a0), raw(a1), raw(a2)}, bs[3] = {raw(b0), raw(b1), raw(b2)};
    const Fixed sum = sum_products_in_range(as, bs);
    U exact = product(a0, b0) + product(a1, b1) + product(a2, b2);
    REQUIRE_QUIETLY(rounds_correctly(sum.raw(), exact, uint64_t{1} << 32), show(sum));
  }
  // A tie rounds to even: 0.5 ulp + 1 ulp = 1.5 ulp -> 2 ulp; 0.5 ulp -> 0.
  const Fixed half_ulp[2] = {raw(1), raw(3)}, halves[2] = {raw(half_raw), raw(half_raw)};
  CHECK(sum_products_in_range(half_ulp, halves).raw() == 2);
  const Fixed one_term[1] = {raw(1)}, one_half[1] = {raw(half_raw)};
  CHECK(sum_products_in_range(one_term, one_half).raw() == 0);
}
