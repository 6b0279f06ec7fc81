#include "fixed/known_answer.h"

#include "fixed/decimal.h"
#include "fixed/mat33.h"
#include "fixed/splitmix64.h"

namespace bitstep {

namespace {

// Operands drawn from a seeded SplitMix64.
struct Operands {
  SplitMix64 rng;

  // A raw value of random sign whose magnitude has exactly `bits` bits, bits
  // uniform in [min_bits, max_bits]: log-uniform over the scales a simulation
  // meets, and never zero.
  Fixed scaled(int min_bits, int max_bits, bool allow_negative = true) {
    const uint64_t r = rng.next();
    const int span = max_bits - min_bits + 1;
    const int bits = min_bits + static_cast<int>(r % static_cast<uint64_t>(span));
    const uint64_t m = (rng.next() >> (64 - bits)) | (uint64_t{1} << (bits - 1));
    const bool negative = allow_negative && ((r >> 40) & 1u) != 0;
    return Fixed::from_raw(negative ? -static_cast<int64_t>(m) : static_cast<int64_t>(m));
  }
  Quat unit_quat() {
    const Fixed w = scaled(1, 33), x = scaled(1, 33), y = scaled(1, 33), z = scaled(1, 33);
    return normalize(Quat{w, x, y, z});
  }
  Vec3 vec(int min_bits, int max_bits) {
    const Fixed x = scaled(min_bits, max_bits), y = scaled(min_bits, max_bits), z = scaled(min_bits, max_bits);
    return {x, y, z};
  }
};

// FNV-1a over the little-endian bytes of each raw value: independent of the
// host's byte order.
struct Fold {
  uint64_t hash = 0xCBF29CE484222325u;
  uint64_t count = 0;
  void add(Fixed f) {
    const uint64_t v = static_cast<uint64_t>(f.raw());
    for (int i = 0; i < 8; ++i) {
      hash ^= (v >> (8 * i)) & 0xFFu;
      hash *= 0x100000001B3u;
    }
  }
  void add(Vec3 v) {
    add(v.x);
    add(v.y);
    add(v.z);
  }
  void add(Quat q) {
    add(q.w);
    add(q.x);
    add(q.y);
    add(q.z);
  }
};

constexpr int rounds = 50000;
constexpr int kinds = 24;

}  // namespace

// Operand ranges keep every result inside the range, so the checked build runs
// this too (saturation and wrapping are covered by tests/fixed/checked_tests.cpp).
KnownAnswer run_known_answer() {
  Operands rng{{0x0B175E9u}};
  Fold fold;
  const Fixed one = Fixed::one();
  for (int pass = 0; pass < rounds; ++pass) {
    for (int kind = 0; kind < kinds; ++kind) {
      // Operands are drawn into named locals first: the order in which C++
      // evaluates function arguments is unspecified.
      const Fixed a = rng.scaled(1, 46), b = rng.scaled(1, 46), c = rng.scaled(1, 61), d = rng.scaled(1, 61);
      switch (kind) {
        case 0: fold.add(c + d); break;
        case 1: fold.add(c - d); break;
        case 2: fold.add(a * b); break;
        case 3: fold.add(a / rng.scaled(24, 62)); break;
        case 4: fold.add(mul_add(a, b, c)); break;
        case 5: fold.add(mul_div(a, b, rng.scaled(40, 62))); break;
        case 6: fold.add(sqrt(rng.scaled(1, 63, false))); break;
        case 7: fold.add(rsqrt(rng.scaled(1, 63, false))); break;
        case 8: fold.add(sin(rng.scaled(1, 63))); break;
        case 9: fold.add(cos(rng.scaled(1, 63))); break;
        case 10: fold.add(tan(rng.scaled(1, 32))); break;
        case 11: fold.add(atan2(c, d)); break;
        case 12: fold.add(asin(rng.scaled(1, 32))); break;
        case 13: fold.add(acos(rng.scaled(1, 32))); break;
        case 14: {
          const Vec3 u = rng.vec(1, 46);
          fold.add(dot(u, rng.vec(1, 46)));
          break;
        }
        case 15: {
          const Vec3 u = rng.vec(1, 46);
          fold.add(cross(u, rng.vec(1, 46)));
          break;
        }
        case 16: fold.add(length(rng.vec(1, 62))); break;
        case 17: fold.add(normalize(rng.vec(1, 62))); break;
        case 18: {
          const Quat p = rng.unit_quat(), q = rng.unit_quat();
          fold.add(p * q);
          fold.add(rotate(p, rng.vec(1, 50)));
          fold.add(integrate(q, rng.vec(1, 38), Fixed::from_ratio(1, 60)));
          break;
        }
        case 19: {
          for (const Vec3& row : rotation(rng.unit_quat()).rows) fold.add(row);
          break;
        }
        case 20: {
          if (pass % 16 != 0) break;  // the exact inverse is slow; 3,125 of them
          // A symmetric positive-definite tensor: diagonal dominance.
          const Fixed i = rng.scaled(30, 40, false), j = rng.scaled(30, 40, false), k = rng.scaled(30, 40, false);
          const Fixed e = rng.scaled(1, 28), f = rng.scaled(1, 28), g = rng.scaled(1, 28);
          const Mat33 m{{Vec3{i + one, e, f}, Vec3{e, j + one, g}, Vec3{f, g, k + one}}};
          for (const Vec3& row : inverse(m).rows) fold.add(row);
          break;
        }
        case 21:
          fold.add(floor(c));
          fold.add(ceil(c));
          fold.add(round(c));
          fold.add(abs(c));
          break;
        case 22: {
          if (pass % 8 != 0) break;  // text round trips are slow; 6,250 of them
          const std::string text = to_string(rng.scaled(1, 63));
          fold.add(parse_fixed(text).value);
          fold.add(Fixed::from_int(static_cast<int32_t>(text.size())));
          break;
        }
        default: {
          fold.add(min(c, d));
          fold.add(max(c, d));
          fold.add(clamp(rng.scaled(1, 62), min(c, d), max(c, d)));
          break;
        }
      }
      ++fold.count;
    }
  }
  return {fold.hash, fold.count};
}

}  // namespace bitstep
