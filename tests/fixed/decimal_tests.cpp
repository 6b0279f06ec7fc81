#include <catch2/catch.hpp>
#include <cstdint>
#include <initializer_list>
#include <random>
#include <string>
#include <string_view>
#include <vector>

#include "fixed/decimal.h"
#include "tests/test_support.h"

using bitstep::Fixed;
using bitstep::parse_fixed;
using bitstep::ParseError;
using bitstep::to_raw_string;
using bitstep::to_string;
using namespace bitstep::literals;

namespace {

struct Case {
  std::string text;
  int64_t raw;
};

void check_parses_to(std::initializer_list<Case> cases) {
  for (const Case& c : cases) {
    INFO("parse_fixed(\"" << c.text << "\")");
    const bitstep::ParseResult r = parse_fixed(c.text);
    CHECK(bitstep::describe(r.error) == bitstep::describe(ParseError::none));
    CHECK(r.value.raw() == c.raw);
  }
}

void check_rejected(ParseError expected, std::initializer_list<std::string> texts) {
  for (const std::string& text : texts) {
    INFO("parse_fixed(\"" << text << "\")");
    CHECK(bitstep::describe(parse_fixed(text).error) == bitstep::describe(expected));
  }
}

std::string zeros(int n) { return std::string(static_cast<size_t>(n), '0'); }
std::string nines(int n) { return std::string(static_cast<size_t>(n), '9'); }

// Concatenation without `"literal" + string`, which trips gcc 12's -Wrestrict.
std::string cat(std::initializer_list<std::string_view> parts) {
  std::string out;
  for (const std::string_view part : parts) out.append(part);
  return out;
}

constexpr int64_t max_raw = INT64_MAX;
constexpr int64_t lowest_raw = INT64_MIN;
constexpr int64_t one_raw = int64_t{1} << 32;

// 0, +-1 ulp, +-max, lowest, and +-2^k, +-(2^k +- 1) for every k.
std::vector<Fixed> edge_values() {
  std::vector<Fixed> values = {Fixed{}, Fixed::ulp(), -Fixed::ulp(), Fixed::max(), -Fixed::max(), Fixed::lowest()};
  for (int k = 0; k < 63; ++k) {
    const int64_t p = int64_t{1} << k;
    for (const int64_t raw : {p - 1, p, p + 1, -(p - 1), -p, -(p + 1)}) values.push_back(Fixed::from_raw(raw));
  }
  return values;
}

// Random raw values from std::mt19937_64 (its output is fixed by the
// standard): uniform bits, log-uniform magnitudes, and short decimals k/10^j.
class RandomValues {
 public:
  Fixed next() {
    const uint64_t r = bits_();
    switch (r % 3) {
      case 0: return Fixed::from_raw(static_cast<int64_t>(bits_()));
      case 1: return Fixed::from_raw(static_cast<int64_t>(bits_()) >> (r >> 58));
      default: {
        const int j = 1 + static_cast<int>((r >> 8) % 9);
        int64_t scale = 1;
        for (int i = 0; i < j; ++i) scale *= 10;
        const uint64_t span = static_cast<uint64_t>(scale) * 2000000000u;  // |k / 10^j| < 10^9
        const int64_t k = static_cast<int64_t>(bits_() % span) - static_cast<int64_t>(span / 2);
        return Fixed::from_ratio(k, scale);
      }
    }
  }

 private:
  std::mt19937_64 bits_{20240611u};
};

int fraction_digits(const std::string& text) {
  const size_t point = text.find('.');
  return point == std::string::npos ? 0 : static_cast<int>(text.size() - point - 1);
}

// The decimals with `digits` fractional digits just below and just above |x|
// (floor and floor + 1 at that precision), with x's sign.
std::vector<std::string> neighbours(Fixed x, int digits) {
  uint64_t scale = 1;
  for (int i = 0; i < digits; ++i) scale *= 10;
  const uint64_t below = (bitstep::Wide::mul(bitstep::magnitude(x.raw()), scale) >> 32).lo();
  std::vector<std::string> out;
  for (const uint64_t d : {below, below + 1}) {
    std::string text = x.raw() < 0 ? "-" : "";
    text += std::to_string(d / scale);
    if (digits > 0) {
      const std::string fraction = std::to_string(d % scale);
      text.append(".").append(zeros(digits - static_cast<int>(fraction.size()))).append(fraction);
    }
    out.push_back(text);
  }
  return out;
}

}  // namespace

// The `_fx` literal runs parse_fixed at compile time.
static_assert((0.1_fx).raw() == 0x1999999A);
static_assert((0.05_fx).raw() == 0xCCCCCCD);
static_assert((1e-3_fx).raw() == 4294967);
static_assert((.5_fx).raw() == one_raw / 2);
static_assert((5._fx) == Fixed::from_int(5));
static_assert((1_fx) == Fixed::one());
static_assert((0_fx) == Fixed{});
static_assert((2147483647.9999999998_fx) == Fixed::max());
static_assert(("-2147483648"_fx) == Fixed::lowest());  // -2147483648_fx would be -(2147483648_fx): out of range
static_assert(("1/60"_fx).raw() == 71582788);
static_assert(("-2.5e-3"_fx).raw() == -10737418);
static_assert(("1/3"_fx) == Fixed::from_ratio(1, 3));
static_assert(("raw:-8000000000000000"_fx) == Fixed::lowest());
static_assert(("0.000000000349245965480804443359375"_fx).raw() == 2);  // 3 2^-33, a tie: to even

TEST_CASE("parse_fixed reads exact values rounded to nearest Q32.32", "[fixed][decimal]") {
  check_parses_to({
      {"0", 0},
      {"-0", 0},
      {"+0.000", 0},
      {"1", one_raw},
      {"-1", -one_raw},
      {"0.1", 0x1999999A},  // 0.1 2^32 = 429496729.6
      {"-0.1", -0x1999999A},
      {"0.05", 0xCCCCCCD},
      {"-2.5e-3", -10737418},  // -10737418.24
      {"1/60", 71582788},      // 71582788.27
      {"-2.5e-3/7", -1533917},
      {"1/-3", -0x55555555},
      {"-2/-3", 0xAAAAAAAB},
      {".5", one_raw / 2},
      {"5.", 5 * one_raw},
      {"-.5", -one_raw / 2},
      {"+5", 5 * one_raw},
      {"1E3", 1000 * one_raw},
      {"1e+3", 1000 * one_raw},
      {"5.e-1", one_raw / 2},
      {"0.0000000002328306436538696289062500", 1},  // exactly 2^-32
      {"1e-30", 0},
      {"1e-999999", 0},
      {"0e999999", 0},
      {"3.14159265358979", 0x3243F6A89},
      {"123456.789", 0x1E240C9FBE76D},
      {"2147483647", int64_t{0x7FFFFFFF} << 32},
      {"2147483647.9999999998", max_raw},
      {"-2147483648", lowest_raw},
      {"raw:1999999a", 0x1999999A},
      {"raw:1999999A", 0x1999999A},
      {"raw:-1", -1},
      {"raw:0", 0},
      {"raw:-0", 0},
      {"raw:7fffffffffffffff", max_raw},
      {"raw:-8000000000000000", lowest_raw},
  });
}

TEST_CASE("parse_fixed rounds exact midpoints between raw values to the even one", "[fixed][decimal]") {
  check_parses_to({
      {"0.000000000116415321826934814453125", 0},  // 2^-33: between 0 and 1 ulp
      {"0.000000000349245965480804443359375", 2},  // 3 2^-33: between 1 and 2
      {"0.000000000582076609134674072265625", 2},  // 5 2^-33: between 2 and 3
      {"0.000000000814907252788543701171875", 4},  // 7 2^-33: between 3 and 4
      {"-0.000000000349245965480804443359375", -2},
      {"-0.000000000116415321826934814453125", 0},
      {"1.000000000116415321826934814453125", one_raw},
      {"1.000000000349245965480804443359375", one_raw + 2},
      {"1/8589934592", 0},
      {"3/8589934592", 2},
      {"-5/8589934592", -2},
      {"0.1164153218269348144531250e-9", 0},  // the same tie written with an exponent
  });
}

TEST_CASE("parse_fixed reaches max and lowest, and the top tie and anything beyond either end is out of range",
          "[fixed][decimal]") {
  check_parses_to({
      {"2147483647.99999999976716935634613037109375", max_raw},       // max exactly
      {"2147483647.999999999883584678173065185546874", max_raw},      // just below the tie max / 2^31
      {"-2147483648.000000000116415321826934814453125", lowest_raw},  // tie lowest / lowest - 1 ulp: to even
      {"-2147483648.000000000116415321826934814453124", lowest_raw},
      {"-2147483647.9999999999", lowest_raw},
      {"-4294967296/2", lowest_raw},
  });
  check_rejected(
      ParseError::out_of_range,
      {"2147483647.999999999883584678173065185546875",    // the tie rounds to even 2^31
       "2147483647.9999999999",                           // rounds up to 2^31
       "-2147483648.0000000001164153218269348144531251",  // beyond the bottom tie
       "2147483648", "-2147483649", "4294967296/2", "1e10", "-1e10", "1e999999", "99999999999999999999", "1/1e-10",
       "raw:8000000000000000", "raw:-8000000000000001", "raw:ffffffffffffffff", "raw:10000000000000000"});
}

TEST_CASE("parse_fixed keeps a non-zero digit beyond the 60th significant digit: it breaks ties", "[fixed][decimal]") {
  const std::string tie = "0.000000000116415321826934814453125";  // 2^-33, 24 significant digits
  const std::string three_halves = "0.000000000349245965480804443359375";
  const std::string top_tie = "2147483647.999999999883584678173065185546875";
  check_parses_to({
      {cat({tie, zeros(40), "1"}), 1},  // 65 significant digits: just above the tie
      {cat({"-", tie, zeros(40), "1"}), -1},
      {cat({tie, zeros(100)}), 0},  // still exactly the tie
      {cat({three_halves, zeros(60), "1"}), 2},
      {cat({"0.000000000349245965480804443359374", nines(60)}), 1},  // just below 3 2^-33
      {cat({"116415321826934814453125", zeros(40), "1e-74"}), 1},    // the dropped digits are integer digits
      {cat({"1", zeros(69), "1e-70"}), one_raw},
      {cat({zeros(100), "1.5"}), one_raw + one_raw / 2},
      {cat({"0.", zeros(200), "1"}), 0},
      {cat({"2147483647.999999999883584678173065185546874", nines(40)}), max_raw},
  });
  check_rejected(ParseError::out_of_range, {cat({top_tie, zeros(40), "1"})});
}

TEST_CASE("parse_fixed rejects malformed text as a syntax error", "[fixed][decimal]") {
  check_rejected(ParseError::syntax,
                 {"",    "-",    "+",   ".",    "-.",      "1..2",  "1.2.3",  "1e",      "1e+",   "e5",  ".e5",
                  "abc", "1/",   "/2",  "1 /2", "1/ 2",    " 1",    "1 ",     "1/2/3",   "1e5.5", "--1", "+-1",
                  "1,5", "0x10", "1/-", "raw:", "raw:xyz", "raw:-", "raw:+1", "raw:12g", "RAW:1"});
}

TEST_CASE("parse_fixed reports a zero denominator and over-long ratio terms", "[fixed][decimal]") {
  check_rejected(ParseError::division_by_zero, {"1/0", "0/0", "-1/0.000", "5/0e10"});
  check_rejected(ParseError::too_many_digits, {cat({"1", std::string(40, '1'), "/3"}),
                                               cat({"1/", std::string(41, '1')}), cat({"1.5/3", zeros(40), "1"})});
}

// The two exponents of a ratio may cancel, so they are kept exact up to 10^9;
// a ratio term beyond that is refused rather than misread.
TEST_CASE("parse_fixed ratios cancel exponents of any size up to 10^9", "[fixed][decimal]") {
  check_parses_to({{"1e1000000/1e1000001", 0x1999999A}, {"1e-1000000/1e-1000001", 10 * one_raw},
                   {"1e999999999/1e999999999", one_raw}});
  check_rejected(ParseError::exponent_too_large, {"1e1000000001/1e1000000000", "1/1e-99999999999"});
  check_parses_to({{"1e-99999999999", 0}});
  check_rejected(ParseError::out_of_range, {"1e99999999999"});
}

TEST_CASE("parse_fixed raw values may carry leading zeros", "[fixed][decimal]") {
  check_parses_to({{"raw:00000000000000001", 1}, {"raw:-0000000000000000180000000", -0x180000000}});
  check_rejected(ParseError::syntax, {"raw:00000000000000000000x"});
  check_rejected(ParseError::out_of_range, {"raw:10000000000000000"});
}

TEST_CASE("to_string and to_raw_string give the documented text", "[fixed][decimal]") {
  CHECK(to_string(Fixed{}) == "0");
  CHECK(to_string(Fixed::one()) == "1");
  CHECK(to_string(-Fixed::one()) == "-1");
  CHECK(to_string(Fixed::from_raw(0x1999999A)) == "0.1");
  CHECK(to_string(Fixed::from_ratio(1, 3)) == "0.3333333333");
  CHECK(to_string(Fixed::from_ratio(1, 7)) == "0.142857143");
  CHECK(to_string(Fixed::from_raw(0x3243F6A89)) == "3.1415926537");
  CHECK(to_string(Fixed::from_raw(0x1E240C9FBE76D)) == "123456.789");
  CHECK(to_string(Fixed::ulp()) == "0.0000000002");
  CHECK(to_string(-Fixed::ulp()) == "-0.0000000002");
  CHECK(to_string(Fixed::one() + Fixed::ulp()) == "1.0000000002");
  CHECK(to_string(Fixed::max()) == "2147483647.9999999998");
  CHECK(to_string(Fixed::lowest()) == "-2147483648");
  CHECK(to_raw_string(Fixed{}) == "raw:0");
  CHECK(to_raw_string(Fixed::ulp()) == "raw:1");
  CHECK(to_raw_string(-Fixed::ulp()) == "raw:-1");
  CHECK(to_raw_string(Fixed::from_raw(0x1999999A)) == "raw:1999999a");
  CHECK(to_raw_string(Fixed::max()) == "raw:7fffffffffffffff");
  CHECK(to_raw_string(Fixed::lowest()) == "raw:-8000000000000000");
}

TEST_CASE("the _fx literal agrees with parse_fixed", "[fixed][decimal]") {
  CHECK(0.1_fx == parse_fixed("0.1").value);
  CHECK(1e-3_fx == parse_fixed("1e-3").value);
  CHECK("1/60"_fx == parse_fixed("1/60").value);
  CHECK(2147483647.9999999998_fx == parse_fixed("2147483647.9999999998").value);
}

// One pass for both properties: to_string (up to 11 exact parses per call)
// dominates the run time, most of all under the sanitizers (10^5 values
// there: test_support.h).
TEST_CASE(
    "to_string and to_raw_string read back to the same bits, and to_string is shortest, for the edges and "
    "10^6 random values",
    "[fixed][decimal]") {
  std::vector<Fixed> values = edge_values();
  RandomValues random;
  for (uint64_t i = 0; i < bitstep::test::samples(1000000); ++i) values.push_back(random.next());
  uint64_t not_read_back = 0, not_shortest = 0;
  for (const Fixed x : values) {
    const std::string text = to_string(x), raw_text = to_raw_string(x);
    const bitstep::ParseResult back = parse_fixed(text), raw_back = parse_fixed(raw_text);
    const int digits = fraction_digits(text);
    if (!back.ok() || back.value != x || !raw_back.ok() || raw_back.value != x || digits > 10) {
      if (++not_read_back <= 10) FAIL_CHECK(to_raw_string(x) << " -> \"" << text << "\" / \"" << raw_text << "\"");
    }
    // Both decimals with one fractional digit fewer around x (any shorter
    // text that reads back to x would be one of them) must read elsewhere.
    if (digits == 0) continue;
    for (const std::string& shorter : neighbours(x, digits - 1)) {
      const bitstep::ParseResult shorter_back = parse_fixed(shorter);
      if (!shorter_back.ok() || shorter_back.value != x) continue;
      if (++not_shortest <= 10) FAIL_CHECK("\"" << shorter << "\" reads back to " << to_raw_string(x) << " too");
    }
  }
  CHECK(not_read_back == 0);
  CHECK(not_shortest == 0);
}
