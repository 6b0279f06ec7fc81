// Ball and socket: a point of a and a point of b kept together, three
// linear rows solved as one 3x3 block (after Jolt's PointConstraintPart):
// lambda = K^-1 (target - J v), K = (1/m_a + 1/m_b) 1 - [r_a]x I_a^-1
// [r_a]x - [r_b]x I_b^-1 [r_b]x (joint_parts.h). In the tree solve
// (joint_tree.h) the block is a node of three rows.
#include "core/joint_types.h"

namespace bitstep {

Result<void> PointJoint::validate(const JointDef& def) {
  if (!def.limited) return {};
  return check_angle_limits(def);
}

Result<void> PointJoint::check_motor(Fixed speed, Fixed max) { return check_no_motor(speed, max); }

const Vec3& PointJoint::anchor_b(const JointDef& def) { return def.anchor_a; }

void PointJoint::make_frames(const JointDef&, const Body&, const Body&, Joint&) {}

void PointJoint::prepare(const JointSetup& setup, JointRow& row) {
  prepare_point_rows(setup, row, anchor_gap(setup, row));
  prepare_turn_friction(setup, row, nullptr);
}

void PointJoint::warm_start(SolverBody& sa, SolverBody& sb, const JointRow& row) {
  apply_point(sa, sb, sa.velocity, sb.velocity, row.ra, row.rb, row.joint->point_impulse);
}

void PointJoint::solve_rows(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b, JointRow& row,
                            const Targets& target, Impulses impulse, bool in_tree) {
  if (!in_tree) solve_point_rows(sa, sb, a, b, row, target, impulse);
}

void PointJoint::solve_friction(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b, JointRow& row) {
  solve_turn_friction(sa, sb, a, b, row);
}

bool PointJoint::breaks(const Joint& joint) { return length(joint.point_impulse) > joint.break_impulse; }

bool PointJoint::tree_alone(const JointRow& row) { return row.is_tree_node(); }

// The anchors' gap, each component as prepare_point_rows closes it.
Fixed PointJoint::position_error(const Joint& joint, const Body& a, const Body& b) { return largest_gap(joint, a, b); }

}  // namespace bitstep
