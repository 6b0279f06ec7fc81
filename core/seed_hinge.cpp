#include "core/seed_hinge.h"

namespace bitstep {

std::vector<JointDef> seed_hinge(const JointDef& hinge, Fixed half_width, Fixed sloppiness) {
  const Vec3 axis = normalize(hinge.axis);
  const Vec3 centre = hinge.anchor_a;
  std::vector<JointDef> joints;
  JointDef point = hinge;
  point.type = JointType::point;
  point.limited = false;
  joints.push_back(point);
  for (const Fixed side : {half_width, -half_width}) {
    JointDef rope = hinge;
    rope.type = JointType::max_distance;
    rope.limited = false;
    rope.anchor_a = rope.anchor_b = centre + axis * side;
    rope.length = sloppiness;
    joints.push_back(rope);
  }
  if (hinge.limited) {
    // A unit vector normal to the axis (as the hinge's own reference).
    const Vec3 other = abs(axis.x) < 0.5_fx ? Vec3{Fixed::one(), Fixed{}, Fixed{}} : Vec3{Fixed{}, Fixed::one(), Fixed{}};
    const Vec3 reference = normalize(cross(axis, other));
    const Fixed middle = (hinge.lower_angle + hinge.upper_angle) / 2.0_fx;
    const Fixed half_range = (hinge.upper_angle - hinge.lower_angle) / 2.0_fx;
    JointDef limit = hinge;
    limit.type = JointType::max_distance;
    limit.limited = false;
    limit.anchor_a = centre + rotate(from_axis_angle(axis, middle), reference) * half_width;
    limit.anchor_b = centre + reference * half_width;
    // The chord of the half range on a circle of radius half_width.
    limit.length = 2.0_fx * half_width * sin(half_range / 2.0_fx);
    joints.push_back(limit);
  }
  return joints;
}

}  // namespace bitstep
