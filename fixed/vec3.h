// Vec3: three Fixed components. dot, cross and length_sq sum exact 128-bit
// products and round once; length is correctly rounded; normalize is within
// 1 ulp per component and returns the zero vector for the zero vector.
#pragma once

#include "fixed/fixed.h"

namespace bitstep {

struct Vec3 {
  Fixed x, y, z;

  static constexpr Vec3 zero() { return {}; }

  friend constexpr Vec3 operator+(Vec3 a, Vec3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
  friend constexpr Vec3 operator-(Vec3 a, Vec3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
  friend constexpr Vec3 operator-(Vec3 a) { return {-a.x, -a.y, -a.z}; }
  // Inlined always, as cross below: out of line, gcc passes the vectors
  // through the stack both ways, which costs about what the products do.
  [[gnu::always_inline]] friend constexpr Vec3 operator*(Vec3 a, Fixed s) { return {a.x * s, a.y * s, a.z * s}; }
  friend constexpr Vec3 operator*(Fixed s, Vec3 a) { return a * s; }
  friend constexpr Vec3 operator/(Vec3 a, Fixed s) { return {a.x / s, a.y / s, a.z / s}; }
  constexpr Vec3& operator+=(Vec3 b) { return *this = *this + b; }
  constexpr Vec3& operator-=(Vec3 b) { return *this = *this - b; }
  constexpr Vec3& operator*=(Fixed s) { return *this = *this * s; }
  friend constexpr bool operator==(Vec3 a, Vec3 b) = default;
};

// Inlined always, as raw::dot3's common case: out of line, both vectors go
// through the stack.
[[gnu::always_inline]] constexpr Fixed dot(Vec3 a, Vec3 b) {
  return Fixed::from_raw(raw::dot3<Wide>(a.x.raw(), b.x.raw(), a.y.raw(), b.y.raw(), a.z.raw(), b.z.raw()));
}

[[gnu::always_inline]] constexpr Vec3 cross(Vec3 a, Vec3 b) {
  auto term = [](Fixed p, Fixed q, Fixed r, Fixed s) {  // p q - r s, rounded once
    return Fixed::from_raw(raw::mul_sub_mul<Wide>(p.raw(), q.raw(), r.raw(), s.raw()));
  };
  return {term(a.y, b.z, a.z, b.y), term(a.z, b.x, a.x, b.z), term(a.x, b.y, a.y, b.x)};
}

constexpr Fixed length_sq(Vec3 v) { return dot(v, v); }

// a * s + b per component, each rounded once (position += velocity * dt).
constexpr Vec3 mul_add(Vec3 a, Fixed s, Vec3 b) {
  return {mul_add(a.x, s, b.x), mul_add(a.y, s, b.y), mul_add(a.z, s, b.z)};
}

constexpr Vec3 abs(Vec3 v) { return {abs(v.x), abs(v.y), abs(v.z)}; }
constexpr Vec3 min(Vec3 a, Vec3 b) { return {min(a.x, b.x), min(a.y, b.y), min(a.z, b.z)}; }
constexpr Vec3 max(Vec3 a, Vec3 b) { return {max(a.x, b.x), max(a.y, b.y), max(a.z, b.z)}; }

Fixed length(Vec3 v);
// Whether length(v) > limit, the same answer without the square root:
// length rounds sqrt(S) to nearest (S the sum of the raw squares), and for
// L >= 0, round(sqrt(S)) > L exactly when S > L^2 + L.
bool length_exceeds(Vec3 v, Fixed limit);
// v / |v|; the zero vector for the zero vector.
Vec3 normalize(Vec3 v);
// v / |v|; `fallback` for the zero vector.
Vec3 normalize_or(Vec3 v, Vec3 fallback);

}  // namespace bitstep
