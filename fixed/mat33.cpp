#include "fixed/mat33.h"

#include <cstddef>

#include "fixed/big_int.h"

namespace bitstep {

Mat33 rotation(Quat q) {
  // R = I + 2 w [u]x + 2 [u]x^2 for u = (x, y, z), written out:
  //   [1 - 2(y^2 + z^2)   2(xy - wz)         2(xz + wy)      ]
  //   [2(xy + wz)         1 - 2(x^2 + z^2)   2(yz - wx)      ]
  //   [2(xz - wy)         2(yz + wx)         1 - 2(x^2 + y^2)]
  // Each entry is one exact sum rounded once.
  auto entry = [](int64_t constant, Fixed a, Fixed b, int sign_ab, Fixed c, Fixed d, int sign_cd) {
    raw::Accumulator<Wide> sum;
    sum.add_raw(constant);
    for (int twice = 0; twice < 2; ++twice) {
      sign_ab > 0 ? sum.add_product(a.raw(), b.raw()) : sum.sub_product(a.raw(), b.raw());
      sign_cd > 0 ? sum.add_product(c.raw(), d.raw()) : sum.sub_product(c.raw(), d.raw());
    }
    bool saturated = false;
    return Fixed::from_raw(sum.to_raw(saturated));
  };
  const int64_t one = Fixed::one().raw();
  return {{
      Vec3{entry(one, q.y, q.y, -1, q.z, q.z, -1), entry(0, q.x, q.y, 1, q.w, q.z, -1),
           entry(0, q.x, q.z, 1, q.w, q.y, 1)},
      Vec3{entry(0, q.x, q.y, 1, q.w, q.z, 1), entry(one, q.x, q.x, -1, q.z, q.z, -1),
           entry(0, q.y, q.z, 1, q.w, q.x, -1)},
      Vec3{entry(0, q.x, q.z, 1, q.w, q.y, -1), entry(0, q.y, q.z, 1, q.w, q.x, 1),
           entry(one, q.x, q.x, -1, q.y, q.y, -1)},
  }};
}

namespace {

using Big = BigUint<8>;

using SignedBig = BigInt<8>;

// p q - r s exactly.
SignedBig minor(int64_t p, int64_t q, int64_t r, int64_t s) {
  return SignedBig::from_i64(p) * SignedBig::from_i64(q) - SignedBig::from_i64(r) * SignedBig::from_i64(s);
}

// round(numerator 2^64 / denominator) as raw, ties to even, saturated.
Fixed divide(SignedBig numerator, const SignedBig& denominator) {
  const bool negative = numerator.negative != denominator.negative;
  numerator.magnitude.shift_left(64);
  Big limit = denominator.magnitude;
  limit.shift_left(63);
  if (numerator.magnitude.compare(limit) >= 0) {
    BITSTEP_FAULT_IF(true, "inverse", "entry out of range, saturated", 0, 0);
    return negative ? Fixed::lowest() : Fixed::max();
  }
  Big remainder;
  uint64_t q = divide_small_quotient(numerator.magnitude, denominator.magnitude, 63, remainder);
  remainder.shift_left(1);
  const int half = remainder.compare(denominator.magnitude);
  if (half > 0 || (half == 0 && (q & 1u) != 0)) ++q;
  bool saturated = false;
  return Fixed::from_raw(raw::signed_saturate(negative, Wide{q}, saturated));
}

}  // namespace

Mat33 inverse(const Mat33& m) {
  // In raw units an entry is A 2^-32, a 2x2 minor C 2^-64, the determinant
  // D 2^-96, so an entry of adj(M) / det(M) has the raw value C 2^64 / D.
  int64_t a[3][3];
  for (int i = 0; i < 3; ++i) {
    a[i][0] = m.rows[static_cast<std::size_t>(i)].x.raw();
    a[i][1] = m.rows[static_cast<std::size_t>(i)].y.raw();
    a[i][2] = m.rows[static_cast<std::size_t>(i)].z.raw();
  }
  // Cofactor C_ij = (-1)^(i+j) minor_ij, with cyclic indices taking the sign.
  SignedBig cofactor[3][3];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const int i1 = (i + 1) % 3, i2 = (i + 2) % 3, j1 = (j + 1) % 3, j2 = (j + 2) % 3;
      cofactor[i][j] = minor(a[i1][j1], a[i2][j2], a[i1][j2], a[i2][j1]);
    }
  }
  SignedBig determinant;
  for (int j = 0; j < 3; ++j) {
    determinant = determinant + cofactor[0][j] * SignedBig::from_i64(a[0][j]);
  }
  if (determinant.magnitude.is_zero()) {
    BITSTEP_FAULT_IF(true, "inverse", "singular matrix", 0, 0);
    return Mat33{};
  }
  Mat33 r;
  for (int i = 0; i < 3; ++i) {
    // (M^-1)_ij = C_ji / det
    r.rows[static_cast<std::size_t>(i)] = {divide(cofactor[0][i], determinant), divide(cofactor[1][i], determinant),
                                      divide(cofactor[2][i], determinant)};
  }
  return r;
}

}  // namespace bitstep
