// Mat33: a 3x3 matrix stored by rows. Products use fused dot products (one
// rounding per entry).
#pragma once

#include <array>

#include "fixed/quat.h"

namespace bitstep {

struct Mat33 {
  std::array<Vec3, 3> rows{};

  static constexpr Mat33 identity() {
    return {{Vec3{Fixed::one(), {}, {}}, Vec3{{}, Fixed::one(), {}}, Vec3{{}, {}, Fixed::one()}}};
  }
  static constexpr Mat33 diagonal(Vec3 d) { return {{Vec3{d.x, {}, {}}, Vec3{{}, d.y, {}}, Vec3{{}, {}, d.z}}}; }
  constexpr Vec3 column(int j) const {
    auto pick = [j](Vec3 r) { return j == 0 ? r.x : (j == 1 ? r.y : r.z); };
    return {pick(rows[0]), pick(rows[1]), pick(rows[2])};
  }
  friend constexpr bool operator==(const Mat33& a, const Mat33& b) = default;
};

constexpr Mat33 transpose(const Mat33& m) { return {{m.column(0), m.column(1), m.column(2)}}; }
constexpr Vec3 operator*(const Mat33& m, Vec3 v) { return {dot(m.rows[0], v), dot(m.rows[1], v), dot(m.rows[2], v)}; }
constexpr Mat33 operator*(const Mat33& a, const Mat33& b) {
  const Mat33 bt = transpose(b);
  return {{bt * a.rows[0], bt * a.rows[1], bt * a.rows[2]}};
}
constexpr Mat33 operator+(const Mat33& a, const Mat33& b) {
  return {{a.rows[0] + b.rows[0], a.rows[1] + b.rows[1], a.rows[2] + b.rows[2]}};
}
constexpr Mat33 operator-(const Mat33& a, const Mat33& b) {
  return {{a.rows[0] - b.rows[0], a.rows[1] - b.rows[1], a.rows[2] - b.rows[2]}};
}
constexpr Mat33 operator*(const Mat33& m, Fixed s) { return {{m.rows[0] * s, m.rows[1] * s, m.rows[2] * s}}; }
// [r]x, the matrix of r x (.): skew(r) v = cross(r, v).
constexpr Mat33 skew(Vec3 r) {
  return {{Vec3{Fixed{}, -r.z, r.y}, Vec3{r.z, Fixed{}, -r.x}, Vec3{-r.y, r.x, Fixed{}}}};
}

// The rotation matrix of a unit quaternion; each entry rounded once.
Mat33 rotation(Quat q);
// The exact inverse, each entry rounded once (adjugate / determinant in exact
// big-integer arithmetic, so an inertia tensor of a 1e5 kg, 50 m body neither
// overflows nor loses its small entries). A singular matrix gives the zero
// matrix; entries beyond the range saturate.
Mat33 inverse(const Mat33& m);

}  // namespace bitstep
