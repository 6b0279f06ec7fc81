// Pose: a rigid transform, position (m) and orientation.
#pragma once

#include "fixed/quat.h"

namespace bitstep {

struct Pose {
  Vec3 position;
  Quat orientation;

  // A point given in this pose's frame, in the parent frame.
  Vec3 apply(Vec3 local_point) const { return position + rotate(orientation, local_point); }
  // A point given in the parent frame, in this pose's frame.
  Vec3 apply_inverse(Vec3 point) const { return rotate_inverse(orientation, point - position); }
  friend bool operator==(const Pose&, const Pose&) = default;
};

// parent * child: the child pose expressed in the parent's parent frame.
inline Pose compose(const Pose& parent, const Pose& child) {
  if (child.orientation == Quat::identity()) return {parent.apply(child.position), parent.orientation};
  return {parent.apply(child.position), normalize(parent.orientation * child.orientation)};
}

}  // namespace bitstep
