// Measured accuracy of every fixed/ function (see tests/fixed/fixed_accuracy.h).
//
// Each function gets edge operands (0, +-1 ulp, +-max, lowest, powers of two
// and their neighbours, plus its own special points) and `random_samples`
// random ones from a seeded SplitMix64 sampler. Operands whose correct result
// lies outside the range are skipped, never fed: the checked build aborts on
// any saturation.
//
// Errors are in ulps (raw units, 2^-32) against
//  - "exact": the true result as an integer floor plus a remainder fraction,
//    from unsigned __int128 arithmetic on the raw operands (or, for decimal
//    text, decimal long division on digit strings). Only the last step, the
//    size of the fraction, is a long double, and whether an error exceeds
//    1/2 (the bound of every exact row) is decided with integers.
//  - "long double": sinl, cosl, tanl, atan2l, asinl, acosl, 1/sqrtl on the
//    exact input (a raw int64 times 2^-32 is exact in long double's 64-bit
//    mantissa); their own error is ~2^-63 relative, far below an ulp here.
#include "tests/fixed/fixed_accuracy.h"

#if !defined(__SIZEOF_INT128__)
#error "tests/fixed/fixed_accuracy.cpp needs unsigned __int128: it is built natively on 64-bit hosts only"
#endif

#include <algorithm>
#include <array>
#include <bit>
#include <cmath>
#include <initializer_list>
#include <limits>
#include <numbers>
#include <optional>
#include <span>
#include <string>
#include <string_view>

#include "fixed/decimal.h"
#include "fixed/splitmix64.h"
#include "fixed/vec3.h"

namespace bitstep {

namespace {

__extension__ typedef __int128 i128;
__extension__ typedef unsigned __int128 u128;

constexpr long double raw_per_unit = 4294967296.0L;  // 2^32 raw = 1.0
constexpr i128 one_raw = i128{1} << 32;
constexpr long double infinite_error = std::numeric_limits<long double>::infinity();
constexpr const char* exact_reference = "exact";
constexpr const char* long_double_reference = "long double";

template <size_t N>
using Ops = std::array<int64_t, N>;

// ---------------------------------------------------------------------------
// Exact results and their errors

// An error just computed in long double, put on the side of 1/2 that exact
// integer arithmetic says it is on.
long double settle_half(long double error, bool within_half) {
  if (within_half && error > 0.5L) return 0.5L;
  if (!within_half && error <= 0.5L) return std::nextafter(0.5L, 1.0L);
  return error;
}

// numerator / denominator for numerator <= denominator.
long double fraction_ulps(u128 numerator, u128 denominator) {
  const long double error = static_cast<long double>(numerator) / static_cast<long double>(denominator);
  return settle_half(error, numerator <= denominator - numerator);
}

// A true result in raw units: floor + remainder / denominator.
struct Exact {
  i128 floor = 0;
  u128 remainder = 0;  // 0 <= remainder < denominator
  u128 denominator = 1;

  // To nearest, ties to even: the correctly rounded raw value.
  i128 rounded() const {
    const u128 rest = denominator - remainder;
    const bool up = remainder > rest || (remainder == rest && (floor & 1) != 0);
    return up ? floor + 1 : floor;
  }
  bool fits() const {
    const i128 r = rounded();
    return r >= std::numeric_limits<int64_t>::min() && r <= std::numeric_limits<int64_t>::max();
  }
  // |result - true value| in ulps.
  long double error(int64_t result) const {
    const i128 steps = i128{result} - floor;
    if (steps == 0) return fraction_ulps(remainder, denominator);
    if (steps == 1) return fraction_ulps(denominator - remainder, denominator);
    const long double fraction = static_cast<long double>(remainder) / static_cast<long double>(denominator);
    return std::fabs(static_cast<long double>(steps) - fraction);  // >= 1 either way
  }
};

// +-(whole + remainder / denominator) as an Exact.
Exact signed_exact(bool negative, u128 whole, u128 remainder, u128 denominator) {
  if (!negative) return {static_cast<i128>(whole), remainder, denominator};
  if (remainder == 0) return {-static_cast<i128>(whole), 0, denominator};
  return {-static_cast<i128>(whole) - 1, denominator - remainder, denominator};
}

u128 magnitude128(i128 v) { return v < 0 ? u128{0} - static_cast<u128>(v) : static_cast<u128>(v); }

// numerator / divisor (divisor != 0).
Exact quotient(i128 numerator, int64_t divisor) {
  const u128 n = magnitude128(numerator), d = magnitude(divisor);
  return signed_exact((numerator < 0) != (divisor < 0), n / d, n % d, d);
}

i128 product(int64_t a, int64_t b) { return i128{a} * b; }

// A sum of Q64.64 terms (products of raw values) in raw units, i.e. / 2^32.
// Each term is split into floor and low 32 bits first, so the sum of up to
// three terms of magnitude 2^126 never needs more than 128 bits.
Exact q64_sum(std::initializer_list<i128> terms) {
  constexpr u128 low_mask = 0xFFFFFFFFu;
  i128 whole = 0;
  u128 low = 0;
  for (const i128 term : terms) {
    whole += term >> 32;  // arithmetic shift: the floor
    low += static_cast<u128>(term) & low_mask;
  }
  return {whole + static_cast<i128>(low >> 32), low & low_mask, low_mask + 1};
}

// |result - sqrt(n)| in ulps for an integer n, from the exact residual:
// |R - sqrt n| = |R^2 - n| / (R + sqrt n). sqrt n is never a half-integer, so
// round(sqrt n) = R exactly when R^2 - R < n <= R^2 + R.
long double root_error(int64_t result, u128 n) {
  if (result < 0) return infinite_error;
  const u128 r = static_cast<u128>(result);
  const u128 square = r * r;
  const bool within_half = (r == 0 || square - r < n) && n <= square + r;
  const u128 residual = square > n ? square - n : n - square;
  const long double scale = static_cast<long double>(r) + std::sqrt(static_cast<long double>(n));
  const long double error = scale == 0.0L ? 0.0L : static_cast<long double>(residual) / scale;
  return settle_half(error, within_half);
}

// ---------------------------------------------------------------------------
// Recording the worst case of one function

// The smallest double >= error, so that a bound check on the double is never
// more lenient than on the long double.
double round_up(long double error) {
  double d = static_cast<double>(error);
  if (static_cast<long double>(d) < error) d = std::nextafter(d, std::numeric_limits<double>::infinity());
  return d;
}

std::string describe(std::span<const int64_t> operands) {
  std::string text;
  for (const int64_t v : operands) {
    if (!text.empty()) text += ", ";
    text += to_raw_string(Fixed::from_raw(v)) + " (" + to_string(Fixed::from_raw(v)) + ")";
  }
  return text;
}

class Row {
 public:
  Row(const char* function, const char* reference, double bound) : row_{function, reference, bound, 0.0, "", 0} {}

  void record(long double error, std::span<const int64_t> operands) {
    if (is_new_worst(error)) row_.worst_input = describe(operands);
  }
  void record(long double error, const std::string& text) {
    if (is_new_worst(error)) row_.worst_input = "\"" + text + "\"";
  }
  AccuracyRow finish() const { return row_; }

 private:
  bool is_new_worst(long double error) {
    ++row_.samples;
    if (std::isnan(error)) error = infinite_error;
    if (row_.samples > 1 && error <= worst_) return false;
    worst_ = error;
    row_.worst_ulps = round_up(error);
    return true;
  }

  AccuracyRow row_;
  long double worst_ = 0.0L;
};

// ---------------------------------------------------------------------------
// Operands

int bit_length(int64_t v) { return 64 - std::countl_zero(magnitude(v)); }

// Random operands from SplitMix64 (Steele, Lea, Flood 2014), seeded per row.
class Sampler {
 public:
  explicit Sampler(std::string_view function) {
    for (const char c : function) rng_.state = (rng_.state ^ static_cast<uint8_t>(c)) * 0x100000001B3u;  // FNV-1a
  }

  uint64_t next() { return rng_.next(); }
  int below(int n) { return rng_.below(n); }
  bool coin() { return (next() & 1u) != 0; }
  int bits() { return 1 + below(64); }

  // A raw value with |v| < 2^bits (any int64 for bits >= 64): a third
  // uniform raw bits, a third log-uniform magnitudes, a third small values
  // (a few ulps, or a multiple of 1/2 up to 16 give or take two ulps).
  int64_t operand(int bits) {
    bits = std::clamp(bits, 1, 64);
    uint64_t m = 0;
    switch (below(3)) {
      case 0:
        if (bits == 64) return static_cast<int64_t>(next());
        m = next() >> (64 - bits);
        break;
      case 1: {
        const int length = 1 + below(std::min(bits, 63));
        m = (next() >> (64 - length)) | (uint64_t{1} << (length - 1));
        break;
      }
      default:
        m = coin() ? static_cast<uint64_t>(below(17)) : magnitude((int64_t{below(33)} << 31) + below(5) - 2);
        break;
    }
    if (bits < 64) m &= (uint64_t{1} << bits) - 1;
    m &= uint64_t{INT64_MAX};
    return coin() ? -static_cast<int64_t>(m) : static_cast<int64_t>(m);
  }
  int64_t operand() { return operand(64); }

 private:
  SplitMix64 rng_{0xCBF29CE484222325u};
};

// Calls check on every edge operand set, then on random ones from draw until
// `count` were accepted (check returns false for operands outside the
// function's range; the attempt cap only guards against a bad sampler, and
// would show as a sample count below the requested one).
template <class Operands, class Check, class Draw>
void sweep(const std::vector<Operands>& edges, uint64_t count, Check check, Draw draw) {
  for (const Operands& o : edges) check(o);
  uint64_t accepted = 0;
  for (uint64_t attempts = 0; accepted < count && attempts < 64 * count + 64; ++attempts) {
    if (check(draw())) ++accepted;
  }
}

int64_t negate(int64_t v) { return v == INT64_MIN ? INT64_MAX : -v; }

// 0, +-1 ulp, +-max, lowest and +-2^k, +-(2^k +- 1 ulp) for k = 0 .. 62
// (2^-32 .. 2^30), or for a few k only when `coarse`.
std::vector<int64_t> edge_values(bool coarse = false) {
  std::vector<int64_t> values = {0, 1, -1, INT64_MAX, -INT64_MAX, INT64_MIN};
  for (int k = 0; k <= 62; ++k) {
    if (coarse && k != 1 && k != 16 && k != 31 && k != 32 && k != 33 && k != 47 && k != 62) continue;
    const int64_t p = int64_t{1} << k;
    for (const int64_t v : {p - 1, p, p + 1}) {
      values.push_back(v);
      values.push_back(-v);
    }
  }
  return values;
}

// Raw values nearest +-k * step and their +-1 ulp neighbours, for small k and
// huge k up to the end of the range (raw 2^63 is 1367130551.2 quarter turns):
// where the argument reduction of sin, cos and tan is most delicate.
std::vector<int64_t> multiples_of(long double step) {
  std::vector<int64_t> values;
  for (long double k : {1.0L, 2.0L, 3.0L, 4.0L, 5.0L, 8.0L, 100.0L, 1e4L, 1e6L, 1e8L, 1e9L, 1367130551.0L}) {
    const long double raw = k * step * raw_per_unit;
    if (raw >= 9.2e18L) continue;
    const int64_t nearest = std::llround(raw);
    for (const int64_t v : {nearest - 1, nearest, nearest + 1}) {
      values.push_back(v);
      values.push_back(-v);
    }
  }
  return values;
}

std::vector<Ops<1>> singles(const std::vector<int64_t>& values) {
  std::vector<Ops<1>> out;
  for (const int64_t v : values) out.push_back({v});
  return out;
}
std::vector<Ops<2>> pairs(const std::vector<int64_t>& values) {
  std::vector<Ops<2>> out;
  for (const int64_t a : values) {
    for (const int64_t b : values) out.push_back({a, b});
  }
  return out;
}
std::vector<Ops<3>> triples(const std::vector<int64_t>& values) {
  std::vector<Ops<3>> out;
  for (const int64_t a : values) {
    for (const Ops<2>& bc : pairs(values)) out.push_back({a, bc[0], bc[1]});
  }
  return out;
}

// Vectors from the coarse edge values: along each axis, on the diagonal, with
// a mixed sign; with `planar` also every (e, f, 0).
std::vector<Ops<3>> edge_vectors(bool planar) {
  std::vector<Ops<3>> out;
  const std::vector<int64_t> values = edge_values(true);
  for (const int64_t e : values) {
    for (const Ops<3>& v :
         {Ops<3>{e, 0, 0}, Ops<3>{0, e, 0}, Ops<3>{0, 0, e}, Ops<3>{e, e, e}, Ops<3>{e, negate(e), e}}) {
      out.push_back(v);
    }
    if (!planar) continue;
    for (const int64_t f : values) out.push_back({e, f, 0});
  }
  return out;
}
std::vector<Ops<6>> edge_vector_pairs() {
  std::vector<Ops<6>> out;
  const std::vector<Ops<3>> vectors = edge_vectors(false);
  for (const Ops<3>& a : vectors) {
    for (const Ops<3>& b : vectors) out.push_back({a[0], a[1], a[2], b[0], b[1], b[2]});
  }
  return out;
}

Ops<3> random_vector(Sampler& s, int bits) {
  const int64_t x = s.operand(bits), y = s.operand(bits), z = s.operand(bits);
  return {x, y, z};
}
// Two vectors whose component products stay below 2^94 (raw 2^62).
Ops<6> random_vector_pair(Sampler& s) {
  const int a_bits = s.bits();
  const Ops<3> a = random_vector(s, a_bits), b = random_vector(s, 94 - a_bits);
  return {a[0], a[1], a[2], b[0], b[1], b[2]};
}

Fixed fx(int64_t raw) { return Fixed::from_raw(raw); }
Vec3 vec(int64_t x, int64_t y, int64_t z) { return {fx(x), fx(y), fx(z)}; }

// ---------------------------------------------------------------------------
// Rows

using MaybeError = std::optional<long double>;

// One row: error(operands) is the error in ulps, or nullopt for operands
// outside the function's range (skipped); draw(sampler) gives random operands.
template <size_t N, class Error, class Draw>
AccuracyRow measure(const char* function, const char* reference, double bound, const std::vector<Ops<N>>& edges,
                    uint64_t count, Error error, Draw draw) {
  Row row(function, reference, bound);
  Sampler s(function);
  sweep(
      edges, count,
      [&](const Ops<N>& o) {
        const MaybeError e = error(o);
        if (e) row.record(*e, o);
        return e.has_value();
      },
      [&] { return draw(s); });
  return row.finish();
}

// The error of result() against an exact true value; nullopt, without
// calling result() (the checked build would abort), when it does not fit.
template <class Result>
MaybeError exact_error(const Exact& exact, Result result) {
  if (!exact.fits()) return std::nullopt;
  return exact.error(result().raw());
}

// a, b with |a b| < 2^95: raw products up to about the end of the range.
Ops<2> random_factors(Sampler& s) {
  const int64_t a = s.operand();
  return {a, s.operand(95 - bit_length(a))};
}

u128 sum_of_squares(const Ops<3>& v) {  // < 3 2^126
  u128 sum = 0;
  for (const int64_t c : v) sum += u128{magnitude(c)} * magnitude(c);
  return sum;
}

AccuracyRow measure_mul(uint64_t count) {
  return measure<2>(
      "mul", exact_reference, 0.5, pairs(edge_values()), count,
      [](const Ops<2>& o) { return exact_error(q64_sum({product(o[0], o[1])}), [&] { return fx(o[0]) * fx(o[1]); }); },
      random_factors);
}

AccuracyRow measure_div(uint64_t count) {
  return measure<2>(
      "div", exact_reference, 0.5, pairs(edge_values()), count,
      [](const Ops<2>& o) -> MaybeError {
        if (o[1] == 0) return std::nullopt;
        return exact_error(quotient(o[0] * one_raw, o[1]), [&] { return fx(o[0]) / fx(o[1]); });
      },
      [](Sampler& s) {
        const int64_t b = s.operand();
        return Ops<2>{s.operand(bit_length(b) + 31), b};  // quotients up to about the end of the range
      });
}

AccuracyRow measure_mul_add(uint64_t count) {
  return measure<3>(
      "mul_add", exact_reference, 0.5, triples(edge_values(true)), count,
      [](const Ops<3>& o) {
        return exact_error(q64_sum({product(o[0], o[1]), o[2] * one_raw}),
                           [&] { return mul_add(fx(o[0]), fx(o[1]), fx(o[2])); });
      },
      [](Sampler& s) {
        const Ops<2> ab = random_factors(s);
        return Ops<3>{ab[0], ab[1], s.operand(s.bits())};
      });
}

AccuracyRow measure_mul_div(uint64_t count) {
  return measure<3>(
      "mul_div", exact_reference, 0.5, triples(edge_values(true)), count,
      [](const Ops<3>& o) -> MaybeError {
        if (o[2] == 0) return std::nullopt;
        return exact_error(quotient(product(o[0], o[1]), o[2]), [&] { return mul_div(fx(o[0]), fx(o[1]), fx(o[2])); });
      },
      [](Sampler& s) {
        const int64_t a = s.operand(), c = s.operand();
        return Ops<3>{a, s.operand(63 + bit_length(c) - bit_length(a)), c};
      });
}

AccuracyRow measure_dot(uint64_t count) {
  return measure<6>(
      "dot", exact_reference, 0.5, edge_vector_pairs(), count,
      [](const Ops<6>& o) {
        const Exact exact = q64_sum({product(o[0], o[3]), product(o[1], o[4]), product(o[2], o[5])});
        return exact_error(exact, [&] { return dot(vec(o[0], o[1], o[2]), vec(o[3], o[4], o[5])); });
      },
      random_vector_pair);
}

AccuracyRow measure_cross(uint64_t count) {
  return measure<6>(
      "cross", exact_reference, 0.5, edge_vector_pairs(), count,
      [](const Ops<6>& o) -> MaybeError {
        std::array<Exact, 3> exact;
        for (size_t i = 0; i < 3; ++i) {  // component i = a_j b_k - a_k b_j for (i, j, k) cyclic
          const size_t j = (i + 1) % 3, k = (i + 2) % 3;
          exact[i] = q64_sum({product(o[j], o[3 + k]), -product(o[k], o[3 + j])});
          if (!exact[i].fits()) return std::nullopt;
        }
        const Vec3 c = cross(vec(o[0], o[1], o[2]), vec(o[3], o[4], o[5]));
        return std::max({exact[0].error(c.x.raw()), exact[1].error(c.y.raw()), exact[2].error(c.z.raw())});
      },
      random_vector_pair);
}

AccuracyRow measure_length_sq(uint64_t count) {
  return measure<3>(
      "length_sq", exact_reference, 0.5, edge_vectors(true), count,
      [](const Ops<3>& o) {
        const Exact exact = q64_sum({product(o[0], o[0]), product(o[1], o[1]), product(o[2], o[2])});
        return exact_error(exact, [&] { return length_sq(vec(o[0], o[1], o[2])); });
      },
      [](Sampler& s) { return random_vector(s, 1 + s.below(48)); });
}

AccuracyRow measure_sqrt(uint64_t count) {
  return measure<1>(
      "sqrt", exact_reference, 0.5, singles(edge_values()), count,
      [](const Ops<1>& o) -> MaybeError {
        if (o[0] < 0) return std::nullopt;
        // sqrt(A 2^-32) = sqrt(A 2^32) 2^-32.
        return root_error(sqrt(fx(o[0])).raw(), static_cast<u128>(o[0]) << 32);
      },
      [](Sampler& s) { return Ops<1>{s.operand() & INT64_MAX}; });
}

AccuracyRow measure_length(uint64_t count) {
  return measure<3>(
      "length", exact_reference, 0.5, edge_vectors(true), count,
      [](const Ops<3>& o) -> MaybeError {
        const u128 sum = sum_of_squares(o);
        // round(sqrt(sum)) <= INT64_MAX exactly when sum <= M^2 + M, M = 2^63 - 1.
        constexpr u128 largest = (u128{1} << 126) - (u128{1} << 63);
        if (sum > largest) return std::nullopt;
        return root_error(length(vec(o[0], o[1], o[2])).raw(), sum);
      },
      [](Sampler& s) { return random_vector(s, s.bits()); });
}

long double to_long_double(int64_t raw) { return static_cast<long double>(raw) / raw_per_unit; }  // exact
long double raw_error(Fixed result, long double reference) {
  return std::fabs(static_cast<long double>(result.raw()) - reference * raw_per_unit);
}

// A one-argument function against a long double reference on the domain
// |a| <= limit (and a > 0 when positive_only), sampled with |a| < 2^sample_bits.
struct UnarySpec {
  const char* name;
  double bound;
  Fixed (*function)(Fixed);
  long double (*reference)(long double);
  uint64_t limit;
  bool positive_only;
  int sample_bits;
};

AccuracyRow measure_unary(const UnarySpec& spec, std::vector<int64_t> edges, uint64_t count) {
  const std::vector<int64_t> common = edge_values();
  edges.insert(edges.end(), common.begin(), common.end());
  return measure<1>(
      spec.name, long_double_reference, spec.bound, singles(edges), count,
      [&](const Ops<1>& o) -> MaybeError {
        if (magnitude(o[0]) > spec.limit || (spec.positive_only && o[0] <= 0)) return std::nullopt;
        return raw_error(spec.function(fx(o[0])), spec.reference(to_long_double(o[0])));
      },
      [&](Sampler& s) {
        const int64_t a = s.operand(spec.sample_bits);
        return Ops<1>{spec.positive_only ? a & INT64_MAX : a};
      });
}

AccuracyRow measure_atan2(uint64_t count) {
  return measure<2>(
      "atan2", long_double_reference, 2.0, pairs(edge_values()), count,
      [](const Ops<2>& o) -> MaybeError {
        // atan2(y 2^-32, x 2^-32) = atan2(y, x): the raw values as they are.
        const long double want = std::atan2(static_cast<long double>(o[0]), static_cast<long double>(o[1]));
        return raw_error(atan2(fx(o[0]), fx(o[1])), want);
      },
      [](Sampler& s) {
        return Ops<2>{s.operand(), s.operand()};
      });
}

AccuracyRow measure_normalize(uint64_t count) {
  return measure<3>(
      "normalize", long_double_reference, 1.0, edge_vectors(true), count,
      [](const Ops<3>& o) -> MaybeError {
        const u128 sum = sum_of_squares(o);
        const long double norm = std::sqrt(static_cast<long double>(sum));  // |v| in raw units
        const Vec3 n = normalize(vec(o[0], o[1], o[2]));
        const std::array<Fixed, 3> got = {n.x, n.y, n.z};
        long double worst = 0.0L;
        for (size_t i = 0; i < 3; ++i) {
          worst = std::max(worst, raw_error(got[i], sum == 0 ? 0.0L : static_cast<long double>(o[i]) / norm));
        }
        return worst;
      },
      [](Sampler& s) { return random_vector(s, s.bits()); });
}

// ---------------------------------------------------------------------------
// Decimal text: an independent exact reference by decimal long division on
// digit strings (parse_fixed divides binary big integers).

// A written decimal: value = digits (as an integer) * 10^exponent.
struct DecimalText {
  bool negative = false;
  std::string digits;
  int exponent = 0;
};

// Reads the texts this file writes: [+-]digits[.digits][(e|E)[+-]digits].
DecimalText read_decimal_text(std::string_view text) {
  DecimalText d;
  size_t pos = 0;
  if (pos < text.size() && (text[pos] == '+' || text[pos] == '-')) d.negative = text[pos++] == '-';
  bool after_point = false;
  for (; pos < text.size() && text[pos] != 'e' && text[pos] != 'E'; ++pos) {
    if (text[pos] == '.') {
      after_point = true;
      continue;
    }
    d.digits.push_back(text[pos]);
    if (after_point) --d.exponent;
  }
  if (pos < text.size()) d.exponent += std::stoi(std::string(text.substr(pos + 1)));
  return d;
}

std::string strip_leading_zeros(std::string_view digits) {
  const size_t first = digits.find_first_not_of('0');
  return first == std::string_view::npos ? std::string() : std::string(digits.substr(first));
}

u128 digits_value(std::string_view digits) {  // at most 38 digits
  u128 v = 0;
  for (const char c : digits) v = v * 10 + static_cast<u128>(c - '0');
  return v;
}

std::string digits_of(u128 v) {
  std::string out;
  do {
    out.insert(out.begin(), static_cast<char>('0' + static_cast<int>(v % 10)));
    v /= 10;
  } while (v != 0);
  return out;
}

// digits *= factor, on decimal digit strings.
void multiply_digits(std::string& digits, uint32_t factor) {
  uint64_t carry = 0;
  for (auto it = digits.rbegin(); it != digits.rend(); ++it) {
    const uint64_t t = static_cast<uint64_t>(*it - '0') * factor + carry;
    *it = static_cast<char>('0' + static_cast<int>(t % 10));
    carry = t / 10;
  }
  for (; carry != 0; carry /= 10) digits.insert(digits.begin(), static_cast<char>('0' + static_cast<int>(carry % 10)));
}

// The raw value (value * 2^32) of a / b exactly; nullopt when it rounds
// outside the range. b's digits are non-zero and fewer than 18.
std::optional<Exact> exact_raw_value(const DecimalText& a, const DecimalText& b) {
  std::string numerator = strip_leading_zeros(a.digits);
  if (numerator.empty()) return Exact{};
  const uint64_t divisor = static_cast<uint64_t>(digits_value(strip_leading_zeros(b.digits)));
  multiply_digits(numerator, 1u << 16);
  multiply_digits(numerator, 1u << 16);
  // raw = numerator 10^exponent / divisor >= 2^32 10^exponent / 10^18.
  const int exponent = a.exponent - b.exponent;
  if (exponent > 28) return std::nullopt;  // raw > 2^63
  constexpr size_t kept_fraction_digits = 36;
  const int appended = std::max(0, 40 + exponent);
  numerator.append(static_cast<size_t>(appended), '0');
  std::string digits;  // numerator / divisor, `appended - exponent` (>= 40) of them after the point
  uint64_t rest = 0;
  for (const char c : numerator) {
    rest = rest * 10 + static_cast<uint64_t>(c - '0');  // < 10 divisor < 2^64
    digits.push_back(static_cast<char>('0' + static_cast<int>(rest / divisor)));
    rest %= divisor;
  }
  const size_t fraction_length = static_cast<size_t>(appended - exponent);
  if (digits.size() < fraction_length) digits.insert(0, fraction_length - digits.size(), '0');
  const std::string whole = strip_leading_zeros(std::string_view(digits).substr(0, digits.size() - fraction_length));
  if (whole.size() > 20) return std::nullopt;
  const std::string_view fraction = std::string_view(digits).substr(digits.size() - fraction_length);
  u128 remainder = digits_value(fraction.substr(0, kept_fraction_digits));
  u128 denominator = digits_value("1" + std::string(kept_fraction_digits, '0'));
  // Digits beyond the kept ones only need to count as "a bit more": 0 and
  // 1/2, where rounding and the 1/2 ulp bound are decided, lie on the grid.
  if (rest != 0 || fraction.substr(kept_fraction_digits).find_first_not_of('0') != std::string_view::npos) {
    remainder = remainder * 10 + 1;
    denominator *= 10;
  }
  const Exact exact = signed_exact(a.negative != b.negative, digits_value(whole), remainder, denominator);
  if (!exact.fits()) return std::nullopt;
  return exact;
}

// Parses text with parse_fixed and records its error; false when the text
// is outside the range (after checking that parse_fixed says so).
bool check_parse(Row& row, const std::string& text) {
  const size_t slash = text.find('/');
  const DecimalText a = read_decimal_text(std::string_view(text).substr(0, slash));
  const DecimalText b = slash == std::string::npos ? DecimalText{false, "1", 0}
                                                   : read_decimal_text(std::string_view(text).substr(slash + 1));
  const ParseResult parsed = parse_fixed(text);
  if (strip_leading_zeros(b.digits).empty()) {
    if (parsed.error != ParseError::division_by_zero) row.record(infinite_error, text);
    return false;
  }
  const std::optional<Exact> exact = exact_raw_value(a, b);
  if (!exact) {
    if (parsed.error != ParseError::out_of_range) row.record(infinite_error, text);
    return false;
  }
  row.record(parsed.ok() ? exact->error(parsed.value.raw()) : infinite_error, text);
  return true;
}

// A random decimal of `length` random digits with the point at a random place
// and an exponent that makes the value < 10^order; random sign and spelling.
std::string random_decimal(Sampler& s, int length, int order) {
  std::string digits;
  for (int i = 0; i < length; ++i) digits.push_back(static_cast<char>('0' + s.below(10)));
  const int point = s.below(length + 1);  // digits before the point
  std::string text = s.coin() ? "-" : (s.below(8) == 0 ? "+" : "");
  if (point == 0 && s.coin()) text += '0';
  text += digits.substr(0, static_cast<size_t>(point));
  if (point < length || s.coin()) text += '.';
  text += digits.substr(static_cast<size_t>(point));
  const int exponent = order - point;
  if (exponent != 0 || s.below(8) == 0) {
    text += s.coin() ? 'e' : 'E';
    if (exponent >= 0 && s.coin()) text += '+';
    text += std::to_string(exponent);
  }
  return text;
}

// The exact decimal text of (2 r + 1) 2^-33, the midpoint between raw r and
// r + 1 (a tie), or that moved away from / towards zero by 10^-(33 + extra).
std::string midpoint_text(int64_t r, int nudge, int extra) {
  std::string digits = digits_of(magnitude128(2 * i128{r} + 1));
  for (int i = 0; i < 3; ++i) multiply_digits(digits, 48828125);  // 5^11: (2r + 1) 5^33 = value 10^33
  size_t fraction_length = 33;
  if (nudge > 0) digits += std::string(static_cast<size_t>(extra - 1), '0') + "1";
  if (nudge < 0) {
    --digits.back();  // an odd multiple of 5 ends in 5: no borrow
    digits += std::string(static_cast<size_t>(extra), '9');
  }
  if (nudge != 0) fraction_length += static_cast<size_t>(extra);
  if (digits.size() <= fraction_length) digits.insert(0, fraction_length + 1 - digits.size(), '0');
  const size_t point = digits.size() - fraction_length;  // >= 1 after the padding
  std::string text = r < 0 ? "-" : "";
  return text.append(digits, 0, point).append(".").append(digits, point);
}

std::string random_parse_text(Sampler& s) {
  switch (s.below(8)) {
    case 0:
    case 1:
    case 2: return random_decimal(s, 1 + s.below(20), s.below(23) - 12);
    case 3: return random_decimal(s, 25 + s.below(56), s.below(23) - 12);
    case 4:
    case 5: {
      const int64_t r = s.operand();
      const int nudge = s.below(3) - 1;
      return midpoint_text(r, nudge, 1 + s.below(40));
    }
    case 6: {
      const std::string numerator = random_decimal(s, 1 + s.below(12), s.below(15) - 4);
      return numerator + "/" + random_decimal(s, 1 + s.below(12), s.below(11) - 4);
    }
    default: return to_string(fx(s.operand()));
  }
}

// Known values, spellings, range ends, and ties (k 2^-33 for odd k) met
// exactly, just above and just below, also past 60 significant digits.
std::vector<std::string> parse_edges() {
  // clang-format off
  std::vector<std::string> texts = {
      "0", "-0", "+0", "0.0", "1", "-1", "0.1", "-2.5e-3", "1/60", "-1/3", "2/3", ".5", "5.", "-.5", "1e-30", "1E+3",
      "2147483647", "2147483647.9999999998", "-2147483648", "-2147483647.9999999998",
      "1/8589934592", "3/8589934592", "-1/4294967296", "1e9", "-1e9", "1e10", "1e-10", "1e-11"};
  // clang-format on
  texts.push_back("3.14159265358979323846264338327950288419716939937510582097494459230781640628620899862803482534");
  for (const int64_t r : {int64_t{0}, int64_t{1}, int64_t{-1}, INT64_MAX - 1, INT64_MAX, INT64_MIN}) {
    for (const int nudge : {-1, 0, 1}) {
      for (const int extra : {1, 10, 50}) texts.push_back(midpoint_text(r, nudge, extra));
    }
  }
  return texts;
}

AccuracyRow measure_parse(uint64_t count) {
  Row row("parse", exact_reference, 0.5);
  Sampler s("parse");
  sweep(
      parse_edges(), count, [&](const std::string& text) { return check_parse(row, text); },
      [&] { return random_parse_text(s); });
  return row.finish();
}

}  // namespace

std::vector<AccuracyRow> measure_accuracy(uint64_t random_samples) {
  constexpr long double pi = std::numbers::pi_v<long double>;
  constexpr uint64_t whole_range = uint64_t{1} << 63;
  constexpr uint64_t one = uint64_t{1} << 32;
  const uint64_t n = random_samples;
  const std::vector<int64_t> tan_edges = {INT64_C(0x180000000), -INT64_C(0x180000000), INT64_C(0x17FFFFFFF),
                                          -INT64_C(0x17FFFFFFF)};  // +-1.5
  std::vector<int64_t> quarter_pi = multiples_of(pi / 4);
  quarter_pi.insert(quarter_pi.end(), tan_edges.begin(), tan_edges.end());
  const std::vector<int64_t> half_pi = multiples_of(pi / 2);
  return {
      measure_mul(n),
      measure_div(n),
      measure_mul_add(n),
      measure_mul_div(n),
      measure_dot(n),
      measure_cross(n),
      measure_length_sq(n),
      measure_sqrt(n),
      measure_length(n),
      measure_unary({"rsqrt", 1.0, [](Fixed a) { return rsqrt(a); }, [](long double x) { return 1.0L / std::sqrt(x); },
                     whole_range, true, 64},
                    {}, n),
      measure_normalize(n),
      measure_unary({"sin", 1.0, [](Fixed a) { return sin(a); }, [](long double x) { return std::sin(x); }, whole_range,
                     false, 64},
                    half_pi, n),
      measure_unary({"cos", 1.0, [](Fixed a) { return cos(a); }, [](long double x) { return std::cos(x); }, whole_range,
                     false, 64},
                    half_pi, n),
      measure_unary({"tan", 1.0, [](Fixed a) { return tan(a); }, [](long double x) { return std::tan(x); },
                     one + one / 2, false, 33},
                    quarter_pi, n),
      measure_atan2(n),
      measure_unary(
          {"asin", 2.0, [](Fixed a) { return asin(a); }, [](long double x) { return std::asin(x); }, one, false, 33},
          {}, n),
      measure_unary(
          {"acos", 2.0, [](Fixed a) { return acos(a); }, [](long double x) { return std::acos(x); }, one, false, 33},
          {}, n),
      measure_parse(n),
  };
}

}  // namespace bitstep
