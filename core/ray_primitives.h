// The casts the shapes' ray functions are built from (ray_cast.cpp), exact
// in fixed point: each finds where a ray first enters a solid, within the
// ray's length (a ray that starts inside enters at 0, against its
// direction). Internal to core/.
#pragma once

#include "core/ray_cast.h"
#include "fixed/mat33.h"

namespace bitstep::ray_primitives {

// The first of several entries (a union of solids).
struct Nearest {
  bool found = false;
  RayEntry entry;
  void offer(bool hit, const RayEntry& candidate) {
    if (hit && (!found || candidate.distance < entry.distance)) {
      found = true;
      entry = candidate;
    }
  }
};

// A box about `centre` with `rotation` and half extents h.
bool cast_box(Vec3 centre, const Mat33& rotation, Vec3 h, const Ray& ray, RayEntry& entry);
// A ball of radius r.
bool cast_ball(Vec3 centre, Fixed r, const Ray& ray, RayEntry& entry);
// A capsule: the segment centre +- h axis (unit axis) swept by r.
void cast_capsule(Vec3 centre, Vec3 axis, Fixed h, Fixed r, const Ray& ray, Nearest& nearest);
// A box grown by r (rounded edges and corners).
void cast_rounded_box(Vec3 centre, const Mat33& rotation, Vec3 h, Fixed r, const Ray& ray, Nearest& nearest);
// The half-space below a plane through `point` with unit `normal`, grown by r.
bool cast_half_space(Vec3 point, Vec3 normal, Fixed r, const Ray& ray, RayEntry& entry);

}  // namespace bitstep::ray_primitives
