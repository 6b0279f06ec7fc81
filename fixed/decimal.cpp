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

// Whether the decimal D / 10^d reads back as the magnitude m: parse_fixed
// rounds D 2^32 / 10^d once, ties to even, and negation is symmetric.
bool reads_back(Wide decimal_digits, uint64_t scale, uint64_t m) {
  uint64_t remainder = 0;
  uint64_t q = (decimal_digits << raw::fraction_bits).divrem(scale, remainder);  // hi < scale, see below
  const uint64_t rest = scale - remainder;
  if (remainder > rest || (remainder == rest && (q & 1u) != 0)) ++q;
  return q == m;
}

}  // namespace

std::string to_string(Fixed value) {
  const uint64_t m = magnitude(value.raw());
  // Try 0, 1, ... fractional digits: the decimal nearest to the value with d
  // digits, D / 10^d with D = round(m 10^d / 2^32), is the best candidate of
  // that length; the first that reads back to the same bits is the shortest.
  // d = 10 always succeeds, because 10^-10 is finer than 1 ulp. D 2^32 <=
  // m 10^d + 2^31 < 10^d 2^64, so both divisions below have their quotient in
  // 64 bits.
  uint64_t scale = 1;
  int digits = 0;
  Wide decimal_digits = raw::round_shift(Wide::mul(m, scale), raw::fraction_bits);
  while (digits < 10 && !reads_back(decimal_digits, scale, m)) {
    ++digits;
    scale *= 10;
    decimal_digits = raw::round_shift(Wide::mul(m, scale), raw::fraction_bits);
  }
  uint64_t fraction = 0;
  const uint64_t integer = decimal_digits.divrem(scale, fraction);
  std::string text;
  if (value.raw() < 0) text.push_back('-');
  append_digits(text, integer, 1);
  if (digits > 0) {
    text.push_back('.');
    append_digits(text, fraction, digits);
  }
  return text;
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
