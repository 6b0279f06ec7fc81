// A rope (max_distance): the anchors at most `length` apart. One axis row
// along the line from a's anchor to b's, J v = d . (v_b + w_b x r_b - v_a
// - w_a x r_a), pulling only (its impulse <= 0), speculative while slack:
// the anchors may separate by what is left of the length this step. It
// takes no part in the tree solve and has no friction.
#include "core/joint_types.h"

namespace bitstep {

namespace {

// Below this the rope's direction is not defined (m); it is slack there.
constexpr Fixed rope_min_length = 0.0001_fx;

}  // namespace

Result<void> RopeJoint::validate(const JointDef& def) {
  if (def.limited) {
    if (Result<void> refused = check_angle_limits(def); !refused.ok()) return refused;
  }
  if (def.friction_torque != Fixed{}) return Error{"friction_torque", "a rope has no friction"};
  return {};
}

Result<void> RopeJoint::check_motor(Fixed speed, Fixed max) { return check_no_motor(speed, max); }

const Vec3& RopeJoint::anchor_b(const JointDef& def) { return def.anchor_b; }

void RopeJoint::make_frames(const JointDef&, const Body&, const Body&, Joint&) {}

void RopeJoint::prepare(const JointSetup& setup, JointRow& row) {
  Joint& joint = setup.joint;
  const Vec3 gap = anchor_gap(setup, row);
  const Fixed distance = length(gap);
  row.rope_active = distance > rope_min_length;
  if (!row.rope_active) {
    joint.distance_impulse = Fixed{};
    return;
  }
  row.rope = make_jacobian(setup.a, setup.b, row.ra, row.rb, gap / distance);
  // Slack: the anchors may separate by what is left of the length this
  // step. Taut beyond it: they stop separating, and the excess is pushed
  // out (or, Baumgarte, pulled in by the velocity).
  const Fixed excess = distance - joint.length;
  if (excess <= Fixed{}) {
    row.rope_target = -excess * setup.inverse_dt;
  } else if (setup.settings.baumgarte) {
    row.rope_target = -recovery(excess, setup.factor, setup.inverse_dt, setup.max_speed);
  } else {
    row.rope_push_target = -recovery(excess, setup.factor, setup.inverse_dt, setup.max_speed);
  }
}

void RopeJoint::warm_start(SolverBody& sa, SolverBody& sb, const JointRow& row) {
  if (row.rope_active) apply_rate(sa.velocity, sb.velocity, row.rope, row.joint->distance_impulse);
}

void RopeJoint::solve_rows(const SolverBody&, const SolverBody&, BodyRates& a, BodyRates& b, JointRow& row,
                           const Targets& target, Impulses impulse, bool) {
  if (!target.rope_on) return;
  // Pulling only: the impulse along the line from a to b is <= 0.
  const Fixed rate = relative_rate(a, b, row.rope);
  const Fixed total = min(bounded_total(impulse.rope, row.rope.mass * (target.rope - rate)), Fixed{});
  apply_rate(a, b, row.rope, total - impulse.rope);
  impulse.rope = total;
}

void RopeJoint::solve_friction(const SolverBody&, const SolverBody&, BodyRates&, BodyRates&, JointRow&) {}

bool RopeJoint::breaks(const Joint& joint) { return -joint.distance_impulse > joint.break_impulse; }

// A taut rope is a one-sided row of its own, solved row by row.
bool RopeJoint::tree_alone(const JointRow& row) { return !row.rope_active && row.rope_push_target == Fixed{}; }

// How far the anchors are apart beyond the length.
Fixed RopeJoint::position_error(const Joint& joint, const Body& a, const Body& b) {
  return max(length(anchor_gap(joint, a, b)) - joint.length, Fixed{});
}

}  // namespace bitstep
