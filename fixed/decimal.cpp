#include "fixed/decimal.h"

namespace bitstep {

namespace {

// Appends the decimal digits of v, at least min_digits of them (zero-padded).
void append_digits(std::string& out, uint64_t v, int min_digits) {
  char buffer[24];
  int n = 0;
  do {
    buffer[n++] = static_cast<char>('0' + v % 10);
    v /= 10;
  } while (v != 0 || n < min_digits);
  while (n > 0) out.push_back(buffer[--n]);
}

}  // namespace

std::string to_string(Fixed value) {
  const uint64_t m = magnitude(value.raw());
  // Try 0, 1, ... fractional digits: the decimal nearest to the value with d
  // digits, D / 10^d with D = round(m 10^d / 2^32), is the best candidate of
  // that length; the first that parses back to the same bits is the shortest.
  // d = 10 always succeeds, because 10^-10 is finer than 1 ulp.
  uint64_t scale = 1;
  std::string text;
  for (int d = 0; d <= 10; ++d, scale *= 10) {
    const Wide scaled = raw::round_shift(Wide::mul(m, scale), raw::fraction_bits);  // < 2^66
    uint64_t fraction = 0;
    const uint64_t integer = scaled.divrem(scale, fraction);  // scaled.hi() <= 3 < scale for d >= 1
    text.clear();
    if (value.raw() < 0 && (integer != 0 || fraction != 0)) text.push_back('-');
    append_digits(text, integer, 1);
    if (d > 0) {
      text.push_back('.');
      append_digits(text, fraction, d);
    }
    const ParseResult back = parse_fixed(text);
    if (back.ok() && back.value == value) return text;
  }
  return to_raw_string(value);  // unreachable: d = 10 always round-trips
}

std::string to_raw_string(Fixed value) {
  static constexpr char hex[] = "0123456789abcdef";
  uint64_t m = magnitude(value.raw());
  char buffer[16];
  int n = 0;
  do {
    buffer[n++] = hex[m & 15u];
    m >>= 4;
  } while (m != 0);
  std::string out = value.raw() < 0 ? "raw:-" : "raw:";
  while (n > 0) out.push_back(buffer[--n]);
  return out;
}

}  // namespace bitstep
