// The distance between two convex shapes by GJK (Gilbert, Johnson and
// Keerthi 1988) over their support functions, exact in fixed point: the
// generic path for convex pairs without a hand-written routine. Each shape
// is its core (a point, a segment or a box: shape_types.h core_support)
// grown by its core radius, as in Box2D's b2ShapeDistance and Jolt's convex
// radius: GJK finds the closest points of the cores, the radii are taken
// off after. The search runs on the Minkowski difference A - B of the
// cores; the closest point of each simplex (a point, segment, triangle or
// tetrahedron) to the origin comes from Ericson's Voronoi-region tests,
// dot products only. Coordinates are taken about A's centre, so that the
// products stay small for shapes far from the world's origin.
#pragma once

#include <array>

#include "core/shape.h"

namespace bitstep {

struct ConvexDistance {
  bool overlap = false;   // the cores meet (distance < 0 by at least the radii): no witness points
  Fixed distance;         // between the shapes (the cores' less both radii): negative when the radii overlap
  Vec3 point_a, point_b;  // the closest points on the shapes' surfaces (world)
  Vec3 normal;            // unit, from A toward B
  int iterations = 0;
};

// A convex core as GJK reads it: its farthest point along a world
// direction (any length), a point inside it, and the radius it is grown by.
// A placed shape is one (convex_core); so is a mesh's triangle (collide_mesh.cpp).
struct ConvexCore {
  const void* object;
  Vec3 (*support)(const void* object, Vec3 direction);
  Vec3 centre;
  Fixed radius;
};

// The core of a placed shape (shape_types.h core_support, core_radius);
// not a plane (unbounded: no support point). It refers to `s`.
ConvexCore convex_core(const WorldShape& s);

// A triangle's core: `corners` (the caller's, alive while it is used).
ConvexCore triangle_core(const std::array<Vec3, 3>& corners);

ConvexDistance convex_distance(const ConvexCore& a, const ConvexCore& b);
// Neither shape may be a plane.
inline ConvexDistance convex_distance(const WorldShape& a, const WorldShape& b) {
  return convex_distance(convex_core(a), convex_core(b));
}

}  // namespace bitstep
