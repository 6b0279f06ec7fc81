#include "core/mass.h"

#include "core/settings.h"

namespace bitstep {

namespace {

constexpr Fixed pi = "raw:3243f6a89"_fx;  // pi rounded to Q32.32
constexpr Fixed four_thirds_pi = "raw:430548e0b"_fx;  // 4 pi / 3 rounded

struct PartMass {
  Fixed mass;
  Vec3 principal;  // diagonal of the inertia tensor in the shape's own axes, kg m^2
};

// Solid box of half extents h: I_xx = m (h_y^2 + h_z^2) / 3, and so on.
PartMass box_mass(Vec3 h, Fixed mass) {
  const Fixed third = mass / 3.0_fx;
  return {mass, {third * (h.y * h.y + h.z * h.z), third * (h.x * h.x + h.z * h.z), third * (h.x * h.x + h.y * h.y)}};
}

// Solid sphere: I = 2/5 m r^2.
PartMass sphere_mass(Fixed r, Fixed mass) {
  const Fixed i = mass * 2.0_fx / 5.0_fx * r * r;
  return {mass, {i, i, i}};
}

// Capsule along y: a cylinder of radius r, length 2h, and two hemispheres.
//   cylinder:    I_yy = m_c r^2 / 2,  I_xx = m_c (r^2 / 4 + (2h)^2 / 12)
//   hemispheres: I_yy = m_s 2 r^2 / 5, I_xx = m_s (2 r^2 / 5 + h^2 + 3 h r / 4)
// (each hemisphere's centre of mass sits 3r/8 beyond the segment end; the
// last term is the parallel-axis shift from its flat face to the capsule's
// centre).
PartMass capsule_mass(Fixed r, Fixed h, Fixed density) {
  const Fixed r2 = r * r;
  const Fixed cylinder = density * pi * r2 * (h + h);
  const Fixed spheres = density * four_thirds_pi * r2 * r;
  const Fixed i_yy = cylinder * r2 / 2.0_fx + spheres * r2 * 2.0_fx / 5.0_fx;
  const Fixed i_xx = cylinder * (r2 / 4.0_fx + h * h / 3.0_fx) +
                     spheres * (r2 * 2.0_fx / 5.0_fx + h * h + h * r * 3.0_fx / 4.0_fx);
  return {cylinder + spheres, {i_xx, i_yy, i_xx}};
}

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

}  // namespace

Fixed volume(const Shape& shape) {
  switch (shape.type) {
    case ShapeType::box: return 8.0_fx * shape.half_extents.x * shape.half_extents.y * shape.half_extents.z;
    case ShapeType::sphere: return four_thirds_pi * shape.radius * shape.radius * shape.radius;
    case ShapeType::capsule: {
      const Fixed r = shape.radius;
      return pi * r * r * (shape.half_height + shape.half_height) + four_thirds_pi * r * r * r;
    }
    case ShapeType::plane: return Fixed{};
  }
  return Fixed{};
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
  std::vector<PartMass> parts;
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
    switch (shape.type) {
      case ShapeType::box: parts.push_back(box_mass(shape.half_extents, m)); break;
      case ShapeType::sphere: parts.push_back(sphere_mass(shape.radius, m)); break;
      case ShapeType::capsule: parts.push_back(capsule_mass(shape.radius, shape.half_height, density)); break;
      case ShapeType::plane: parts.push_back({}); break;
    }
    result.mass += m;
    if (result.mass > range.max) {
      result.ok = false;
      return result;
    }
    weighted_center += shape.local.position * m;
  }
  if (result.mass < range.min) {
    result.ok = false;
    return result;
  }
  result.center = weighted_center / result.mass;
  // I = sum of R_i diag(principal_i) R_i^T + m_i (|d_i|^2 E - d_i d_i^T), d_i = c_i - c.
  for (size_t i = 0; i < shapes.size(); ++i) {
    const Mat33 r = rotation(shapes[i].local.orientation);
    const Mat33 own = r * Mat33::diagonal(parts[i].principal) * transpose(r);
    result.inertia = result.inertia + own + point_mass_tensor(parts[i].mass, shapes[i].local.position - result.center);
  }
  return result;
}

}  // namespace bitstep
