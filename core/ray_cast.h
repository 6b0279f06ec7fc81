// A ray against one placed shape, exact in fixed point: where it first
// enters the solid shape, and the shape's outward normal there. The world's
// queries (core/query.h) build on it; a sphere cast is the ray of the
// sphere's centre against the shape grown by the sphere's radius.
#pragma once

#include "core/aabb.h"
#include "core/shape.h"

namespace bitstep {

// From `origin` along the unit `direction` for `length` metres.
struct Ray {
  Vec3 origin;
  Vec3 direction;  // unit
  Fixed length;    // m, >= 0
};

// Where a ray enters a shape.
struct RayEntry {
  Fixed distance;  // m along the ray, 0..length
  Vec3 normal;     // the shape's outward unit normal at the entry
};

// Coordinates and ray lengths the casts accept (m): beyond them a cast
// misses. Every product and square below stays inside Q32.32 for them.
inline constexpr Fixed max_ray_coordinate = Fixed::from_int(65536);
inline constexpr Fixed max_ray_length = Fixed::from_int(131072);

// |v| <= r on every axis (r >= 0), by comparisons: abs of the lowest value
// saturates (and aborts the checked build), and a caller's ray may hold it.
constexpr bool within_axes(Vec3 v, Fixed r) {
  return v.x >= -r && v.x <= r && v.y >= -r && v.y <= r && v.z >= -r && v.z <= r;
}

// The first point of the solid shape, grown by `radius` (0 for a ray),
// along the ray within its length; false when the ray misses it. Shapes
// are solid: a ray that starts inside (or on the surface) enters at
// distance 0 with normal -direction (as Jolt treats convex shapes). A
// plane is the half-space below it.
bool ray_enters(const WorldShape& shape, const Ray& ray, Fixed radius, RayEntry& entry);

// The distance at which the ray enters the box (0 when it starts inside);
// false when it misses it within its length.
bool ray_enters(const Aabb& box, const Ray& ray, Fixed& distance);

}  // namespace bitstep
