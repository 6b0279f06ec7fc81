// A box: half extents along its local axes (shape_types.h).
#include "core/ray_primitives.h"
#include "core/shape_types.h"

namespace bitstep {

Fixed BoxShape::volume(const Shape& shape) {
  return 8.0_fx * shape.half_extents.x * shape.half_extents.y * shape.half_extents.z;
}

// Solid, of half extents h: I_xx = m (h_y^2 + h_z^2) / 3, and so on.
ShapeMass BoxShape::mass(const Shape& shape, Fixed density) {
  const Fixed mass = density * volume(shape);
  const Vec3 h = shape.half_extents;
  const Fixed third = mass / 3.0_fx;
  return {mass,
          Mat33::diagonal(
              {third * (h.y * h.y + h.z * h.z), third * (h.x * h.x + h.z * h.z), third * (h.x * h.x + h.y * h.y)}),
          Vec3{}};
}

Result<void> BoxShape::check(const Shape& shape) {
  const Vec3 h = shape.half_extents;
  if (!size_in_envelope(h.x) || !size_in_envelope(h.y) || !size_in_envelope(h.z)) {
    return Error{"half_extents", "outside 0.01..50 m"};
  }
  return {};
}

Fixed BoxShape::extent(const Shape& shape) { return length(shape.half_extents); }

// Half widths along the world axes: |R| h.
Aabb BoxShape::bounds(const WorldShape& placed) {
  const Mat33 r = rotation(placed.pose.orientation);
  const Vec3 h = placed.shape->half_extents;
  const Vec3 extent{dot(abs(r.rows[0]), h), dot(abs(r.rows[1]), h), dot(abs(r.rows[2]), h)};
  return {placed.pose.position - extent, placed.pose.position + extent};
}

// A ray: the box's slabs; a sphere cast: the box grown by its radius.
bool BoxShape::ray(const WorldShape& placed, const Ray& ray, Fixed radius, RayEntry& entry) {
  const Mat33 rotation_matrix = rotation(placed.pose.orientation);
  const Vec3 centre = placed.pose.position;
  if (radius == Fixed{}) return ray_primitives::cast_box(centre, rotation_matrix, placed.shape->half_extents, ray, entry);
  ray_primitives::Nearest nearest;
  ray_primitives::cast_rounded_box(centre, rotation_matrix, placed.shape->half_extents, radius, ray, nearest);
  if (nearest.found) entry = nearest.entry;
  return nearest.found;
}

Fixed BoxShape::core_radius(const Shape&) { return Fixed{}; }

// The corner whose signs are d's in the box's axes: R (sign(R^T d) h) + c.
Vec3 BoxShape::core_support(const WorldShape& placed, Vec3 direction) {
  const Mat33 r = rotation(placed.pose.orientation);
  const Vec3 h = placed.shape->half_extents;
  const auto pick = [](Fixed along, Fixed half) { return along < Fixed{} ? -half : half; };
  const Vec3 local{pick(dot(r.column(0), direction), h.x), pick(dot(r.column(1), direction), h.y),
                   pick(dot(r.column(2), direction), h.z)};
  return placed.pose.position + r * local;
}

}  // namespace bitstep
