// A ragdoll's shoulder or hip: a point joint whose twist axis (on b) stays
// within swing_angle of a's copy of it (a cone) and whose twist about it
// stays within [lower_angle, upper_angle]. The point block (joint_point.cpp's),
// a one-sided swing row turning b's axis back toward a's, and the twist's
// limit row. In the tree solve (joint_tree.h) the joint is a node of the
// point block's three rows and the swing and twist limit where engaged.
#include "core/joint_types.h"

namespace bitstep {

namespace {

// The row whose rate is a cone's twist rate (hinge_angle's): t = (a + b) /
// (1 + a . b) for the two bodies' axes a and b. The twist is b's reference
// against a's carried by the shortest turn S from a to b, so it turns with
// w . b (w = w_b - w_a) less the frame S's own turn about b, which is
// -(a x b) . (w x b) / (1 + a . b) = -(w . a - (a . b)(w . b)) / (1 + a . b);
// together (a + b) . w / (1 + a . b). b alone (the rate about b's axis)
// leaves out a swing's sweep around the cone: a shoulder swung wide and
// circling would twist far past its limit while its row saw no twist.
// |t| = sqrt(2 / (1 + a . b)), 1.55 at the widest cone a ragdoll has (80
// degrees); near a swing of 180 degrees, where the twist is undefined, b.
Vec3 twist_rate_axis(Vec3 axis_a, Vec3 axis_b) {
  const Fixed one_plus_cosine = Fixed::one() + dot(axis_a, axis_b);
  if (one_plus_cosine < 0.01_fx) return axis_b;
  return (axis_a + axis_b) / one_plus_cosine;
}

// The swing back toward the cone: b's axis turned toward a's about s =
// axis_b x axis_a (normalised), one-sided, speculative like the limits;
// undefined (and far inside any cone wider than 0.06 degrees) below 1e-3
// rad. The row is hinge[0].
void prepare_swing(const JointSetup& setup, JointRow& row, Vec3 axis_a, Vec3 axis_b) {
  Joint& joint = setup.joint;
  const Vec3 s = cross(axis_b, axis_a);
  const Fixed sine = length(s);
  row.swing_active = sine > 0.001_fx;
  if (!row.swing_active) {
    joint.hinge_impulse[0] = Fixed{};
    return;
  }
  const Fixed swing = atan2(sine, dot(axis_a, axis_b));
  row.hinge[0] = make_twist(setup.a, setup.b, s / sine);
  pair_with_point(row, row.hinge[0], row.hinge_anchor[0], row.hinge_mass[0]);
  const Fixed past = swing - joint.swing_angle;
  if (past <= Fixed{}) {
    row.hinge_target[0] = past * setup.inverse_dt;
  } else if (setup.settings.baumgarte) {
    row.hinge_target[0] = recovery(past, setup.factor, setup.inverse_dt, setup.max_speed);
  } else {
    row.hinge_push_target[0] = recovery(past, setup.factor, setup.inverse_dt, setup.max_speed);
  }
  // In the tree solve (engaged) where it binds at the rates the step
  // starts with, or is past, or held last step; else row by row.
  const Fixed rate = spin(body_rates(setup.body_a), body_rates(setup.body_b), row.hinge[0]);
  row.swing_in_tree = past > Fixed{} || rate <= row.hinge_target[0] || joint.hinge_impulse[0] > Fixed{};
}

}  // namespace

Result<void> ConeJoint::validate(const JointDef& def) {
  if (length(def.axis) < 0.001_fx) return Error{"axis", "shorter than 0.001"};
  if (Result<void> refused = check_angle_limits(def); !refused.ok()) return refused;
  if (def.swing_angle < Fixed{} || def.swing_angle > half_turn) return Error{"swing_angle", "outside 0..180 degrees"};
  return {};
}

Result<void> ConeJoint::check_motor(Fixed speed, Fixed max) { return check_no_motor(speed, max); }

const Vec3& ConeJoint::anchor_b(const JointDef& def) { return def.anchor_a; }

void ConeJoint::make_frames(const JointDef& def, const Body& a, const Body& b, Joint& joint) {
  set_axis_frames(def, a, b, joint);
  joint.limited = true;  // the twist's limits always
  joint.lower_angle = def.lower_angle;
  joint.upper_angle = def.upper_angle;
  joint.swing_angle = def.swing_angle;
}

void ConeJoint::prepare(const JointSetup& setup, JointRow& row) {
  const Joint& joint = setup.joint;
  prepare_point_rows(setup, row, anchor_gap(setup, row));
  const auto [axis_a, axis_b] = world_axes(setup);
  prepare_swing(setup, row, axis_a, axis_b);
  if (joint.limited) {
    prepare_angle_limit(setup, row, twist_angle(joint, setup.body_a, setup.body_b), twist_rate_axis(axis_a, axis_b));
  }
  prepare_turn_friction(setup, row, nullptr);
}

void ConeJoint::warm_start(SolverBody& sa, SolverBody& sb, const JointRow& row) {
  const Joint& joint = *row.joint;
  apply_point(sa, sb, sa.velocity, sb.velocity, row.ra, row.rb, joint.point_impulse);
  if (row.swing_active) apply_turn(sa.velocity, sb.velocity, row.hinge[0], joint.hinge_impulse[0]);
  if (row.limit_side != 0) apply_turn(sa.velocity, sb.velocity, row.limit, joint.limit_impulse);
}

// The swing, the twist limit, then the point block, so that the anchors'
// coincidence has the last word; with the tree solve, the swing and the
// limit alone where they are not engaged.
void ConeJoint::solve_rows(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b, JointRow& row,
                           const Targets& target, Impulses impulse, bool in_tree) {
  if (target.swing_on && !(in_tree && row.swing_in_tree)) {
    // The swing back toward the cone: an impulse >= 0 about s.
    const Fixed total =
        clamp_swing(bounded_total(impulse.hinge[0], row.hinge_mass[0] * (target.hinge[0] - spin(a, b, row.hinge[0]))));
    apply_paired(sa, sb, a, b, row, row.hinge[0], row.hinge_anchor[0], total - impulse.hinge[0], impulse.point);
    impulse.hinge[0] = total;
  }
  solve_angle_limit(sa, sb, a, b, row, target, impulse, in_tree);
  if (!in_tree) solve_point_rows(sa, sb, a, b, row, target, impulse);
}

void ConeJoint::solve_friction(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b, JointRow& row) {
  solve_turn_friction(sa, sb, a, b, row);
}

bool ConeJoint::breaks(const Joint& joint) { return length(joint.point_impulse) > joint.break_impulse; }

// An engaged swing and twist limit must be in the tree.
bool ConeJoint::tree_alone(const JointRow& row) {
  return row.is_tree_node() && (!row.swing_active || row.swing_in_tree) && (row.limit_side == 0 || row.limit_in_tree);
}

// Its swing and twist limits are not measured here: the projection builds
// its rows.
Fixed ConeJoint::position_error(const Joint&, const Body&, const Body&) { return Fixed::max(); }

// A cone's twist: a's reference carried by the swing (the shortest turn
// taking a's axis onto b's, about k = axis_a x axis_b / sin, by Rodrigues'
// formula), then its angle to b's reference about b's axis. Measured about
// a's axis instead, a 60 degree swing read as 80 degrees of twist.
Fixed twist_angle(const Joint& joint, const Body& a, const Body& b) {
  const Vec3 axis = rotate(a.pose.orientation, joint.local_axis_a);
  Vec3 ref_a = rotate(a.pose.orientation, joint.local_reference_a);
  const Vec3 ref_b = rotate(b.pose.orientation, joint.local_reference_b);
  const Vec3 axis_b = rotate(b.pose.orientation, joint.local_axis_b);
  const Vec3 k = cross(axis, axis_b);
  const Fixed sine = length(k), cosine = dot(axis, axis_b);
  if (sine > 0.000001_fx) {
    const Vec3 unit = k / sine;
    ref_a = ref_a * cosine + cross(unit, ref_a) * sine + unit * (dot(unit, ref_a) * (Fixed::one() - cosine));
  }
  return atan2(dot(cross(ref_a, ref_b), axis_b), dot(ref_a, ref_b));
}

Fixed swing_angle(const Joint& joint, const Body& a, const Body& b) {
  const Vec3 axis_a = rotate(a.pose.orientation, joint.local_axis_a);
  const Vec3 axis_b = rotate(b.pose.orientation, joint.local_axis_b);
  return atan2(length(cross(axis_b, axis_a)), dot(axis_a, axis_b));
}

}  // namespace bitstep
