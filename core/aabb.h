// Axis-aligned bounding boxes in world space.
#pragma once

#include "core/shape.h"

namespace bitstep {

struct Aabb {
  Vec3 min, max;

  bool overlaps(const Aabb& o) const {
    return min.x <= o.max.x && o.min.x <= max.x && min.y <= o.max.y && o.min.y <= max.y && min.z <= o.max.z &&
           o.min.z <= max.z;
  }
  Aabb merged(const Aabb& o) const { return {bitstep::min(min, o.min), bitstep::max(max, o.max)}; }
  Aabb expanded(Fixed margin) const {
    const Vec3 m{margin, margin, margin};
    return {min - m, max + m};
  }
  friend bool operator==(const Aabb&, const Aabb&) = default;
};

// The bounds of a placed shape; a plane's are the whole world.
Aabb shape_aabb(const WorldShape& s);

}  // namespace bitstep
