#include "core/joint_parts.h"

#include "core/joint_types.h"

namespace bitstep {

Result<void> check_angle_limits(const JointDef& def) {
  if (def.lower_angle < -half_turn || def.lower_angle > Fixed{} || def.upper_angle < Fixed{} ||
      def.upper_angle > half_turn) {
    return Error{"limits", "lower must be within -180..0 degrees and upper within 0..180"};
  }
  return {};
}

void set_axis_frames(const JointDef& def, const Body& a, const Body& b, Joint& joint) {
  const Vec3 axis = normalize(def.axis);
  // A unit vector normal to the axis: the angle is measured between its
  // two bodies' copies, equal now.
  const Vec3 other = abs(axis.x) < 0.5_fx ? Vec3{Fixed::one(), Fixed{}, Fixed{}} : Vec3{Fixed{}, Fixed::one(), Fixed{}};
  const Vec3 reference = normalize(cross(axis, other));
  joint.local_axis_a = rotate_inverse(a.pose.orientation, axis);
  joint.local_axis_b = rotate_inverse(b.pose.orientation, axis);
  joint.local_reference_a = rotate_inverse(a.pose.orientation, reference);
  joint.local_reference_b = rotate_inverse(b.pose.orientation, reference);
}

void prepare_point_rows(const JointSetup& setup, JointRow& row, Vec3 gap) {
  row.point_k = point_block(setup.a, setup.b, row.ra, row.rb);
  row.point_mass = inverse_spd(row.point_k);
  row.has_point_block = true;
  const Vec3 closing = -recovery(gap, setup.factor, setup.inverse_dt, setup.max_speed);
  (setup.settings.baumgarte ? row.point_target : row.point_push_target) = closing;
  // The constraint held at the step's end pose, not only in the direction
  // it has now: over the step an arm r turning at w moves its anchor by w
  // x (w x r) dt^2 / 2 beyond (w x r) dt (the anchor's centripetal path),
  // so the anchors' rate is to undo that. Without it each step's
  // projection onto the constraint as it stands takes away about (v dt /
  // L)^2 of the kinetic energy, and a swinging chain visibly slows down
  // (tests/core/joint_tests.cpp: it loses less than 5% in 10 s).
  const Vec3 curve_a = cross(setup.body_a.angular_velocity, cross(setup.body_a.angular_velocity, row.ra));
  const Vec3 curve_b = cross(setup.body_b.angular_velocity, cross(setup.body_b.angular_velocity, row.rb));
  row.point_target -= (curve_b - curve_a) * (setup.settings.dt / 2.0_fx);
}

Fixed prepare_limit_side(const JointSetup& setup, JointRow& row, Fixed value, Fixed rate, Fixed lower_bound,
                         Fixed upper_bound) {
  Joint& joint = setup.joint;
  // The limit nearer to where the value is heading (its rate at the
  // velocities the step starts the solve with: a fast turn toward the far
  // limit went past it while the near one was watched), as a speculative
  // row: the value may approach it by what is left this step; past it, it
  // stops, and the excess is pushed back.
  const Fixed heading = value + rate * setup.settings.dt;
  const bool lower = heading - lower_bound < upper_bound - heading;
  row.limit_side = lower ? 1 : -1;
  const Fixed bound = lower ? lower_bound : upper_bound;
  const Fixed past = lower ? bound - value : value - bound;  // > 0: beyond the limit
  if (past <= Fixed{}) {
    row.limit_target = (bound - value) * setup.inverse_dt;
  } else if (setup.settings.baumgarte) {
    row.limit_target = recovery(bound - value, setup.factor, setup.inverse_dt, setup.max_speed);
  } else {
    row.limit_push_target = recovery(bound - value, setup.factor, setup.inverse_dt, setup.max_speed);
  }
  // Last step's impulse held the other limit: it does not carry over.
  if ((lower && joint.limit_impulse < Fixed{}) || (!lower && joint.limit_impulse > Fixed{})) {
    joint.limit_impulse = Fixed{};
  }
  return past;
}

void prepare_angle_limit(const JointSetup& setup, JointRow& row, Fixed angle, Vec3 axis) {
  const Joint& joint = setup.joint;
  row.limit = make_twist(setup.a, setup.b, axis);
  pair_with_point(row, row.limit, row.limit_anchor, row.limit_mass);
  const Fixed rate = spin(body_rates(setup.body_a), body_rates(setup.body_b), row.limit);
  const Fixed past = prepare_limit_side(setup, row, angle, rate, joint.lower_angle, joint.upper_angle);
  // Engaged: in the tree solve; else row by row.
  row.limit_in_tree = limit_engaged(row, past, rate, joint.limit_impulse);
}

Result<void> check_motor(Fixed speed, Fixed max, Fixed max_speed) {
  if (max < Fixed{} || max > 1000000.0_fx) return Error{"motor", "max_torque or max_force outside 0..1000000"};
  if (speed < -max_speed || speed > max_speed) return Error{"motor", "speed beyond the world's largest"};
  return {};
}

Result<void> check_joint_motor(JointType type, Fixed speed, Fixed max) {
  if (!is_joint_type(type)) return Error{"type", "not a joint type"};
  return with_joint_type(type, [&](auto kind) { return decltype(kind)::check_motor(speed, max); });
}

Result<void> check_no_motor(Fixed speed, Fixed max) {
  if (speed != Fixed{} || max != Fixed{}) return Error{"motor", "only hinges and sliders have one"};
  return {};
}

void prepare_motor_limit(const JointSetup& setup, JointRow& row) {
  Joint& joint = setup.joint;
  row.motor = joint.motor_max > Fixed{};
  if (!row.motor) {
    joint.motor_impulse = Fixed{};
    return;
  }
  // Last step's impulse within this step's bound (motor_max or dt may
  // have changed since).
  row.motor_limit = joint.motor_max * setup.settings.dt;
  joint.motor_impulse = max(min(joint.motor_impulse, row.motor_limit), -row.motor_limit);
}

void prepare_turn_friction(const JointSetup& setup, JointRow& row, const Vec3* axis) {
  if (setup.joint.friction_torque <= Fixed{}) return;
  row.friction = true;
  row.friction_max = setup.joint.friction_torque * setup.settings.dt;
  if (axis != nullptr) {
    row.friction_hinge = make_twist(setup.a, setup.b, *axis);
  } else {
    row.friction_mass = inverse_spd(setup.a.inverse_inertia + setup.b.inverse_inertia);
  }
}

// About every axis at once: M = (I_a^-1 + I_b^-1)^-1, the accumulated
// total's length within friction_torque dt.
void solve_turn_friction(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b, JointRow& row) {
  const Fixed max_impulse = row.friction_max;
  Vec3 total = row.friction_impulse - row.friction_mass * (b.angular - a.angular);
  const Fixed size = length(total);
  if (size > max_impulse) total = total * (max_impulse / size);
  const Vec3 change = total - row.friction_impulse;
  a.angular -= sa.inverse_inertia * change;
  b.angular += sb.inverse_inertia * change;
  row.friction_impulse = total;
}

Fixed hinge_angle(const Joint& joint, const Body& a, const Body& b) {
  if (joint.type == JointType::cone) return twist_angle(joint, a, b);
  const Vec3 axis = rotate(a.pose.orientation, joint.local_axis_a);
  const Vec3 ref_a = rotate(a.pose.orientation, joint.local_reference_a);
  const Vec3 ref_b = rotate(b.pose.orientation, joint.local_reference_b);
  return atan2(dot(cross(ref_a, ref_b), axis), dot(ref_a, ref_b));
}

}  // namespace bitstep
