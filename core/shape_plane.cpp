// A plane: the static half-space below it; its local +y is the outward
// normal and its surface passes through its origin (shape_types.h).
#include "core/ray_primitives.h"
#include "core/shape_types.h"

namespace bitstep {

Fixed PlaneShape::volume(const Shape&) { return Fixed{}; }

// A plane belongs to a static body: no mass of its own.
ShapeMass PlaneShape::mass(const Shape&, Fixed) { return {}; }

Result<void> PlaneShape::check(const Shape&) { return {}; }

Fixed PlaneShape::extent(const Shape&) { return Fixed{}; }

// The whole world envelope (and a margin), never the full range: widths must not overflow.
Aabb PlaneShape::bounds(const WorldShape&) {
  const Fixed w = envelope::max_position + envelope::max_position;
  return {{-w, -w, -w}, {w, w, w}};
}

bool PlaneShape::ray(const WorldShape& placed, const Ray& ray, Fixed radius, RayEntry& entry) {
  return ray_primitives::cast_half_space(placed.pose.position,
                                         rotate(placed.pose.orientation, Vec3{Fixed{}, Fixed::one(), Fixed{}}), radius,
                                         ray, entry);
}

Fixed PlaneShape::core_radius(const Shape&) { return Fixed{}; }

// Unbounded: no support point (its origin); the generic path never takes a plane.
Vec3 PlaneShape::core_support(const WorldShape& placed, Vec3) { return placed.pose.position; }

}  // namespace bitstep
