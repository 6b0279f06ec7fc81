// A hinge: a point joint whose bodies turn relative to each other about
// one axis only, optionally within [lower_angle, upper_angle], optionally
// driven by a motor. The point
// block (joint_point.cpp's), two angular rows (w_b - w_a) . p_k about axes
// p_k normal to a's hinge axis that keep b's copy of the axis on it, and
// a limit row about the axis. In the tree solve (joint_tree.h) the joint
// is a node of the point block's three rows, the two angular rows and the
// limit where it is engaged.
#include "core/joint_types.h"

namespace bitstep {

namespace {

// The motor: a row about the axis, (w_b - w_a) . axis = motor_speed,
// paired with the point impulse as the limit is (pair_with_point), its
// accumulated impulse within motor_max dt (N m s) either way.
void prepare_motor(const JointSetup& setup, JointRow& row, Vec3 axis) {
  prepare_motor_limit(setup, row);
  if (!row.motor) return;
  row.motor_turn = make_twist(setup.a, setup.b, axis);
  pair_with_point(row, row.motor_turn, row.motor_anchor, row.motor_mass);
}

void solve_motor(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b, const JointRow& row,
                 const Targets& target, Impulses& impulse) {
  const Fixed change = row.motor_mass * (target.motor - spin(a, b, row.motor_turn));
  const Fixed total = max(min(bounded_total(impulse.motor, change), row.motor_limit), -row.motor_limit);
  apply_paired(sa, sb, a, b, row, row.motor_turn, row.motor_anchor, total - impulse.motor, impulse.point);
  impulse.motor = total;
}

}  // namespace

Result<void> HingeJoint::validate(const JointDef& def) {
  if (length(def.axis) < 0.001_fx) return Error{"axis", "shorter than 0.001"};
  if (!def.limited) return {};
  return check_angle_limits(def);
}

Result<void> HingeJoint::check_motor(Fixed speed, Fixed max) {
  return bitstep::check_motor(speed, max, envelope::max_angular_speed);
}

const Vec3& HingeJoint::anchor_b(const JointDef& def) { return def.anchor_a; }

void HingeJoint::make_frames(const JointDef& def, const Body& a, const Body& b, Joint& joint) {
  set_axis_frames(def, a, b, joint);
  joint.limited = def.limited;
  if (joint.limited) {
    joint.lower_angle = def.lower_angle;
    joint.upper_angle = def.upper_angle;
  }
  joint.motor_speed = def.motor_speed;
  joint.motor_max = def.motor_max;
}

void HingeJoint::prepare(const JointSetup& setup, JointRow& row) {
  const Joint& joint = setup.joint;
  prepare_point_rows(setup, row, anchor_gap(setup, row));
  const auto [axis_a, axis_b] = world_axes(setup);
  Vec3 p[2];
  normal_pair(axis_a, p[0], p[1]);
  // b's axis is turned onto a's by a rotation about axis_b x axis_a (its
  // length the sine of the angle between them).
  const Vec3 misalignment = cross(axis_b, axis_a);
  for (int k = 0; k < 2; ++k) {
    row.hinge[k] = make_twist(setup.a, setup.b, p[k]);
    const Fixed rate = recovery(dot(misalignment, p[k]), setup.factor, setup.inverse_dt, setup.max_speed);
    (setup.settings.baumgarte ? row.hinge_target[k] : row.hinge_push_target[k]) = rate;
  }
  for (int k = 0; k < 2; ++k) pair_with_point(row, row.hinge[k], row.hinge_anchor[k], row.hinge_mass[k]);
  row.hinge_rows_in_tree = true;
  if (joint.limited) prepare_angle_limit(setup, row, hinge_angle(joint, setup.body_a, setup.body_b), axis_a);
  prepare_turn_friction(setup, row, &axis_a);
  prepare_motor(setup, row, axis_a);
}

void HingeJoint::warm_start(SolverBody& sa, SolverBody& sb, const JointRow& row) {
  const Joint& joint = *row.joint;
  apply_point(sa, sb, sa.velocity, sb.velocity, row.ra, row.rb, joint.point_impulse);
  apply_turn(sa.velocity, sb.velocity, row.hinge[0], joint.hinge_impulse[0]);
  apply_turn(sa.velocity, sb.velocity, row.hinge[1], joint.hinge_impulse[1]);
  if (row.limit_side != 0) apply_turn(sa.velocity, sb.velocity, row.limit, joint.limit_impulse);
  if (row.motor) apply_turn(sa.velocity, sb.velocity, row.motor_turn, joint.motor_impulse);
}

// The motor (velocity only), the two angular rows, the limit, then the point block, so that the
// anchors' coincidence has the last word; with the tree solve, the limit
// alone where it is not engaged.
void HingeJoint::solve_rows(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b, JointRow& row,
                            const Targets& target, Impulses impulse, bool in_tree) {
  if (target.motor_on) solve_motor(sa, sb, a, b, row, target, impulse);
  for (int k = 0; k < 2 && !in_tree; ++k) {
    const Fixed lambda = accumulate(impulse.hinge[k], row.hinge_mass[k] * (target.hinge[k] - spin(a, b, row.hinge[k])));
    apply_paired(sa, sb, a, b, row, row.hinge[k], row.hinge_anchor[k], lambda, impulse.point);
  }
  solve_angle_limit(sa, sb, a, b, row, target, impulse, in_tree);
  if (!in_tree) solve_point_rows(sa, sb, a, b, row, target, impulse);
}

// About the axis alone: the total in friction_impulse.x, within
// friction_torque dt either way.
void HingeJoint::solve_friction(const SolverBody&, const SolverBody&, BodyRates& a, BodyRates& b, JointRow& row) {
  const Fixed max_impulse = row.friction_max;
  const Fixed total =
      max(min(row.friction_impulse.x - row.friction_hinge.mass * spin(a, b, row.friction_hinge), max_impulse),
          -max_impulse);
  apply_turn(a, b, row.friction_hinge, total - row.friction_impulse.x);
  row.friction_impulse.x = total;
}

bool HingeJoint::breaks(const Joint& joint) { return length(joint.point_impulse) > joint.break_impulse; }

// Its motor is a row of its own; an engaged limit must be in the tree.
bool HingeJoint::tree_alone(const JointRow& row) {
  return row.is_tree_node() && !row.motor && (row.limit_side == 0 || row.limit_in_tree);
}

// The anchors' gap; the axes' misalignment, |axis_b x axis_a| bounded by
// its components' sum (each angular row closes its part along p_k); and
// how far the angle is past either limit.
Fixed HingeJoint::position_error(const Joint& joint, const Body& a, const Body& b) {
  const Vec3 misalignment =
      cross(rotate(b.pose.orientation, joint.local_axis_b), rotate(a.pose.orientation, joint.local_axis_a));
  Fixed error = max(largest_gap(joint, a, b), abs(misalignment.x) + abs(misalignment.y) + abs(misalignment.z));
  if (joint.limited) {
    const Fixed angle = hinge_angle(joint, a, b);
    error = max(error, max(joint.lower_angle - angle, angle - joint.upper_angle));
  }
  return error;
}

}  // namespace bitstep
