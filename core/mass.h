// Mass properties from shapes and density: mass, centre of mass and the
// inertia tensor about it, with the parallel-axis rule for compounds.
#pragma once

#include <vector>

#include "core/settings.h"
#include "core/shape.h"
#include "fixed/mat33.h"

namespace bitstep {

struct MassProperties {
  Fixed mass;      // kg
  Vec3 center;     // m, in the body frame
  Mat33 inertia;   // kg m^2, about the centre, body axes
  bool ok = true;  // false when the mass falls outside the range asked for
};

// The masses a body may come out with, kg. A density gives the envelope's
// 0.01..1e5 kg; a given mass goes through density = m / V rounded to Q32.32,
// which moves it by up to V 2^-33 kg (1.2e-4 kg for the largest box): it is
// admitted when the given mass is in the envelope, and here only kept
// from losing half of itself or growing past the range the inertia holds.
struct MassRange {
  Fixed min = envelope::min_mass;
  Fixed max = envelope::max_mass;
};
inline constexpr MassRange given_mass_range{envelope::min_mass / 2.0_fx, envelope::max_mass + Fixed::one()};

// The volume of a shape in m^3 (0 for a plane).
Fixed volume(const Shape& shape);
// The volume of all the shapes, m^3 (overlaps counted twice). The caller
// keeps the sum in range (check_envelope: at most envelope's max_total_volume).
Fixed total_volume(const std::vector<Shape>& shapes);
// The density a body is made of, kg/m^3: `density`, or mass / total volume
// when a mass (kg) is given (> 0).
Fixed body_density(const std::vector<Shape>& shapes, Fixed density, Fixed mass);
// a b > limit for a, b, limit >= 0, decided on the exact 128-bit product (no
// rounding, no saturation): density x volume against a mass bound.
bool product_exceeds(Fixed a, Fixed b, Fixed limit);
// Mass properties of a body's shapes at one density (kg/m^3); not ok (and
// incomplete) when the mass leaves `range`, checked before it could overflow.
MassProperties mass_properties(const std::vector<Shape>& shapes, Fixed density, MassRange range = {});
// Those of a body definition's shapes, density or given mass (the range to match).
MassProperties mass_properties(const std::vector<Shape>& shapes, Fixed density, Fixed mass);

}  // namespace bitstep
