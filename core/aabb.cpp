#include "core/aabb.h"

#include "core/settings.h"
#include "fixed/mat33.h"

namespace bitstep {

Aabb shape_aabb(const WorldShape& s) {
  const Vec3 c = s.pose.position;
  Vec3 extent;
  switch (s.shape->type) {
    case ShapeType::box: {
      // Half widths along the world axes: |R| h.
      const Mat33 r = rotation(s.pose.orientation);
      const Vec3 h = s.shape->half_extents;
      extent = {dot(abs(r.rows[0]), h), dot(abs(r.rows[1]), h), dot(abs(r.rows[2]), h)};
      break;
    }
    case ShapeType::sphere: extent = {s.shape->radius, s.shape->radius, s.shape->radius}; break;
    case ShapeType::capsule: {
      const Vec3 axis = abs(rotate(s.pose.orientation, Vec3{Fixed{}, s.shape->half_height, Fixed{}}));
      const Fixed r = s.shape->radius;
      extent = axis + Vec3{r, r, r};
      break;
    }
    case ShapeType::plane: {
      // The whole world envelope (and a margin), never the full range: widths must not overflow.
      const Fixed w = envelope::max_position + envelope::max_position;
      return {{-w, -w, -w}, {w, w, w}};
    }
  }
  return {c - extent, c + extent};
}

}  // namespace bitstep
