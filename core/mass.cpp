#include "core/mass.h"

#include "core/settings.h"
#include "core/shape_types.h"

namespace bitstep {

namespace {

// The tensor of a point mass m at offset d, for the parallel-axis rule:
// m (|d|^2 E - d d^T).
Mat33 point_mass_tensor(Fixed m, Vec3 d) {
  const Fixed dd = length_sq(d);
  return {{Vec3{m * (dd - d.x * d.x), -m * d.x * d.y, -m * d.x * d.z},
           Vec3{-m * d.y * d.x, m * (dd - d.y * d.y), -m * d.y * d.z},
           Vec3{-m * d.z * d.x, -m * d.z * d.y, m * (dd - d.z * d.z)}}};
}

// density V > max_mass, for density, V >= 0: as density > max_mass / V
// where that quotient is in range (the rule bodies were always admitted by),
// and on the exact product where it is not: below V = 1e5 / 2^31 = 4.7e-5
// m^3 (a 0.036 m box) the quotient saturated, and a checked build aborted.
bool heavier_than(Fixed density, Fixed v, Fixed max_mass) {
  if (v == Fixed{}) return false;
  const bool quotient_in_range = product_exceeds(v, Fixed::max(), max_mass);
  if (quotient_in_range) return density > max_mass / v;
  return product_exceeds(density, v, max_mass);
}

// A shape's centre of mass in the body frame.
Vec3 shape_center(const Shape& shape, const ShapeMass& part) {
  if (part.center == Vec3{}) return shape.local.position;  // the primitives'
  return shape.local.position + rotate(shape.local.orientation, part.center);
}

}  // namespace

Fixed volume(const Shape& shape) {
  return with_shape_type(shape.type, [&](auto type) { return decltype(type)::volume(shape); });
}

Fixed total_volume(const std::vector<Shape>& shapes) {
  Fixed sum;
  for (const Shape& s : shapes) sum += volume(s);
  return sum;
}

Fixed body_density(const std::vector<Shape>& shapes, Fixed density, Fixed mass) {
  return mass > Fixed{} ? mass / total_volume(shapes) : density;
}

bool product_exceeds(Fixed a, Fixed b, Fixed limit) {
  // Raw values: a b 2^-64 > limit 2^-32  <=>  A B > L 2^32.
  const Wide product = Wide::mul(magnitude(a.raw()), magnitude(b.raw()));
  return product > (Wide{magnitude(limit.raw())} << raw::fraction_bits);
}

MassProperties mass_properties(const std::vector<Shape>& shapes, Fixed density, Fixed mass) {
  return mass_properties(shapes, body_density(shapes, density, mass), mass > Fixed{} ? given_mass_range : MassRange{});
}

MassProperties mass_properties(const std::vector<Shape>& shapes, Fixed density, MassRange range) {
  MassProperties result;
  std::vector<ShapeMass> parts;
  parts.reserve(shapes.size());
  Vec3 weighted_center;
  for (const Shape& shape : shapes) {
    // m = density V, refused before it could leave the envelope (or the range).
    const Fixed v = volume(shape);
    if (heavier_than(density, v, range.max)) {
      result.ok = false;
      return result;
    }
    const Fixed m = density * v;
    parts.push_back(with_shape_type(shape.type, [&](auto type) { return decltype(type)::mass(shape, density); }));
    result.mass += m;
    if (result.mass > range.max) {
      result.ok = false;
      return result;
    }
    weighted_center += shape_center(shape, parts.back()) * m;
  }
  if (result.mass < range.min) {
    result.ok = false;
    return result;
  }
  result.center = weighted_center / result.mass;
  // I = sum of R_i I_i R_i^T + m_i (|d_i|^2 E - d_i d_i^T), d_i = c_i - c.
  for (size_t i = 0; i < shapes.size(); ++i) {
    const Mat33 r = rotation(shapes[i].local.orientation);
    const Mat33 own = r * parts[i].inertia * transpose(r);
    const Vec3 offset = shape_center(shapes[i], parts[i]) - result.center;
    result.inertia = result.inertia + own + point_mass_tensor(parts[i].mass, offset);
  }
  return result;
}

}  // namespace bitstep
