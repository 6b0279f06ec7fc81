// A moving shape against one placed shape, exact in fixed point: how far a
// sphere, capsule or box travels along a straight path before it first
// touches the target, where, and the target's normal there. The world's
// shape casts (core/query.h) build on it, as its ray casts build on
// core/ray_cast.h.
//
// How each pair is solved:
// - a sphere is the ray of its centre against the target grown by its
//   radius (core/ray_cast.h), and a target sphere the ray of its centre,
//   backwards, against the moving shape grown by its radius;
// - against a plane, the moving shape's lowest point along the plane's
//   normal is the ray;
// - box against box: the boxes touch when their projections overlap on all
//   fifteen separating axes; along each axis the projections overlap over
//   one interval of the path, and the first touch is the latest of the
//   intervals' starts (the separating axis test for moving boxes);
// - capsule against capsule or box: conservative advancement. The gap g
//   between the two (distance between the inner segment and the other's core,
//   less the radii) is a convex function of the distance travelled, so
//   stepping by g / closing speed (Newton from before the root) never
//   passes the first touch and converges in a few steps.
#pragma once

#include "core/ray_cast.h"

namespace bitstep {

struct ShapeEntry {
  Fixed distance;  // m along the path, 0..length
  Vec3 point;      // where the two surfaces first touch
  Vec3 normal;     // the target's outward unit normal there; -direction when they overlap at the start
};

// `moving` placed at its start, moved along `path` (its origin is ignored:
// the shape's own pose is the start). False when it does not touch `target`
// within the path's length. Shapes are solid: overlapping at the start (or
// touching) enters at distance 0, with the moving shape's centre as the
// point.
bool shape_enters(const WorldShape& moving, const Ray& path, const WorldShape& target, ShapeEntry& entry);

}  // namespace bitstep
