// Exact text <-> Fixed.
//
// parse_fixed reads
//   decimal   [+-]digits[.digits][(e|E)[+-]digits]   also ".5" and "5."
//   ratio     decimal/decimal                         e.g. "1/60", "-2.5e-3/7"
//   raw       raw:[-]hex                              the int64 raw value
// and rounds the exact rational value once to the nearest Q32.32 value, ties to
// even. Values beyond the range are errors, not saturation; values too small
// to represent round to 0. It is constexpr: the `_fx` literal uses it at
// compile time.
//
// to_string gives the shortest decimal text that parses back to the same bits
// (at most 10 fractional digits, since 1e-10 < 1 ulp); to_raw_string the raw form.
#pragma once

#include <cstdint>
#include <string>
#include <string_view>

#include "fixed/big_uint.h"
#include "fixed/fixed.h"

namespace bitstep {

enum class ParseError { none, syntax, out_of_range, division_by_zero, too_many_digits, exponent_too_large };

constexpr const char* describe(ParseError e) {
  switch (e) {
    case ParseError::none: return "ok";
    case ParseError::syntax: return "not a number (expected decimal, ratio a/b or raw:<hex>)";
    case ParseError::out_of_range: return "outside the Q32.32 range [-2147483648, 2147483647.99999999977]";
    case ParseError::division_by_zero: return "ratio with a zero denominator";
    case ParseError::too_many_digits: return "more than 40 significant digits in a ratio term";
    case ParseError::exponent_too_large: return "exponent beyond +-10^9 in a ratio term";
  }
  return "unknown error";
}

struct ParseResult {
  Fixed value;
  ParseError error = ParseError::none;
  constexpr bool ok() const { return error == ParseError::none; }
};

namespace decimal_detail {

using Big = BigUint<16>;

// A decimal number as mantissa * 10^exponent, with the mantissa's digit count.
struct Decimal {
  Big mantissa;
  int64_t exponent = 0;
  int64_t digits = 0;  // significant digits kept in the mantissa
  bool negative = false;
  bool truncated = false;           // non-zero digits were dropped beyond max_digits
  bool exponent_saturated = false;  // the written exponent exceeded +-10^9
};

// Written exponents are exact up to this magnitude. A single decimal beyond it
// is far out of range (or rounds to 0) either way; a ratio term beyond it is
// an error, because the two exponents of a ratio may cancel.
inline constexpr int64_t exponent_limit = 1000000000;

constexpr bool is_digit(char c) { return c >= '0' && c <= '9'; }

// Parses one decimal from text[pos..], advancing pos. Keeps max_digits
// significant digits; any non-zero digit beyond them sets `truncated`.
constexpr bool read_decimal(std::string_view text, size_t& pos, int max_digits, Decimal& out) {
  if (pos < text.size() && (text[pos] == '+' || text[pos] == '-')) out.negative = text[pos++] == '-';
  bool any_digit = false, seen_point = false;
  int64_t dropped_integer_digits = 0, kept_fraction_digits = 0;
  for (; pos < text.size(); ++pos) {
    const char c = text[pos];
    if (c == '.' && !seen_point) {
      seen_point = true;
      continue;
    }
    if (!is_digit(c)) break;
    any_digit = true;
    const uint32_t d = static_cast<uint32_t>(c - '0');
    if (out.digits == 0 && d == 0) {  // leading zero: only its position matters
      if (seen_point) ++kept_fraction_digits;
      continue;
    }
    if (out.digits < max_digits) {
      out.mantissa.mul_small(10);
      out.mantissa.add_small(d);
      ++out.digits;
      if (seen_point) ++kept_fraction_digits;
    } else {
      if (d != 0) out.truncated = true;
      if (!seen_point) ++dropped_integer_digits;
    }
  }
  if (!any_digit) return false;
  int64_t exponent = 0;
  if (pos < text.size() && (text[pos] == 'e' || text[pos] == 'E')) {
    ++pos;
    bool exponent_negative = false;
    if (pos < text.size() && (text[pos] == '+' || text[pos] == '-')) exponent_negative = text[pos++] == '-';
    if (pos >= text.size() || !is_digit(text[pos])) return false;
    for (; pos < text.size() && is_digit(text[pos]); ++pos) {
      exponent = exponent * 10 + (text[pos] - '0');
      if (exponent > exponent_limit) {
        exponent = exponent_limit;
        out.exponent_saturated = true;
      }
    }
    if (exponent_negative) exponent = -exponent;
  }
  out.exponent = exponent + dropped_integer_digits - kept_fraction_digits;
  return true;
}

// round(numerator / denominator) as a signed raw value, ties to even; both
// are exact and the denominator non-zero.
constexpr ParseResult round_ratio(bool negative, const Big& numerator, const Big& denominator) {
  // The largest magnitude is 2^63 (for -2^31); anything >= 2^63 + 1/2 is out.
  Big limit = denominator;
  limit.shift_left(63);
  const int versus_limit = numerator.compare(limit);
  if (versus_limit > 0 && !negative) return {Fixed{}, ParseError::out_of_range};
  if (versus_limit >= 0) {
    // >= 2^63: only exactly 2^63 .. 2^63 + 1/2 (rounding to the even 2^63) is -2^31.
    Big excess = numerator;
    excess.subtract(limit);
    excess.shift_left(1);
    if (!negative || excess.compare(denominator) > 0) return {Fixed{}, ParseError::out_of_range};
    return {Fixed::lowest(), ParseError::none};
  }
  Big remainder;
  uint64_t q = divide_small_quotient(numerator, denominator, 63, remainder);
  remainder.shift_left(1);
  const int half = remainder.compare(denominator);
  if (half > 0 || (half == 0 && (q & 1u) != 0)) ++q;  // q <= 2^63
  if (q == (uint64_t{1} << 63)) {
    if (!negative) return {Fixed{}, ParseError::out_of_range};
    return {Fixed::lowest(), ParseError::none};
  }
  const int64_t magnitude_raw = static_cast<int64_t>(q);
  return {Fixed::from_raw(negative ? -magnitude_raw : magnitude_raw), ParseError::none};
}

// value = (a / b) * 10^exponent rounded; a, b are mantissas (b != 0) and
// `magnitude_exponent` bounds log10 of the value: value < 10^magnitude_exponent.
constexpr ParseResult round_scaled(bool negative, Big a, Big b, int64_t exponent, int64_t magnitude_upper,
                                   int64_t magnitude_lower) {
  if (magnitude_lower >= 10) return {Fixed{}, ParseError::out_of_range};  // >= 1e10 > 2^31
  if (magnitude_upper < -10) return {Fixed{}, ParseError::none};          // < 1e-11 < half an ulp
  a.shift_left(32);
  if (exponent > 0) a.mul_pow10(static_cast<int>(exponent));  // |exponent| <= 10 + 61 here
  if (exponent < 0) b.mul_pow10(static_cast<int>(-exponent));
  if (a.overflow || b.overflow) return {Fixed{}, ParseError::too_many_digits};
  return round_ratio(negative, a, b);
}

constexpr int hex_value(char c) {
  if (c >= '0' && c <= '9') return c - '0';
  if (c >= 'a' && c <= 'f') return c - 'a' + 10;
  if (c >= 'A' && c <= 'F') return c - 'A' + 10;
  return -1;
}

constexpr ParseResult parse_raw(std::string_view hex) {
  bool negative = false;
  if (!hex.empty() && hex[0] == '-') {
    negative = true;
    hex.remove_prefix(1);
  }
  if (hex.empty()) return {Fixed{}, ParseError::syntax};
  for (char c : hex) {
    if (hex_value(c) < 0) return {Fixed{}, ParseError::syntax};
  }
  while (hex.size() > 1 && hex[0] == '0') hex.remove_prefix(1);  // leading zeros carry no value
  if (hex.size() > 16) return {Fixed{}, ParseError::out_of_range};
  uint64_t v = 0;
  for (char c : hex) v = (v << 4) | static_cast<uint64_t>(hex_value(c));
  const uint64_t limit = uint64_t{1} << 63;
  if (v > limit || (v == limit && !negative)) return {Fixed{}, ParseError::out_of_range};
  return {Fixed::from_raw(static_cast<int64_t>(negative ? uint64_t{0} - v : v)), ParseError::none};
}

}  // namespace decimal_detail

constexpr ParseResult parse_fixed(std::string_view text) {
  using namespace decimal_detail;
  if (text.substr(0, 4) == "raw:") return parse_raw(text.substr(4));

  // Single decimals keep 60 significant digits: any value in range has its
  // first digit at 10^9 or below, so digits 10^-51 and finer are dropped, and
  // every rounding boundary (a multiple of 2^-33, 33 decimal places) lies on
  // the kept grid: a dropped non-zero tail only needs to count as "a bit more".
  constexpr int single_digits = 60;
  constexpr int ratio_digits = 40;
  size_t pos = 0;
  Decimal a;
  if (!read_decimal(text, pos, single_digits, a)) return {Fixed{}, ParseError::syntax};
  if (pos == text.size()) {
    if (a.mantissa.is_zero()) return {Fixed{}, ParseError::none};
    if (a.truncated) {  // stands for the dropped tail: strictly between the kept grid points
      a.mantissa.mul_small(10);
      a.mantissa.add_small(1);
      a.exponent -= 1;
      a.digits += 1;
    }
    // value in [10^(digits-1+e), 10^(digits+e))
    return round_scaled(a.negative, a.mantissa, Big::from_u64(1), a.exponent, a.digits + a.exponent,
                        a.digits - 1 + a.exponent);
  }
  if (text[pos] != '/') return {Fixed{}, ParseError::syntax};
  ++pos;
  Decimal b;
  if (!read_decimal(text, pos, ratio_digits, b) || pos != text.size()) return {Fixed{}, ParseError::syntax};
  if (a.truncated || b.truncated || a.digits > ratio_digits) return {Fixed{}, ParseError::too_many_digits};
  if (a.exponent_saturated || b.exponent_saturated) return {Fixed{}, ParseError::exponent_too_large};
  if (b.mantissa.is_zero()) return {Fixed{}, ParseError::division_by_zero};
  if (a.mantissa.is_zero()) return {Fixed{}, ParseError::none};
  // a in [10^(da-1+ea), 10^(da+ea)), b likewise: the ratio lies in
  // (10^(da+ea-db-eb-1), 10^(da+ea-db-eb+1)).
  const int64_t order = (a.digits + a.exponent) - (b.digits + b.exponent);
  return round_scaled(a.negative != b.negative, a.mantissa, b.mantissa, a.exponent - b.exponent, order + 1,
                      order - 1);
}

std::string to_string(Fixed value);
std::string to_raw_string(Fixed value);

namespace literals {

// 0.05_fx, 1e-3_fx, "1/60"_fx: exact, parsed at compile time; malformed or
// out-of-range text does not compile.
consteval Fixed operator""_fx(const char* text) {
  const ParseResult r = parse_fixed(text);
  if (!r.ok()) throw "invalid _fx literal";
  return r.value;
}
consteval Fixed operator""_fx(const char* text, size_t length) {
  const ParseResult r = parse_fixed(std::string_view(text, length));
  if (!r.ok()) throw "invalid _fx literal";
  return r.value;
}

}  // namespace literals

}  // namespace bitstep
