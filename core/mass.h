// Mass properties from shapes and density: mass, centre of mass and the
// inertia tensor about it, with the parallel-axis rule for compounds.
#pragma once

#include <vector>

#include "core/shape.h"
#include "fixed/mat33.h"

namespace bitstep {

struct MassProperties {
  Fixed mass;      // kg
  Vec3 center;     // m, in the body frame
  Mat33 inertia;   // kg m^2, about the centre, body axes
  bool ok = true;  // false when a mass falls outside the world envelope (0.01..1e5 kg)
};

// The volume of a shape in m^3 (0 for a plane).
Fixed volume(const Shape& shape);
// Mass properties of a body's shapes at one density (kg/m^3).
MassProperties mass_properties(const std::vector<Shape>& shapes, Fixed density);

}  // namespace bitstep
