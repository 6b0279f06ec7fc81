#include "fixed/quat.h"

#include "fixed/raw_math.h"

namespace bitstep {

namespace {

// One component of a product: the signed sum of four products, rounded once.
struct Sum4 {
  raw::Accumulator<Wide> sum;
  Sum4& plus(Fixed a, Fixed b) {
    sum.add_product(a.raw(), b.raw());
    return *this;
  }
  Sum4& minus(Fixed a, Fixed b) {
    sum.sub_product(a.raw(), b.raw());
    return *this;
  }
  Fixed value() const {
    bool saturated = false;
    const int64_t r = sum.to_raw(saturated);
    BITSTEP_FAULT_IF(saturated, "quat", "result out of range, saturated", r, 0);
    return Fixed::from_raw(r);
  }
};

}  // namespace

Quat operator*(Quat a, Quat b) {
  return {
      Sum4{}.plus(a.w, b.w).minus(a.x, b.x).minus(a.y, b.y).minus(a.z, b.z).value(),
      Sum4{}.plus(a.w, b.x).plus(a.x, b.w).plus(a.y, b.z).minus(a.z, b.y).value(),
      Sum4{}.plus(a.w, b.y).minus(a.x, b.z).plus(a.y, b.w).plus(a.z, b.x).value(),
      Sum4{}.plus(a.w, b.z).plus(a.x, b.y).minus(a.y, b.x).plus(a.z, b.w).value(),
  };
}

Quat normalize(Quat q) {
  const int64_t in[4] = {q.w.raw(), q.x.raw(), q.y.raw(), q.z.raw()};
  int64_t out[4] = {};
  if (!raw::normalize<Wide>(in, out, 4)) return Quat::identity();
  return {Fixed::from_raw(out[0]), Fixed::from_raw(out[1]), Fixed::from_raw(out[2]), Fixed::from_raw(out[3])};
}

Quat from_axis_angle(Vec3 axis, Fixed angle) {
  const Fixed half = angle / Fixed::from_int(2);
  const Fixed s = sin(half);
  return {cos(half), axis.x * s, axis.y * s, axis.z * s};
}

Vec3 rotate(Quat q, Vec3 v) {
  // v' = v + w t + u x t with u = (x, y, z) and t = 2 (u x v): the expanded
  // q v q* for unit q, two cross products instead of two quaternion products.
  const Vec3 u = q.vector();
  const Vec3 uv = cross(u, v);
  const Vec3 t = uv + uv;
  return v + t * q.w + cross(u, t);
}

Vec3 rotate_inverse(Quat q, Vec3 v) { return rotate(conjugate(q), v); }

Quat integrate(Quat q, Vec3 omega, Fixed dt) {
  const Fixed half_dt = dt / Fixed::from_int(2);
  const Quat spin = Quat{Fixed{}, omega.x, omega.y, omega.z} * q;
  return normalize(Quat{mul_add(spin.w, half_dt, q.w), mul_add(spin.x, half_dt, q.x),
                        mul_add(spin.y, half_dt, q.y), mul_add(spin.z, half_dt, q.z)});
}

}  // namespace bitstep
