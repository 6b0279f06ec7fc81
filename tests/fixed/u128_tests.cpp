// The two 128-bit backends agree bit for bit.
//
// Every primitive of NativeU128 and PortableU128 (mul, divrem, +, -, unary -,
// <<, >>, &, |, comparisons, top_bit, count_leading_zeros) is run on 10^7
// operands, and every raw:: algorithm written over the backend (mul, div,
// mul_div, mul_add, dot3, mul_sub_mul, isqrt_floor, sqrt, rsqrt, length3,
// normalize, sin, cos, tan, atan2, asin, acos) on 10^6 operands each, through
// one comparison harness. The operands come from a seeded SplitMix64 and pass
// through __attribute__((noinline)) wrappers, so nothing is constant-folded;
// each sweep starts with an exhaustive list of boundary operands (0, 1,
// 2^32 - 1, 2^32, 2^63 - 1, 2^63, 2^64 - 1 and +-1 around each; for divrem
// every normalisation shift 0..63 and dividends with hi = 0 .. divisor - 1).
// Unoptimised builds run a tenth of the operands.
//
// The native backend's products and their rounding, one widening `imul` and
// four instructions on x86-64 (raw::wide_product, raw::bias_shift_q64_parts),
// are compared with the plain __int128 expressions, and mul, mul_in_range,
// mul_add, dot3, sum_products_in_range and mul_sub_mul over them with the
// portable backend: 10^7 operand tuples each (1.5 10^6 unoptimised), a quarter
// of the products exact ties at half an ulp or one off a tie.
//
// Without __int128 (i686) the native side does not exist; the portable mul and
// divrem are then checked against an independent bit-serial reference, which
// also runs (on fewer operands) where the native backend exists.
//
// A negative control proves the harness can fail: a portable multiply that
// drops the carry out of the middle column and a portable divrem that skips
// the second quotient-digit correction go through the same sweeps and must be
// reported, with their first mismatching operands.
#include <algorithm>
#include <array>
#include <bit>
#include <catch2/catch.hpp>
#include <cinttypes>
#include <cstdint>
#include <cstdio>
#include <string>
#include <tuple>
#include <utility>
#include <vector>

#include "fixed/checked.h"
#include "fixed/fixed.h"
#include "fixed/raw_arith.h"
#include "fixed/raw_math.h"
#include "fixed/u128.h"
#include "fixed/splitmix64.h"
#include "tests/test_support.h"

namespace {

using bitstep::PortableU128;
using bitstep::SplitMix64;

// A tenth of each in unoptimised builds (test_support.h).
constexpr uint64_t primitive_count = bitstep::test::samples(10'000'000);  // operands per U primitive
constexpr uint64_t algorithm_count = bitstep::test::samples(1'000'000);   // operands per raw:: algorithm
// In the checked build saturating operands are skipped; every algorithm must
// still compare at least 60% of its operands (17 x 600000 > 10^7 in total).
constexpr uint64_t algorithm_minimum_compared = algorithm_count / 10 * 6;


// A result as up to six 64-bit words, compared exactly.
struct Bits {
  std::array<uint64_t, 6> w{};
  friend bool operator==(const Bits&, const Bits&) = default;
};

Bits bits(uint64_t a, uint64_t b = 0, uint64_t c = 0, uint64_t d = 0, uint64_t e = 0, uint64_t f = 0) {
  return {{a, b, c, d, e, f}};
}
[[maybe_unused]] Bits bits_of(int64_t v) { return bits(static_cast<uint64_t>(v)); }

std::string show(uint64_t v) {
  char text[32];
  std::snprintf(text, sizeof text, "0x%016" PRIx64, v);
  return text;
}
[[maybe_unused]] std::string show(int64_t v) {
  char text[48];
  std::snprintf(text, sizeof text, "%" PRId64 " (raw)", v);
  return text;
}
[[maybe_unused]] std::string show(int v) { return std::to_string(v); }
std::string show(const Bits& b) {
  std::string s = "{";
  for (size_t i = 0; i < b.w.size(); ++i) s += (i ? ", " : "") + show(b.w[i]);
  return s + "}";
}

// Two's complement arithmetic on operands without signed overflow. ([[maybe_unused]]:
// without __int128 only the portable mul/divrem sweeps are compiled in.)
[[maybe_unused]] int64_t wrap_add(int64_t a, int64_t b) {
  return static_cast<int64_t>(static_cast<uint64_t>(a) + static_cast<uint64_t>(b));
}
[[maybe_unused]] int64_t wrap_neg(int64_t a) { return static_cast<int64_t>(uint64_t{0} - static_cast<uint64_t>(a)); }

// The comparison harness: counts operands, keeps the first mismatch.
class Comparison {
 public:
  explicit Comparison(std::string name) : name_(std::move(name)) {}

  template <class Tuple>
  void record(const Bits& expected, const Bits& actual, const Tuple& operands) {
    ++compared_;
    if (expected == actual) return;
    if (mismatches_++ != 0) return;
    first_operands_.clear();
    std::apply(
        [this](const auto&... op) { ((first_operands_ += (first_operands_.empty() ? "" : ", ") + show(op)), ...); },
        operands);
    first_expected_ = show(expected);
    first_actual_ = show(actual);
  }
  void skip() { ++skipped_; }

  uint64_t compared() const { return compared_; }
  uint64_t skipped() const { return skipped_; }
  uint64_t mismatches() const { return mismatches_; }
  const std::string& first_operands() const { return first_operands_; }

  std::string describe() const {
    std::string s = name_ + ": " + std::to_string(compared_) + " operands compared, " + std::to_string(skipped_) +
                    " skipped (saturating; checked build only), " + std::to_string(mismatches_) + " mismatches";
    if (mismatches_ != 0) {
      s += "\n    first mismatch at operands (" + first_operands_ + ")\n    reference " + first_expected_ +
           "\n    candidate " + first_actual_;
    }
    return s;
  }
  void print() const { std::printf("[u128] %s\n", describe().c_str()); }

 private:
  std::string name_;
  uint64_t compared_ = 0;
  uint64_t skipped_ = 0;
  uint64_t mismatches_ = 0;
  std::string first_operands_;
  std::string first_expected_;
  std::string first_actual_;
};

template <class... Args>
using Fn = Bits (*)(Args...);

// Runs `count` operand tuples (first the edge tuples, then generated ones)
// through reference and candidate. `skip` says which operands are outside
// the domain being compared (saturating ones in the checked build).
template <class... Args, class Generate, class Skip>
Comparison sweep(const std::string& name, uint64_t count, uint64_t seed, Fn<Args...> reference, Fn<Args...> candidate,
                 const std::vector<std::tuple<Args...>>& edges, Generate generate, Skip skip) {
  Comparison c(name);
  SplitMix64 rng{seed};
  for (uint64_t i = 0; i < count; ++i) {
    const std::tuple<Args...> operands = i < edges.size() ? edges[static_cast<size_t>(i)] : generate(rng);
    if (skip(operands)) {
      c.skip();
      continue;
    }
    c.record(std::apply(reference, operands), std::apply(candidate, operands), operands);
  }
  return c;
}

template <class... Args, class Generate>
Comparison sweep(const std::string& name, uint64_t count, uint64_t seed, Fn<Args...> reference, Fn<Args...> candidate,
                 const std::vector<std::tuple<Args...>>& edges, Generate generate) {
  return sweep(name, count, seed, reference, candidate, edges, generate,
               [](const std::tuple<Args...>&) { return false; });
}

// ---------------------------------------------------------------------------
// Operands.

// 0, 1, 2^32 - 1, 2^32, 2^63 - 1 (INT64_MAX), 2^63 (INT64_MIN), 2^64 - 1, and
// +-1 around each (wrapping), plus a few more powers of two.
std::vector<uint64_t> make_boundaries() {
  const uint64_t centres[] = {0,
                              1,
                              0xFFFFFFFFu,
                              uint64_t{1} << 32,
                              uint64_t{INT64_MAX},
                              uint64_t{1} << 63,
                              UINT64_MAX,
                              uint64_t{1} << 31,
                              uint64_t{1} << 62,
                              UINT64_MAX << 32};
  std::vector<uint64_t> out;
  for (uint64_t c : centres) {
    for (uint64_t v : {c - 1, c, c + 1}) {
      bool seen = false;
      for (uint64_t o : out) seen = seen || o == v;
      if (!seen) out.push_back(v);
    }
  }
  return out;
}
const std::vector<uint64_t> boundaries = make_boundaries();

constexpr uint32_t limb_patterns[] = {0, 1, 2, 0x7FFFFFFF, 0x80000000, 0x80000001, 0xFFFFFFFE, 0xFFFFFFFF};

uint64_t limb_pattern(SplitMix64& rng) {
  const uint64_t r = rng.next();
  auto limb = [&](uint64_t pick) -> uint64_t { return pick < 8 ? limb_patterns[pick] : (rng.next() & 0xFFFFFFFFu); };
  return (limb(r % 11) << 32) | limb((r >> 8) % 11);
}

// An unsigned operand: boundaries, boundaries +- a little, random bit
// lengths, 32-bit limb patterns, or uniform.
uint64_t interesting_u64(SplitMix64& rng) {
  const uint64_t r = rng.next();
  switch (r & 7u) {
    case 0: return boundaries[static_cast<size_t>((r >> 8) % boundaries.size())];
    case 1: return boundaries[static_cast<size_t>((r >> 8) % boundaries.size())] + ((r >> 40) & 7u) - 4u;
    case 2: return rng.next() >> ((r >> 8) & 63u);
    case 3: return limb_pattern(rng);
    case 4: return (uint64_t{1} << ((r >> 8) & 63u)) + ((r >> 40) & 3u) - 2u;
    default: return rng.next();
  }
}

// A signed raw operand: the same shapes with a random sign, plus values in the
// range physics uses (|x| < 2^44, i.e. 4096.0).
[[maybe_unused]] int64_t interesting_i64(SplitMix64& rng) {
  const uint64_t r = rng.next();
  uint64_t m = 0;
  switch (r & 3u) {
    case 0: m = rng.next() >> (20 + ((r >> 8) & 31u)); break;
    default: m = interesting_u64(rng); break;
  }
  return static_cast<int64_t>((r >> 63) != 0 ? uint64_t{0} - m : m);
}

[[maybe_unused]] std::vector<int64_t> signed_boundaries() {
  std::vector<int64_t> out;
  for (uint64_t b : boundaries) out.push_back(static_cast<int64_t>(b));
  for (int64_t v : {int64_t{-2}, -(int64_t{1} << 31), -(int64_t{1} << 32), -(int64_t{1} << 32) - 1,
                    -(int64_t{1} << 32) + 1, int64_t{3} << 31, -(int64_t{3} << 31)})
    out.push_back(v);
  return out;
}
const std::vector<int64_t> signed_edges = signed_boundaries();

template <class... Args>
std::vector<std::tuple<Args...>> no_edges() {
  return {};
}

// ---------------------------------------------------------------------------
// The U primitives behind noinline wrappers.

template <class U>
__attribute__((noinline)) Bits u_mul(uint64_t a, uint64_t b) {
  const U p = U::mul(a, b);
  return bits(p.hi(), p.lo());
}
template <class U>
__attribute__((noinline)) Bits u_divrem(uint64_t hi, uint64_t lo, uint64_t divisor) {
  uint64_t remainder = 0;
  const uint64_t quotient = U{hi, lo}.divrem(divisor, remainder);
  return bits(quotient, remainder);
}
template <class U>
__attribute__((noinline)) Bits u_add_sub(uint64_t ah, uint64_t al, uint64_t bh, uint64_t bl) {
  const U a{ah, al}, b{bh, bl};
  const U s = a + b, d = a - b, n = -a;
  return bits(s.hi(), s.lo(), d.hi(), d.lo(), n.hi() ^ (n.lo() << 1));
}
template <class U>
__attribute__((noinline)) Bits u_and_or(uint64_t ah, uint64_t al, uint64_t bh, uint64_t bl) {
  const U a{ah, al}, b{bh, bl};
  const U x = a & b, o = a | b;
  return bits(x.hi(), x.lo(), o.hi(), o.lo());
}
template <class U>
__attribute__((noinline)) Bits u_shifts(uint64_t hi, uint64_t lo, int n) {
  const U a{hi, lo};
  const U l = a << n, r = a >> n;
  return bits(l.hi(), l.lo(), r.hi(), r.lo(),
              static_cast<uint64_t>(bitstep::count_leading_zeros(a)) | (bitstep::top_bit(a) ? 0x100u : 0u));
}
template <class U>
__attribute__((noinline)) Bits u_compare(uint64_t ah, uint64_t al, uint64_t bh, uint64_t bl) {
  const U a{ah, al}, b{bh, bl};
  uint64_t flags = 0;
  flags |= (a == b) ? 1u : 0u;
  flags |= (a != b) ? 2u : 0u;
  flags |= (a < b) ? 4u : 0u;
  flags |= (a > b) ? 8u : 0u;
  flags |= (a <= b) ? 16u : 0u;
  flags |= (a >= b) ? 32u : 0u;
  return bits(flags);
}

// Independent references: bit-serial shift-and-add and restoring division on
// plain uint64_t words, sharing no code with either backend.
__attribute__((noinline)) Bits reference_mul(uint64_t a, uint64_t b) {
  uint64_t hi = 0, lo = 0;  // sum of (a << i) for each set bit i of b
  for (int i = 0; i < 64; ++i) {
    if (((b >> i) & 1u) == 0) continue;
    const uint64_t add_lo = a << i;
    const uint64_t add_hi = i == 0 ? 0 : a >> (64 - i);
    const uint64_t new_lo = lo + add_lo;
    hi += add_hi + (new_lo < lo ? 1u : 0u);
    lo = new_lo;
  }
  return bits(hi, lo);
}
__attribute__((noinline)) Bits reference_divrem(uint64_t hi, uint64_t lo, uint64_t divisor) {
  uint64_t remainder = hi, quotient = 0;  // hi < divisor: the first 64 quotient bits are 0
  for (int i = 63; i >= 0; --i) {
    const bool carry = (remainder >> 63) != 0;
    remainder = (remainder << 1) | ((lo >> i) & 1u);
    if (carry || remainder >= divisor) {
      remainder -= divisor;
      quotient |= uint64_t{1} << i;
    }
  }
  return bits(quotient, remainder);
}

// ---------------------------------------------------------------------------
// Negative controls: deliberately broken copies of the portable code.

// PortableU128::mul without the carry out of the middle column.
__attribute__((noinline)) Bits broken_mul_drops_middle_carry(uint64_t a, uint64_t b) {
  const uint64_t a0 = a & 0xFFFFFFFFu, a1 = a >> 32;
  const uint64_t b0 = b & 0xFFFFFFFFu, b1 = b >> 32;
  const uint64_t p00 = a0 * b0, p01 = a0 * b1, p10 = a1 * b0, p11 = a1 * b1;
  const uint64_t middle = (p00 >> 32) + (p01 & 0xFFFFFFFFu) + (p10 & 0xFFFFFFFFu);
  return bits(p11 + (p01 >> 32) + (p10 >> 32) /* + (middle >> 32) dropped */, (middle << 32) | (p00 & 0xFFFFFFFFu));
}

// PortableU128::divrem without the correction loop of the second quotient digit.
__attribute__((noinline)) Bits broken_divrem_skips_second_correction(uint64_t hi, uint64_t lo, uint64_t divisor) {
  constexpr uint64_t base = uint64_t{1} << 32;
  const int shift = std::countl_zero(divisor);
  const uint64_t v = divisor << shift;
  const uint64_t vn1 = v >> 32, vn0 = v & 0xFFFFFFFFu;
  const uint64_t un32 = shift == 0 ? hi : (hi << shift) | (lo >> (64 - shift));
  const uint64_t un10 = lo << shift;
  const uint64_t un1 = un10 >> 32, un0 = un10 & 0xFFFFFFFFu;
  uint64_t q1 = un32 / vn1;
  uint64_t rhat = un32 - q1 * vn1;
  while (q1 >= base || q1 * vn0 > base * rhat + un1) {
    --q1;
    rhat += vn1;
    if (rhat >= base) break;
  }
  const uint64_t un21 = un32 * base + un1 - q1 * v;
  const uint64_t q0 = un21 / vn1;  // no correction loop here
  const uint64_t remainder = (un21 * base + un0 - q0 * v) >> shift;
  return bits(q1 * base + q0, remainder);
}

// ---------------------------------------------------------------------------
// Sweeps over the U primitives, shared by the real comparison and the
// negative controls.

Comparison sweep_mul(const std::string& name, uint64_t count, Fn<uint64_t, uint64_t> reference,
                     Fn<uint64_t, uint64_t> candidate) {
  std::vector<std::tuple<uint64_t, uint64_t>> edges;
  for (uint64_t a : boundaries)
    for (uint64_t b : boundaries) edges.emplace_back(a, b);
  return sweep(name, count, 0x6D756C, reference, candidate, edges, [](SplitMix64& rng) {
    return std::tuple{interesting_u64(rng), interesting_u64(rng)};
  });
}

// Every divisor shape: each normalisation shift 0..63 (countl_zero of the
// divisor), 32-bit limb patterns, and dividends with hi in {0, 1, divisor - 1,
// divisor - 2, divisor / 2, random below divisor} (the precondition hi < divisor).
uint64_t dividend_hi(SplitMix64& rng, uint64_t divisor) {
  const uint64_t r = rng.next();
  switch (r & 7u) {
    case 0: return 0;
    case 1: return divisor > 1 ? 1 : 0;
    case 2: return divisor - 1;
    case 3: return divisor > 1 ? divisor - 2 : 0;
    case 4: return divisor >> 1;
    case 5: return interesting_u64(rng) % divisor;
    default: return rng.next() % divisor;
  }
}

Comparison sweep_divrem(const std::string& name, uint64_t count, Fn<uint64_t, uint64_t, uint64_t> reference,
                        Fn<uint64_t, uint64_t, uint64_t> candidate) {
  std::vector<std::tuple<uint64_t, uint64_t, uint64_t>> edges;
  std::vector<uint64_t> divisors;
  for (uint64_t d : boundaries)
    if (d != 0) divisors.push_back(d);
  for (int k = 0; k < 64; ++k) {
    const uint64_t p = uint64_t{1} << k;
    for (uint64_t d : {p, p - 1, p + 1, (p << 1) - 1, p | (p >> 1)})
      if (d != 0) divisors.push_back(d);
  }
  for (uint64_t d : divisors) {
    for (uint64_t hi : {uint64_t{0}, d > 1 ? uint64_t{1} : uint64_t{0}, d - 1, d >> 1})
      for (uint64_t lo : boundaries) edges.emplace_back(hi, lo, d);
  }
  uint64_t shift = 0;
  return sweep(name, count, 0x646976, reference, candidate, edges, [&shift](SplitMix64& rng) {
    const uint64_t top = uint64_t{1} << 63;
    const uint64_t base = (rng.next() & 1u) != 0 ? interesting_u64(rng) : limb_pattern(rng);
    const uint64_t divisor = (base | top) >> (shift++ % 64);  // countl_zero = shift
    const uint64_t hi = dividend_hi(rng, divisor);
    const uint64_t lo = (rng.next() & 1u) != 0 ? interesting_u64(rng) : rng.next();
    return std::tuple{hi, lo, divisor};
  });
}

// A 128-bit operand given as two words, often related to the other operand
// so that equal high words (and equal values) occur.
[[maybe_unused]] std::tuple<uint64_t, uint64_t, uint64_t, uint64_t> u128_pair(SplitMix64& rng) {
  const uint64_t ah = interesting_u64(rng), al = interesting_u64(rng);
  const uint64_t r = rng.next();
  switch (r & 7u) {
    case 0: return {ah, al, ah, al};
    case 1: return {ah, al, ah, al + ((r >> 8) & 3u) - 2u};
    case 2: return {ah, al, ah + ((r >> 8) & 3u) - 2u, al};
    case 3: return {ah, al, ~ah, ~al + 1u};  // roughly -a
    case 4: return {ah, al, ah, interesting_u64(rng)};
    default: return {ah, al, interesting_u64(rng), interesting_u64(rng)};
  }
}

[[maybe_unused]] std::vector<std::tuple<uint64_t, uint64_t, uint64_t, uint64_t>> u128_pair_edges() {
  std::vector<std::tuple<uint64_t, uint64_t, uint64_t, uint64_t>> edges;
  const uint64_t words[] = {0, 1, 0xFFFFFFFFu, uint64_t{1} << 63, UINT64_MAX};
  for (uint64_t ah : words)
    for (uint64_t al : words)
      for (uint64_t bh : words)
        for (uint64_t bl : words) edges.emplace_back(ah, al, bh, bl);
  return edges;
}

void require_agreement(const Comparison& c, uint64_t expected_count) {
  c.print();
  INFO(c.describe());
  CHECK(c.compared() + c.skipped() == expected_count);
  CHECK(c.mismatches() == 0);
}

}  // namespace

// ---------------------------------------------------------------------------

TEST_CASE("U::mul: native and portable 64x64->128 products agree bit for bit", "[u128]") {
#if defined(BITSTEP_HAS_NATIVE_128)
  require_agreement(
      sweep_mul("U::mul native vs portable", primitive_count, &u_mul<bitstep::NativeU128>, &u_mul<PortableU128>),
      primitive_count);
  const uint64_t reference_count = primitive_count / 10;
#else
  const uint64_t reference_count = primitive_count;
#endif
  require_agreement(
      sweep_mul("U::mul bit-serial reference vs portable", reference_count, &reference_mul, &u_mul<PortableU128>),
      reference_count);
}

TEST_CASE("U::divrem: native and portable 128/64 quotient and remainder agree for every divisor shape", "[u128]") {
#if defined(BITSTEP_HAS_NATIVE_128)
  require_agreement(sweep_divrem("U::divrem native vs portable", primitive_count, &u_divrem<bitstep::NativeU128>,
                                 &u_divrem<PortableU128>),
                    primitive_count);
  const uint64_t reference_count = primitive_count / 10;
#else
  const uint64_t reference_count = primitive_count;
#endif
  require_agreement(sweep_divrem("U::divrem restoring-division reference vs portable", reference_count,
                                 &reference_divrem, &u_divrem<PortableU128>),
                    reference_count);
}

TEST_CASE("U +, -, unary -, &, |, <<, >>, comparisons agree between native and portable", "[u128]") {
#if defined(BITSTEP_HAS_NATIVE_128)
  using bitstep::NativeU128;
  const auto edges = u128_pair_edges();
  require_agreement(sweep("U +, -, unary - native vs portable", primitive_count, 0x616464, &u_add_sub<NativeU128>,
                          &u_add_sub<PortableU128>, edges, u128_pair),
                    primitive_count);
  require_agreement(sweep("U &, | native vs portable", primitive_count, 0x616E64, &u_and_or<NativeU128>,
                          &u_and_or<PortableU128>, edges, u128_pair),
                    primitive_count);
  require_agreement(sweep("U ==, !=, <, >, <=, >= native vs portable", primitive_count, 0x636D70,
                          &u_compare<NativeU128>, &u_compare<PortableU128>, edges, u128_pair),
                    primitive_count);
  // Every shift count 0..127 in turn, on boundary and random operands.
  std::vector<std::tuple<uint64_t, uint64_t, int>> shift_edges;
  for (uint64_t hi : boundaries)
    for (uint64_t lo : {uint64_t{0}, uint64_t{1}, UINT64_MAX, uint64_t{1} << 63})
      for (int n = 0; n < 128; ++n) shift_edges.emplace_back(hi, lo, n);
  int n = 0;
  require_agreement(sweep("U <<, >>, count_leading_zeros, top_bit native vs portable", primitive_count, 0x73686C,
                          &u_shifts<NativeU128>, &u_shifts<PortableU128>, shift_edges,
                          [&n](SplitMix64& rng) {
                            return std::tuple{interesting_u64(rng), interesting_u64(rng), n++ % 128};
                          }),
                    primitive_count);
#else
  SUCCEED(
      "no __int128 on this target: only the portable backend exists (mul and divrem are checked against "
      "the bit-serial reference)");
#endif
}

// ---------------------------------------------------------------------------
// raw:: algorithms over both backends.

#if defined(BITSTEP_HAS_NATIVE_128)
namespace {

namespace raw = bitstep::raw;
using bitstep::NativeU128;
using bitstep::Wide;
using T2 = std::tuple<int64_t, int64_t>;
using T3 = std::tuple<int64_t, int64_t, int64_t>;
using T4 = std::tuple<int64_t, int64_t, int64_t, int64_t>;
using T6 = std::tuple<int64_t, int64_t, int64_t, int64_t, int64_t, int64_t>;
using T1 = std::tuple<int64_t>;

template <class U>
__attribute__((noinline)) Bits r_mul(int64_t a, int64_t b) {
  return bits_of(raw::mul<U>(a, b));
}
template <class U>
__attribute__((noinline)) Bits r_div(int64_t a, int64_t b) {
  return bits_of(raw::div<U>(a, b));
}
template <class U>
__attribute__((noinline)) Bits r_mul_div(int64_t a, int64_t b, int64_t c) {
  return bits_of(raw::mul_div<U>(a, b, c));
}
template <class U>
__attribute__((noinline)) Bits r_mul_add(int64_t a, int64_t b, int64_t c) {
  return bits_of(raw::mul_add<U>(a, b, c));
}
template <class U>
__attribute__((noinline)) Bits r_dot3(int64_t a0, int64_t b0, int64_t a1, int64_t b1, int64_t a2, int64_t b2) {
  return bits_of(raw::dot3<U>(a0, b0, a1, b1, a2, b2));
}
template <class U>
__attribute__((noinline)) Bits r_sum3_in_range(int64_t a0, int64_t b0, int64_t a1, int64_t b1, int64_t a2,
                                               int64_t b2) {
  const int64_t a[3] = {a0, a1, a2}, b[3] = {b0, b1, b2};
  return bits_of(raw::sum_products_in_range<U, 3>(a, b));
}
// An accumulator's whole state after terms that wrap its 128-bit sum for
// large operands (five times a0 b0 reaches 5 2^126 > 2^127), rounded.
template <class U>
__attribute__((noinline)) Bits r_accumulator(int64_t a0, int64_t b0, int64_t a1, int64_t b1, int64_t a2,
                                             int64_t c) {
  raw::Accumulator<U> sum;
  for (int i = 0; i < 5; ++i) sum.add_product(a0, b0);
  for (int i = 0; i < 3; ++i) sum.sub_product(a1, b1);
  sum.add_raw(c);
  sum.sub_product(a2, a2);
  bool saturated = false;
  const int64_t r = sum.to_raw(saturated);
  return bits(static_cast<uint64_t>(r), saturated ? 1u : 0u, static_cast<uint64_t>(static_cast<int64_t>(sum.wraps)),
              sum.sum.hi(), sum.sum.lo());
}
#if defined(BITSTEP_HAS_NATIVE_128)
// The native in-range sum as it was before raw::InRangeSum: the 128-bit sum
// biased and shifted as one 128-bit value (InRangeSum rounds it in 64-bit
// words). The sweep below proves the same bits, out of range too.
int64_t former_sum_in_range(const int64_t (&a)[3], const int64_t (&b)[3]) {
  raw::native_u128 sum = 0;
  for (size_t i = 0; i < 3; ++i) sum += static_cast<raw::native_u128>(raw::native_i128{a[i]} * b[i]);
  const uint64_t bias = ((uint64_t{1} << 31) - 1) + ((static_cast<uint64_t>(sum) >> 32) & 1u);
  return static_cast<int64_t>(static_cast<uint64_t>((sum + bias) >> raw::fraction_bits));
}
__attribute__((noinline)) Bits former_in_range(int64_t a0, int64_t b0, int64_t a1, int64_t b1, int64_t a2,
                                               int64_t b2) {
  const int64_t a[3] = {a0, a1, a2}, b[3] = {b0, b1, b2}, a_one[3] = {a0, 0, 0}, b_one[3] = {b0, 0, 0};
  const int64_t sum = former_sum_in_range(a, b);
  return bits(static_cast<uint64_t>(sum), static_cast<uint64_t>(sum),
              static_cast<uint64_t>(former_sum_in_range(a_one, b_one)));
}
// Today's forms on the same operands: the raw sum, the Fixed sum (its
// products taken from the Fixed values, no array of raw values) and
// mul_in_range.
__attribute__((noinline)) Bits today_in_range(int64_t a0, int64_t b0, int64_t a1, int64_t b1, int64_t a2,
                                              int64_t b2) {
  using bitstep::Fixed;
  const int64_t a[3] = {a0, a1, a2}, b[3] = {b0, b1, b2};
  const Fixed fa[3] = {Fixed::from_raw(a0), Fixed::from_raw(a1), Fixed::from_raw(a2)};
  const Fixed fb[3] = {Fixed::from_raw(b0), Fixed::from_raw(b1), Fixed::from_raw(b2)};
  return bits(static_cast<uint64_t>(raw::sum_products_in_range<NativeU128, 3>(a, b)),
              static_cast<uint64_t>(bitstep::sum_products_in_range(fa, fb).raw()),
              static_cast<uint64_t>(raw::mul_in_range<NativeU128>(a0, b0)));
}
// The native mul_sub_mul as it was: a b + (-c) d through the overflow-
// checked three-product sum, and the generic accumulator for c = INT64_MIN
// (where -c wraps) or an overflowing sum. Today's takes the 128-bit
// difference at once; the sweep below proves the same bits.
__attribute__((noinline)) Bits former_mul_sub_mul(int64_t a, int64_t b, int64_t c, int64_t d) {
  raw::native_i128 s = 0;
  bool saturated = false;
  if (c != INT64_MIN && raw::sum_products_native(a, b, -c, d, 0, 0, s)) {
    return bits_of(raw::round_q64_native(s, saturated));
  }
  raw::Accumulator<NativeU128> sum;
  sum.add_product(a, b);
  sum.sub_product(c, d);
  return bits_of(sum.to_raw(saturated));
}
__attribute__((noinline)) Bits today_mul_sub_mul(int64_t a, int64_t b, int64_t c, int64_t d) {
  return bits_of(raw::mul_sub_mul<NativeU128>(a, b, c, d));
}
#endif
template <class U>
__attribute__((noinline)) Bits r_mul_sub_mul(int64_t a, int64_t b, int64_t c, int64_t d) {
  return bits_of(raw::mul_sub_mul<U>(a, b, c, d));
}
template <class U>
__attribute__((noinline)) Bits r_isqrt_floor(uint64_t hi, uint64_t lo) {
  return bits(raw::isqrt_floor<U>(U{hi, lo}));
}
template <class U>
__attribute__((noinline)) Bits r_sqrt(int64_t a) {
  return bits_of(raw::sqrt<U>(a));
}
template <class U>
__attribute__((noinline)) Bits r_rsqrt(int64_t a) {
  return bits_of(raw::rsqrt<U>(a));
}
template <class U>
__attribute__((noinline)) Bits r_length3(int64_t x, int64_t y, int64_t z) {
  return bits_of(raw::length3<U>(x, y, z));
}
template <class U>
__attribute__((noinline)) Bits r_normalize(int64_t a, int64_t b, int64_t c, int64_t d) {
  const int64_t in[4] = {a, b, c, d};
  int64_t out[4] = {};
  // d == 0 with odd a selects the 3-component form, so both forms run.
  const int n = (d == 0 && (a & 1) != 0) ? 3 : 4;
  const bool ok = raw::normalize<U>(in, out, n);
  return bits(static_cast<uint64_t>(out[0]), static_cast<uint64_t>(out[1]), static_cast<uint64_t>(out[2]),
              static_cast<uint64_t>(out[3]), ok ? 1u : 0u);
}
template <class U>
__attribute__((noinline)) Bits r_sin(int64_t a) {
  return bits_of(raw::sin<U>(a));
}
template <class U>
__attribute__((noinline)) Bits r_cos(int64_t a) {
  return bits_of(raw::cos<U>(a));
}
template <class U>
__attribute__((noinline)) Bits r_tan(int64_t a) {
  return bits_of(raw::tan<U>(a));
}
template <class U>
__attribute__((noinline)) Bits r_atan2(int64_t y, int64_t x) {
  return bits_of(raw::atan2<U>(y, x));
}
template <class U>
__attribute__((noinline)) Bits r_asin(int64_t a) {
  return bits_of(raw::asin<U>(a));
}
template <class U>
__attribute__((noinline)) Bits r_acos(int64_t a) {
  return bits_of(raw::acos<U>(a));
}

// Saturation predicates for the checked build, from the non-faulting building
// blocks of raw_arith.h (Accumulator::to_raw and divide_magnitudes report
// saturation through a flag instead of aborting).
bool accumulator_saturates(const raw::Accumulator<Wide>& sum) {
  bool saturated = false;
  (void)sum.to_raw(saturated);
  return saturated;
}
bool mul_saturates(int64_t a, int64_t b) {
  raw::Accumulator<Wide> sum;
  sum.add_product(a, b);
  return accumulator_saturates(sum);
}
bool quotient_saturates(bool negative, Wide numerator, int64_t divisor) {
  bool saturated = false;
  (void)raw::divide_magnitudes(negative, numerator, bitstep::magnitude(divisor), saturated);
  return divisor == 0 || saturated;
}
constexpr int64_t one_raw = int64_t{1} << 32;

// Operand tuples from the signed boundaries (all pairs / the diagonal).
std::vector<T2> pair_edges() {
  std::vector<T2> e;
  for (int64_t a : signed_edges)
    for (int64_t b : signed_edges) e.emplace_back(a, b);
  return e;
}
std::vector<T1> single_edges() {
  std::vector<T1> e;
  for (int64_t a : signed_edges) e.emplace_back(a);
  return e;
}

// Half of the tuples take every operand from the range physics uses (|x| <
// 2^46 raw, i.e. 16384.0, where no product or fused sum saturates), the other
// half from the full-range shapes of interesting_i64.
int64_t physics_i64(SplitMix64& rng) {
  const uint64_t r = rng.next();
  const uint64_t m = rng.next() >> (18 + (r >> 8) % 46);
  return static_cast<int64_t>((r & 1u) != 0 ? uint64_t{0} - m : m);
}
int64_t operand(SplitMix64& rng, bool physics) { return physics ? physics_i64(rng) : interesting_i64(rng); }
bool physics_tuple(SplitMix64& rng) { return (rng.next() & 1u) != 0; }

T1 gen1(SplitMix64& rng) { return T1{operand(rng, physics_tuple(rng))}; }
// Three quarters non-negative (sqrt and rsqrt of negative values only saturate).
T1 gen1_mostly_positive(SplitMix64& rng) {
  const int64_t v = std::get<0>(gen1(rng));
  return T1{v < 0 && (rng.next() & 3u) != 0 ? wrap_neg(v) : v};
}
T2 gen2(SplitMix64& rng) {
  const bool p = physics_tuple(rng);
  return T2{operand(rng, p), operand(rng, p)};
}
T3 gen3(SplitMix64& rng) {
  const bool p = physics_tuple(rng);
  return T3{operand(rng, p), operand(rng, p), operand(rng, p)};
}
T4 gen4(SplitMix64& rng) {
  const bool p = physics_tuple(rng);
  return T4{operand(rng, p), operand(rng, p), operand(rng, p), operand(rng, p)};
}
T6 gen6(SplitMix64& rng) {
  const bool p = physics_tuple(rng);
  return T6{operand(rng, p), operand(rng, p), operand(rng, p), operand(rng, p), operand(rng, p), operand(rng, p)};
}

template <class Tuple>
auto checked_skip(bool (*saturates)(const Tuple&)) {
  return [saturates](const Tuple& t) { return bitstep::checked_build && saturates(t); };
}

struct Totals {
  uint64_t compared = 0;
  uint64_t skipped = 0;
};

void require_algorithm(const Comparison& c, Totals& totals) {
  require_agreement(c, algorithm_count);
  CHECK(c.compared() >= algorithm_minimum_compared);
  totals.compared += c.compared();
  totals.skipped += c.skipped();
}

void print_totals(const char* family, const Totals& t) {
  std::printf("[u128] raw %s: %" PRIu64 " operands compared in total, %" PRIu64 " skipped\n", family, t.compared,
              t.skipped);
}

}  // namespace
#endif

TEST_CASE("raw mul, div, mul_div, mul_add, dot3, mul_sub_mul give the same bits over both backends", "[u128]") {
#if defined(BITSTEP_HAS_NATIVE_128)
  Totals totals;
  using P = PortableU128;
  using N = NativeU128;
  require_algorithm(sweep("raw::mul", algorithm_count, 0x10, &r_mul<N>, &r_mul<P>, pair_edges(), gen2,
                          checked_skip<T2>([](const T2& t) { return mul_saturates(std::get<0>(t), std::get<1>(t)); })),
                    totals);
  require_algorithm(sweep("raw::div", algorithm_count, 0x11, &r_div<N>, &r_div<P>, pair_edges(), gen2,
                          checked_skip<T2>([](const T2& t) {
                            const auto [a, b] = t;
                            return quotient_saturates((a < 0) != (b < 0), Wide{bitstep::magnitude(a)} << 32, b);
                          })),
                    totals);
  std::vector<T3> edges3;
  for (int64_t a : signed_edges)
    for (int64_t c : signed_edges) edges3.emplace_back(a, one_raw + 1, c);
  require_algorithm(sweep("raw::mul_div", algorithm_count, 0x12, &r_mul_div<N>, &r_mul_div<P>, edges3, gen3,
                          checked_skip<T3>([](const T3& t) {
                            const auto [a, b, c] = t;
                            return quotient_saturates(((a < 0) != (b < 0)) != (c < 0),
                                                      Wide::mul(bitstep::magnitude(a), bitstep::magnitude(b)), c);
                          })),
                    totals);
  require_algorithm(sweep("raw::mul_add", algorithm_count, 0x13, &r_mul_add<N>, &r_mul_add<P>, edges3, gen3,
                          checked_skip<T3>([](const T3& t) {
                            raw::Accumulator<Wide> sum;
                            sum.add_product(std::get<0>(t), std::get<1>(t));
                            sum.add_raw(std::get<2>(t));
                            return accumulator_saturates(sum);
                          })),
                    totals);
  std::vector<T6> edges6;
  for (int64_t a : signed_edges)
    for (int64_t b : signed_edges) edges6.emplace_back(a, b, b, a, a, a);
  // Three products summed: the checked build faults where the sum saturates.
  const auto sum3_saturates = [](const T6& t) {
    raw::Accumulator<Wide> sum;
    sum.add_product(std::get<0>(t), std::get<1>(t));
    sum.add_product(std::get<2>(t), std::get<3>(t));
    sum.add_product(std::get<4>(t), std::get<5>(t));
    return accumulator_saturates(sum);
  };
  require_algorithm(sweep("raw::dot3", algorithm_count, 0x14, &r_dot3<N>, &r_dot3<P>, edges6, gen6,
                          checked_skip<T6>(sum3_saturates)),
                    totals);
  // Out of range too: the low 64 bits of the rounded sum, the same on both.
  require_algorithm(sweep("raw::sum_products_in_range", algorithm_count, 0x16, &r_sum3_in_range<N>,
                          &r_sum3_in_range<P>, edges6, gen6, checked_skip<T6>(sum3_saturates)),
                    totals);
  // The accumulator itself (the native one sums __int128 products), wraps
  // and all: no skip, it never faults.
  require_algorithm(sweep("raw::Accumulator", algorithm_count, 0x18, &r_accumulator<N>, &r_accumulator<P>, edges6, gen6),
                    totals);
  // The native in-range forms against their former 128-bit rounding.
  require_algorithm(sweep("raw::InRangeSum against the former native path", algorithm_count, 0x17, &today_in_range,
                          &former_in_range, edges6, gen6, checked_skip<T6>([](const T6& t) {
                            raw::Accumulator<Wide> sum;
                            sum.add_product(std::get<0>(t), std::get<1>(t));
                            sum.add_product(std::get<2>(t), std::get<3>(t));
                            sum.add_product(std::get<4>(t), std::get<5>(t));
                            return accumulator_saturates(sum) || mul_saturates(std::get<0>(t), std::get<1>(t));
                          })),
                    totals);
  std::vector<T4> edges4;
  for (int64_t a : signed_edges)
    for (int64_t b : signed_edges) edges4.emplace_back(a, b, b, wrap_add(a, -1));
  const auto difference_saturates = [](const T4& t) {
    raw::Accumulator<Wide> sum;
    sum.add_product(std::get<0>(t), std::get<1>(t));
    sum.sub_product(std::get<2>(t), std::get<3>(t));
    return accumulator_saturates(sum);
  };
  require_algorithm(sweep("raw::mul_sub_mul", algorithm_count, 0x15, &r_mul_sub_mul<N>, &r_mul_sub_mul<P>, edges4, gen4,
                          checked_skip<T4>(difference_saturates)),
                    totals);
  // The native mul_sub_mul against its former path, every pair of edges
  // (INT64_MIN as c and d among them).
  std::vector<T4> edges4_all;
  for (int64_t a : signed_edges)
    for (int64_t c : signed_edges) {
      edges4_all.emplace_back(a, c, c, a);
      edges4_all.emplace_back(a, a, c, c);
      edges4_all.emplace_back(c, a, INT64_MIN, c);
    }
  require_algorithm(sweep("raw::mul_sub_mul against the former native path", algorithm_count, 0x19,
                          &today_mul_sub_mul, &former_mul_sub_mul, edges4_all, gen4,
                          checked_skip<T4>(difference_saturates)),
                    totals);
  print_totals("arithmetic", totals);
#else
  SUCCEED("no __int128 on this target: there is only one backend to run the raw algorithms on");
#endif
}

#if defined(BITSTEP_HAS_NATIVE_128)
namespace {

// The native backend's products and their rounding (raw::wide_product,
// raw::bias_shift_q64_parts: one widening `imul` and four instructions on
// x86-64) against the plain __int128 expressions they replace.
__attribute__((noinline)) Bits wide_primitives(int64_t a, int64_t b) {
  const raw::native_i128 p = raw::wide_product(a, b);
  const auto u = static_cast<raw::native_u128>(p);
  uint64_t hi = static_cast<uint64_t>(u >> 64);
  const uint64_t shifted = raw::bias_shift_q64_parts(hi, static_cast<uint64_t>(u));
  bool saturated = false;
  const int64_t rounded = raw::round_q64_parts(static_cast<uint64_t>(u >> 64), static_cast<uint64_t>(u), saturated);
  return bits(static_cast<uint64_t>(u >> 64), static_cast<uint64_t>(u), shifted, hi, static_cast<uint64_t>(rounded),
              saturated ? 1u : 0u);
}
__attribute__((noinline)) Bits plain_primitives(int64_t a, int64_t b) {
  const auto u = static_cast<raw::native_u128>(raw::native_i128{a} * b);
  uint64_t hi = static_cast<uint64_t>(u >> 64), lo = static_cast<uint64_t>(u);
  raw::bias_q64_parts(hi, lo);
  const uint64_t shifted = (hi << 32) | (lo >> 32);
  // round_q64_parts as it was: the biased high word's range, then the shift.
  const int64_t top = static_cast<int64_t>(hi);
  const bool saturated = (top >> 31) != 0 && (top >> 31) != -1;
  const int64_t rounded = saturated ? (top < 0 ? INT64_MIN : INT64_MAX) : static_cast<int64_t>(shifted);
  return bits(static_cast<uint64_t>(u >> 64), static_cast<uint64_t>(u), shifted, hi, static_cast<uint64_t>(rounded),
              saturated ? 1u : 0u);
}

// One product's forms: mul, mul_in_range, mul_add (c joins the product).
template <class U>
__attribute__((noinline)) Bits r_products(int64_t a, int64_t b, int64_t c) {
  return bits(static_cast<uint64_t>(raw::mul<U>(a, b)), static_cast<uint64_t>(raw::mul_in_range<U>(a, b)),
              static_cast<uint64_t>(raw::mul_add<U>(a, b, c)));
}
// The sums: dot3, the in-range sum of three, mul_sub_mul of the first two.
template <class U>
__attribute__((noinline)) Bits r_sums(int64_t a0, int64_t b0, int64_t a1, int64_t b1, int64_t a2, int64_t b2) {
  const int64_t a[3] = {a0, a1, a2}, b[3] = {b0, b1, b2};
  return bits(static_cast<uint64_t>(raw::dot3<U>(a0, b0, a1, b1, a2, b2)),
              static_cast<uint64_t>(raw::sum_products_in_range<U, 3>(a, b)),
              static_cast<uint64_t>(raw::mul_sub_mul<U>(a0, b0, a1, b1)));
}

// A factor pair whose product is a tie (a b = (2k + 1) 2^31: half an ulp
// past a multiple of 2^32), or one off a tie, either sign: odd a times an
// odd multiple of 2^31, both below 2^46 (physics sizes) or of any size.
T2 tie_pair(SplitMix64& rng, bool physics) {
  const uint64_t r = rng.next();
  const uint64_t widths_a = physics ? 46 : 62, widths_b = physics ? 15 : 32;
  const int width_a = 1 + static_cast<int>((r >> 8) % widths_a), width_b = static_cast<int>((r >> 16) % widths_b);
  const uint64_t a_magnitude = (rng.next() >> (64 - width_a)) | 1u;
  const uint64_t b_magnitude = ((rng.next() >> (64 - width_b - 1)) | 1u) << 31;  // < 2^63
  int64_t a = static_cast<int64_t>(a_magnitude), b = static_cast<int64_t>(b_magnitude);
  if ((r & 1u) != 0) a = wrap_neg(a);
  if ((r & 2u) != 0) b = wrap_neg(b);
  switch ((r >> 2) & 7u) {
    case 0: b = wrap_add(b, 1); break;   // just past the tie
    case 1: b = wrap_add(b, -1); break;  // just before it
    default: break;
  }
  return (r & 32u) != 0 ? T2{a, b} : T2{b, a};
}
// Operand pairs: a quarter ties, the rest as the backend sweeps draw them
// (physics sizes, or the full-range shapes).
T2 product_pair(SplitMix64& rng, bool physics) {
  if ((rng.next() & 3u) == 0) return tie_pair(rng, physics);
  return T2{operand(rng, physics), operand(rng, physics)};
}
// Three quarters of the tuples of physics sizes, where the solver's products
// are (and the checked build skips fewer), a quarter full range.
bool mostly_physics(SplitMix64& rng) { return (rng.next() & 3u) != 0; }

// Edge pairs: every pair of the signed boundaries (0, +-1 raw, INT64_MIN,
// INT64_MAX, 2^32 +- 1, ...), and exact ties k 2^31 for odd k of either sign.
std::vector<T2> product_edges() {
  std::vector<T2> e = pair_edges();
  const int64_t half = int64_t{1} << 31;
  for (int64_t k : {int64_t{1}, int64_t{3}, int64_t{5}, (int64_t{1} << 32) + 1, (int64_t{1} << 32) - 1,
                    (int64_t{1} << 33) + 1, INT64_MAX, INT64_MAX - 2}) {
    for (int64_t s : {k, wrap_neg(k)}) {
      for (int64_t h : {half, wrap_neg(half), half + 1, half - 1, 3 * half, -3 * half}) {
        e.emplace_back(s, h);
        e.emplace_back(h, s);
      }
    }
  }
  return e;
}

}  // namespace
#endif

TEST_CASE("raw products and sums: the widening multiply agrees with the portable backend", "[u128]") {
#if defined(BITSTEP_HAS_NATIVE_128)
  using P = PortableU128;
  using N = NativeU128;
  // Constant evaluation takes the plain C++ forms; ties round to even there too.
  static_assert(raw::mul<N>(1, int64_t{1} << 31) == 0 && raw::mul<N>(3, int64_t{1} << 31) == 2);
  static_assert(raw::mul<N>(-1, int64_t{1} << 31) == 0 && raw::mul<N>(-3, int64_t{1} << 31) == -2);
  static_assert(raw::mul_in_range<N>(5, int64_t{1} << 31) == 2 && raw::mul_in_range<N>(-5, int64_t{1} << 31) == -2);
  const std::vector<T2> edges2 = product_edges();
  std::vector<T3> edges3;
  for (const auto& [a, b] : edges2)
    for (int64_t c : {int64_t{0}, int64_t{-1}, int64_t{1} << 32}) edges3.emplace_back(a, b, c);
  std::vector<T6> edges6;
  for (const auto& [a, b] : edges2) {
    edges6.emplace_back(a, b, 0, 0, 0, 0);
    edges6.emplace_back(a, b, b, a, a, b);
    edges6.emplace_back(a, b, wrap_neg(a), b, 1, int64_t{1} << 31);
  }
  // 10^7 operand tuples per sweep, 1.5 10^6 unoptimised: the checked build
  // skips the saturating ones and still compares more than 10^6.
  const uint64_t count = std::max<uint64_t>(primitive_count, 1'500'000);
  const uint64_t minimum_compared = 1'000'000;

  require_agreement(sweep("raw::wide_product, bias_shift_q64_parts, round_q64_parts against __int128", count,
                          0x20, &plain_primitives, &wide_primitives, edges2,
                          [](SplitMix64& rng) { return product_pair(rng, mostly_physics(rng)); }),
                    count);

  const auto products_saturate = [](const T3& t) {
    const auto [a, b, c] = t;
    raw::Accumulator<Wide> sum;
    sum.add_product(a, b);
    const bool product = accumulator_saturates(sum);
    sum.add_raw(c);
    return product || accumulator_saturates(sum);
  };
  const Comparison products = sweep("raw::mul, mul_in_range, mul_add (native against portable)", count, 0x21,
                                    &r_products<P>, &r_products<N>, edges3,
                                    [](SplitMix64& rng) {
                                      const bool physics = mostly_physics(rng);
                                      const auto [a, b] = product_pair(rng, physics);
                                      return T3{a, b, operand(rng, physics)};
                                    },
                                    checked_skip<T3>(products_saturate));
  require_agreement(products, count);
  CHECK(products.compared() >= minimum_compared);

  const auto sums_saturate = [](const T6& t) {
    raw::Accumulator<Wide> three, two;
    three.add_product(std::get<0>(t), std::get<1>(t));
    two.add_product(std::get<0>(t), std::get<1>(t));
    three.add_product(std::get<2>(t), std::get<3>(t));
    two.sub_product(std::get<2>(t), std::get<3>(t));
    three.add_product(std::get<4>(t), std::get<5>(t));
    return accumulator_saturates(three) || accumulator_saturates(two);
  };
  const Comparison sums = sweep("raw::dot3, sum_products_in_range, mul_sub_mul (native against portable)", count,
                                0x22, &r_sums<P>, &r_sums<N>, edges6,
                                [](SplitMix64& rng) {
                                  const bool physics = mostly_physics(rng);
                                  const auto [a0, b0] = product_pair(rng, physics);
                                  const auto [a1, b1] = product_pair(rng, physics);
                                  const auto [a2, b2] = product_pair(rng, physics);
                                  return T6{a0, b0, a1, b1, a2, b2};
                                },
                                checked_skip<T6>(sums_saturate));
  require_agreement(sums, count);
  CHECK(sums.compared() >= minimum_compared);
#else
  SUCCEED("no __int128 on this target: the portable backend is the only path");
#endif
}

#if defined(BITSTEP_HAS_NATIVE_128)
namespace {
// floor(sqrt(n)) by its definition, r^2 <= n < (r + 1)^2, on both backends:
// one answer whatever the seed table and the number of Newton steps.
template <class U>
bool is_floor_root(uint64_t hi, uint64_t lo) {
  const U n{hi, lo};
  const uint64_t r = raw::isqrt_floor<U>(n);
  if (U::mul(r, r) > n) return false;
  // (r + 1)^2 = 2^128 for r = 2^64 - 1: above every n.
  return r == UINT64_MAX || n < U::mul(r + 1, r + 1);
}
}  // namespace
#endif

TEST_CASE("raw isqrt_floor is floor(sqrt(n)) at every seed interval's ends", "[u128]") {
#if defined(BITSTEP_HAS_NATIVE_128)
  std::vector<std::tuple<uint64_t, uint64_t>> operands;
  // The seed table's intervals [i 2^55, (i + 1) 2^55) of the top word, at
  // each end, under every even normalisation shift.
  for (uint64_t i = 128; i < 512; ++i) {
    for (const uint64_t top : {(i << 55) - 1, i << 55, (i << 55) + 1, ((i + 1) << 55) - 1}) {
      for (const uint64_t low : {uint64_t{0}, UINT64_MAX}) {
        for (int shift = 0; shift < 128; shift += 2) {
          const PortableU128 n = PortableU128{top, low} >> shift;
          operands.emplace_back(n.hi(), n.lo());
        }
      }
    }
  }
  for (uint64_t hi : boundaries)
    for (uint64_t lo : boundaries) operands.emplace_back(hi, lo);
  SplitMix64 rng{0x5EED5};
  for (uint64_t k = 0; k < algorithm_count; ++k) {
    const uint64_t r = interesting_u64(rng);
    const PortableU128 square = PortableU128::mul(r, r);
    operands.emplace_back(rng.next() >> (rng.next() & 63u), rng.next());
    operands.emplace_back(square.hi(), square.lo());
    const PortableU128 below = square - PortableU128{1};
    operands.emplace_back(below.hi(), below.lo());
  }
  uint64_t wrong = 0;
  for (const auto& [hi, lo] : operands) {
    if (!is_floor_root<NativeU128>(hi, lo) || !is_floor_root<PortableU128>(hi, lo)) {
      if (wrong++ == 0) std::printf("isqrt_floor wrong at %s:%s\n", show(hi).c_str(), show(lo).c_str());
    }
  }
  std::printf("[u128] isqrt_floor against its definition: %zu operands, %" PRIu64 " wrong\n", operands.size(), wrong);
  CHECK(wrong == 0);
#else
  SUCCEED("no __int128 on this target");
#endif
}

TEST_CASE("raw length3 along an axis is the general root's result", "[u128]") {
#if defined(BITSTEP_HAS_NATIVE_128)
  // length3 takes |X| for a vector along an axis; the general path, the
  // root of X^2 rounded from its remainder, written out here.
  const auto general = [](int64_t v) {
    const PortableU128 sum = PortableU128::mul(bitstep::magnitude(v), bitstep::magnitude(v));
    const uint64_t root = raw::isqrt_floor<PortableU128>(sum);
    const PortableU128 excess = sum - PortableU128::mul(root, root);
    const uint64_t rounded = excess > PortableU128{root} ? root + 1 : root;
    return rounded > uint64_t{INT64_MAX} ? INT64_MAX : static_cast<int64_t>(rounded);
  };
  std::vector<int64_t> values(signed_edges.begin(), signed_edges.end());
  SplitMix64 rng{0xA815};
  for (uint64_t k = 0; k < algorithm_count / 10; ++k) {
    values.push_back(static_cast<int64_t>(rng.next() >> (rng.next() & 63u)));
  }
  uint64_t wrong = 0, compared = 0;
  for (const int64_t v : values) {
    if (bitstep::checked_build && v == INT64_MIN) continue;  // |v| = 2^63 saturates: the checked build aborts
    const int64_t expected = general(v);
    for (const int64_t got : {raw::length3<NativeU128>(v, 0, 0), raw::length3<NativeU128>(0, v, 0),
                              raw::length3<NativeU128>(0, 0, v), raw::length3<PortableU128>(v, 0, 0),
                              raw::length3<PortableU128>(0, v, 0), raw::length3<PortableU128>(0, 0, v)}) {
      ++compared;
      if (got != expected && wrong++ == 0) std::printf("length3 along an axis wrong at %s\n", show(v).c_str());
    }
  }
  std::printf("[u128] length3 along an axis against the general root: %" PRIu64 " compared, %" PRIu64 " wrong\n",
              compared, wrong);
  CHECK(wrong == 0);
#else
  SUCCEED("no __int128 on this target");
#endif
}

TEST_CASE("raw isqrt_floor, sqrt, rsqrt, length3, normalize give the same bits over both backends", "[u128]") {
#if defined(BITSTEP_HAS_NATIVE_128)
  Totals totals;
  using P = PortableU128;
  using N = NativeU128;
  // isqrt_floor on any 128-bit n: boundary words, and k^2 - 1, k^2, k^2 + 1 around squares.
  std::vector<std::tuple<uint64_t, uint64_t>> isqrt_edges;
  for (uint64_t hi : boundaries)
    for (uint64_t lo : boundaries) isqrt_edges.emplace_back(hi, lo);
  require_algorithm(sweep("raw::isqrt_floor", algorithm_count, 0x20, &r_isqrt_floor<N>, &r_isqrt_floor<P>, isqrt_edges,
                          [](SplitMix64& rng) {
                            const uint64_t r = rng.next();
                            if ((r & 1u) != 0) return std::tuple{interesting_u64(rng), interesting_u64(rng)};
                            const uint64_t k = interesting_u64(rng);
                            const PortableU128 n =
                                PortableU128::mul(k, k) + PortableU128{(r >> 8) & 3u} - PortableU128{1};
                            return std::tuple{n.hi(), n.lo()};
                          }),
                    totals);
  require_algorithm(sweep("raw::sqrt", algorithm_count, 0x21, &r_sqrt<N>, &r_sqrt<P>, single_edges(),
                          gen1_mostly_positive, checked_skip<T1>([](const T1& t) { return std::get<0>(t) < 0; })),
                    totals);
  require_algorithm(sweep("raw::rsqrt", algorithm_count, 0x22, &r_rsqrt<N>, &r_rsqrt<P>, single_edges(),
                          gen1_mostly_positive, checked_skip<T1>([](const T1& t) { return std::get<0>(t) <= 0; })),
                    totals);
  std::vector<T3> length_edges;
  for (int64_t a : signed_edges)
    for (int64_t b : signed_edges) length_edges.emplace_back(a, b, a);
  // Conservative in the checked build: with every |component| < 2^62 the
  // length is < sqrt(3) 2^62 < 2^63 and cannot saturate.
  require_algorithm(sweep("raw::length3", algorithm_count, 0x23, &r_length3<N>, &r_length3<P>, length_edges, gen3,
                          checked_skip<T3>([](const T3& t) {
                            const uint64_t limit = uint64_t{1} << 62;
                            return bitstep::magnitude(std::get<0>(t)) >= limit ||
                                   bitstep::magnitude(std::get<1>(t)) >= limit ||
                                   bitstep::magnitude(std::get<2>(t)) >= limit;
                          })),
                    totals);
  std::vector<T4> normalize_edges;
  for (int64_t a : signed_edges)
    for (int64_t b : signed_edges) {
      normalize_edges.emplace_back(a, b, 0, 0);
      normalize_edges.emplace_back(a, b, a, b);
    }
  require_algorithm(sweep("raw::normalize (3 and 4 components)", algorithm_count, 0x24, &r_normalize<N>,
                          &r_normalize<P>, normalize_edges,
                          [](SplitMix64& rng) {
                            const int64_t d = (rng.next() & 1u) != 0 ? 0 : interesting_i64(rng);
                            return T4{interesting_i64(rng), interesting_i64(rng), interesting_i64(rng), d};
                          }),
                    totals);
  print_totals("square roots", totals);
#else
  SUCCEED("no __int128 on this target: there is only one backend to run the raw algorithms on");
#endif
}

#if defined(BITSTEP_HAS_NATIVE_128)
namespace {
// Raw values near k pi/2 (where tan has its poles and the argument reduction
// is tightest), from pi/2 in Q2.62.
T1 near_quarter_turn(SplitMix64& rng) {
  constexpr uint64_t half_pi_q62 = 0x6487ED5110B4611Au;
  const uint64_t r = rng.next();
  const uint64_t k = (r & 1u) != 0 ? (r >> 1) % 1367130551u : (r >> 1) % 64u;  // k pi/2 < 2^31
  const uint64_t centre = (PortableU128::mul(k, half_pi_q62) >> 30).lo();
  const uint64_t m = centre + ((r >> 40) & 15u) - 8u;
  return T1{(rng.next() & 1u) != 0 ? static_cast<int64_t>(uint64_t{0} - m) : static_cast<int64_t>(m)};
}
T1 trig_operand(SplitMix64& rng) { return (rng.next() & 3u) == 0 ? near_quarter_turn(rng) : gen1(rng); }
// Mostly inside [-1, 1] (raw |a| <= 2^32), some outside.
T1 unit_operand(SplitMix64& rng) {
  const uint64_t r = rng.next();
  if ((r & 7u) == 0) return gen1(rng);
  const uint64_t m = (r & 8u) != 0 ? (uint64_t{1} << 32) - ((r >> 8) & 0xFFFFu) : (r >> 16) % ((uint64_t{1} << 32) + 1);
  return T1{(r & 16u) != 0 ? -static_cast<int64_t>(m) : static_cast<int64_t>(m)};
}
bool outside_unit(const T1& t) { return bitstep::magnitude(std::get<0>(t)) > (uint64_t{1} << 32); }
}  // namespace
#endif

TEST_CASE("raw sin, cos, tan, atan2, asin, acos give the same bits over both backends", "[u128]") {
#if defined(BITSTEP_HAS_NATIVE_128)
  Totals totals;
  using P = PortableU128;
  using N = NativeU128;
  std::vector<T1> trig_edges = single_edges();
  for (uint64_t k = 0; k < 64; ++k) {
    constexpr uint64_t half_pi_q62 = 0x6487ED5110B4611Au;
    const int64_t centre = static_cast<int64_t>((PortableU128::mul(k, half_pi_q62) >> 30).lo());
    for (int64_t d = -3; d <= 3; ++d) {
      trig_edges.emplace_back(centre + d);
      trig_edges.emplace_back(-centre - d);
    }
  }
  require_algorithm(sweep("raw::sin", algorithm_count, 0x30, &r_sin<N>, &r_sin<P>, trig_edges, trig_operand), totals);
  require_algorithm(sweep("raw::cos", algorithm_count, 0x31, &r_cos<N>, &r_cos<P>, trig_edges, trig_operand), totals);
  // tan saturates within ~2 ulp of a pole (|tan| >= 2^31 needs |cos| < 2^-31):
  // the checked build skips every operand whose cosine rounds to <= 4 ulp.
  require_algorithm(sweep("raw::tan", algorithm_count, 0x32, &r_tan<N>, &r_tan<P>, trig_edges, trig_operand,
                          checked_skip<T1>([](const T1& t) {
                            const int64_t c = raw::cos<Wide>(std::get<0>(t));
                            return bitstep::magnitude(c) <= 4;
                          })),
                    totals);
  std::vector<T2> atan2_edges = pair_edges();
  for (int64_t a : signed_edges) {
    atan2_edges.emplace_back(a, wrap_neg(a));
    atan2_edges.emplace_back(a, a);
  }
  require_algorithm(
      sweep("raw::atan2", algorithm_count, 0x33, &r_atan2<N>, &r_atan2<P>, atan2_edges,
            [](SplitMix64& rng) {
              const uint64_t r = rng.next();
              const int64_t y = interesting_i64(rng);
              // |y| = |x| (the octant switch) and |y| / |x| near the
              // table points j/8 and the switch points (2j + 1)/16
              // of the atan reduction, in both octants.
              if ((r & 7u) == 0) return T2{y, (r & 8u) != 0 ? y : wrap_neg(y)};
              if ((r & 7u) == 1) return T2{y, wrap_add(y, static_cast<int64_t>((r >> 8) & 7u) - 4)};
              if ((r & 7u) == 2) {
                const int64_t x = physics_i64(rng);
                const uint64_t sixteenths = (r >> 8) % 17;  // ratio sixteenths / 16 in [0, 1]
                const int64_t scaled =
                    static_cast<int64_t>((PortableU128::mul(bitstep::magnitude(x), sixteenths) >> 4).lo());
                const int64_t ratio_y = wrap_add(x < 0 ? -scaled : scaled, static_cast<int64_t>((r >> 16) & 7u) - 4);
                return (r & 8u) != 0 ? T2{ratio_y, x} : T2{x, ratio_y};
              }
              return T2{y, interesting_i64(rng)};
            }),
      totals);
  std::vector<T1> unit_edges = single_edges();
  for (int64_t d = -4; d <= 4; ++d) {
    unit_edges.emplace_back(one_raw + d);
    unit_edges.emplace_back(-one_raw + d);
    unit_edges.emplace_back(d);
    unit_edges.emplace_back((one_raw >> 1) + d);
  }
  require_algorithm(sweep("raw::asin", algorithm_count, 0x34, &r_asin<N>, &r_asin<P>, unit_edges, unit_operand,
                          checked_skip<T1>(outside_unit)),
                    totals);
  require_algorithm(sweep("raw::acos", algorithm_count, 0x35, &r_acos<N>, &r_acos<P>, unit_edges, unit_operand,
                          checked_skip<T1>(outside_unit)),
                    totals);
  print_totals("trigonometry", totals);
#else
  SUCCEED("no __int128 on this target: there is only one backend to run the raw algorithms on");
#endif
}

// ---------------------------------------------------------------------------
// Negative controls.

TEST_CASE("negative control: the harness reports a portable mul that drops the middle-column carry", "[u128]") {
#if defined(BITSTEP_HAS_NATIVE_128)
  const Fn<uint64_t, uint64_t> reference = &u_mul<bitstep::NativeU128>;
#else
  const Fn<uint64_t, uint64_t> reference = &reference_mul;
#endif
  const Comparison c = sweep_mul("negative control: broken mul (middle carry dropped)", primitive_count / 10, reference,
                                 &broken_mul_drops_middle_carry);
  c.print();
  INFO(c.describe());
  REQUIRE(c.mismatches() > 0);
  CHECK(!c.first_operands().empty());
  // The sweep still agrees when the carry cannot occur: the broken variant is
  // only wrong where the middle column overflows, which the report pinpoints.
  CHECK(c.mismatches() < c.compared());
}

TEST_CASE("negative control: the harness reports a portable divrem that skips the second correction", "[u128]") {
#if defined(BITSTEP_HAS_NATIVE_128)
  const Fn<uint64_t, uint64_t, uint64_t> reference = &u_divrem<bitstep::NativeU128>;
#else
  const Fn<uint64_t, uint64_t, uint64_t> reference = &reference_divrem;
#endif
  const Comparison c = sweep_divrem("negative control: broken divrem (second correction skipped)", primitive_count / 10,
                                    reference, &broken_divrem_skips_second_correction);
  c.print();
  INFO(c.describe());
  REQUIRE(c.mismatches() > 0);
  CHECK(!c.first_operands().empty());
  CHECK(c.mismatches() < c.compared());
}
