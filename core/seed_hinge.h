// JigLib's hinge, built from its two constraints: a point joint
// at the hinge's centre, two max-distance joints at +-half_width along the
// axis whose slack (`sloppiness`) lets the axis tilt a little (which suits
// ragdoll joints, JigLib says), and one more max-distance joint whose
// length bounds the angle: a point of b at `half_width` from the axis, at
// angle 0, may be no farther from a's point at the middle of the range
// than 2 r sin(half range / 2). bitstep's own hinge (JointType::hinge)
// holds the axis with two angular rows instead; core/README.md "Joints"
// compares the two. Used by scenes (the "seed_hinge" joint) and the tests.
#pragma once

#include <vector>

#include "core/joint.h"

namespace bitstep {

// The joints that make `hinge` (a JointType::hinge definition) JigLib's
// way, in the order to create them: the point, the two sides, the limit
// (when hinge.limited).
std::vector<JointDef> seed_hinge(const JointDef& hinge, Fixed half_width, Fixed sloppiness);

}  // namespace bitstep
