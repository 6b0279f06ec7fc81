// A sphere: a radius about its origin (shape_types.h).
#include "core/ray_primitives.h"
#include "core/shape_types.h"

namespace bitstep {

Fixed SphereShape::volume(const Shape& shape) {
  return volume_four_thirds_pi * shape.radius * shape.radius * shape.radius;
}

// Solid: I = 2/5 m r^2.
ShapeMass SphereShape::mass(const Shape& shape, Fixed density) {
  const Fixed mass = density * volume(shape);
  const Fixed r = shape.radius;
  const Fixed i = mass * 2.0_fx / 5.0_fx * r * r;
  return {mass, Mat33::diagonal({i, i, i}), Vec3{}};
}

Result<void> SphereShape::check(const Shape& shape) {
  if (!size_in_envelope(shape.radius)) return Error{"radius", "outside 0.01..50 m"};
  return {};
}

Fixed SphereShape::extent(const Shape& shape) { return shape.radius; }

Aabb SphereShape::bounds(const WorldShape& placed) {
  const Fixed r = placed.shape->radius;
  const Vec3 extent{r, r, r};
  return {placed.pose.position - extent, placed.pose.position + extent};
}

bool SphereShape::ray(const WorldShape& placed, const Ray& ray, Fixed radius, RayEntry& entry) {
  return ray_primitives::cast_ball(placed.pose.position, placed.shape->radius + radius, ray, entry);
}

Fixed SphereShape::core_radius(const Shape& shape) { return shape.radius; }

// Its core is its centre.
Vec3 SphereShape::core_support(const WorldShape& placed, Vec3) { return placed.pose.position; }

}  // namespace bitstep
