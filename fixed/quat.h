// Quat: a rotation quaternion w + xi + yj + zk. Products sum exact 128-bit
// terms and round once per component.
#pragma once

#include "fixed/vec3.h"

namespace bitstep {

struct Quat {
  Fixed w = Fixed::one();
  Fixed x, y, z;

  static constexpr Quat identity() { return {}; }
  constexpr Vec3 vector() const { return {x, y, z}; }
  friend constexpr bool operator==(Quat a, Quat b) = default;
};

// Hamilton product: a * b rotates by b, then by a.
Quat operator*(Quat a, Quat b);
constexpr Quat conjugate(Quat q) { return {q.w, -q.x, -q.y, -q.z}; }
// Unit quaternion; the identity for the zero quaternion.
Quat normalize(Quat q);
// Rotation by `angle` radians about the unit vector `axis`.
Quat from_axis_angle(Vec3 axis, Fixed angle);
// q v q* for a unit q.
Vec3 rotate(Quat q, Vec3 v);
// q* v q: the inverse rotation.
Vec3 rotate_inverse(Quat q, Vec3 v);
// q + dt/2 (0, omega) q, renormalised: one step of dq/dt = 1/2 omega q
// (omega in world coordinates, rad/s).
Quat integrate(Quat q, Vec3 omega, Fixed dt);

}  // namespace bitstep
