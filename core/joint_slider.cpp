// A slider (prismatic joint, as Jolt's SliderConstraint and Box2D's
// prismatic joint): b slides along an axis fixed in a, without turning
// relative to a and without leaving the axis, optionally within
// [lower_translation, upper_translation], optionally driven by a motor,
// optionally against a friction force.
//
// With u = b's anchor minus a's (the gap, m) and a's axis x:
// - two linear rows C_k = u . n_k across the axis (n_1, n_2 normal to x,
//   turning with a). dC/dt = n . (v_b + w_b x r_b - v_a - w_a x r_a) +
//   u . (w_a x n), so J = [-n, -(r_a + u) x n, n, r_b x n]: the row of an
//   arm r_a + u on a (make_jacobian);
// - three angular rows (w_b - w_a) . e_k about the world axes, holding
//   b's frame (axis, reference, their cross product) on a's: the rotation
//   error is theta = 1/2 sum_k c_b,k x c_a,k (rad; for b turned by a small
//   phi from a, sum_k (phi x c) x c = -2 phi, so theta = -phi, the turn
//   that takes b back);
// solved as one block: lambda = K^-1 (target - J v), K = J M^-1 J^T (5x5,
// K_pq = d_p . (d_q / m_a + d_q / m_b) + (arm_a,p) . I_a^-1 arm_a,q +
// (arm_b,p) . I_b^-1 arm_b,q; N s for the linear rows, N m s for the
// angular). The translation d = u . x (m, 0 at creation) moves at J_x v
// with the axis row J_x = [-x, -(r_a + u) x x, x, r_b x x]; its limit, its
// motor and its friction are rows on J_x, each paired with the block
// impulse that leaves the block's rates as they were (c = -K^-1 g, g =
// J_block M^-1 J_x^T; the pair's effective mass 1 / (J_x M^-1 J_x^T + g . c),
// the Schur complement), so that holding the axis does not undo the limit.
//
// The block, and the limit where the step's start engages it, are a node of
// the tree solve (joint_tree.h): solved block by block, a light link
// between two sliders holding 100 times its mass converges only slowly over
// the passes, and swung sideways it slides off along its axis
// (tests/core/joint_range_tests.cpp: it stays on its axes). Where the tree
// cannot take the joints (a loop among movable bodies) the block is solved
// whole here, exact for one slider in one pass, which is also what the
// projection after the integration runs (joint_projection.h). The motor, a
// limit that engages mid-step and friction are rows of their own.
#include "core/joint_types.h"

namespace bitstep {

namespace {

constexpr int block_rows = 5;

// The angular row (w_b - w_a) . e as a Jacobian (no linear part: arms e on
// both bodies), so that the block's rows share one form.
Jacobian angular_row(const SolverBody& a, const SolverBody& b, Vec3 e) {
  const AngularPart part = make_twist(a, b, e);
  return {Vec3{}, e, e, Vec3{}, Vec3{}, part.turn_a, part.turn_b, part.mass};
}

// J_p M^-1 J_q^T: the rate of row p per unit impulse of row q.
Fixed coupling(const Jacobian& p, const Jacobian& q) {
  return dot(p.direction, q.linear_a + q.linear_b) + dot(p.arm_a, q.turn_a) + dot(p.arm_b, q.turn_b);
}

// b's frame turned back onto a's (rad, world axes): theta above.
Vec3 rotation_error(const JointSetup& setup) {
  const Joint& joint = setup.joint;
  const Quat qa = setup.body_a.pose.orientation, qb = setup.body_b.pose.orientation;
  const Vec3 axis_a = rotate(qa, joint.local_axis_a), axis_b = rotate(qb, joint.local_axis_b);
  const Vec3 ref_a = rotate(qa, joint.local_reference_a), ref_b = rotate(qb, joint.local_reference_b);
  const Vec3 sum = cross(axis_b, axis_a) + cross(ref_b, ref_a) + cross(cross(axis_b, ref_b), cross(axis_a, ref_a));
  return sum / 2.0_fx;
}

// The block's rows at the step's poses, K^-1, and the rates that close
// the gap across the axis and the rotation error.
void prepare_block(const JointSetup& setup, JointRow& row, Vec3 arm_a, const Vec3 (&across)[2], Vec3 gap) {
  const Vec3 unit[3] = {{Fixed::one(), {}, {}}, {{}, Fixed::one(), {}}, {{}, {}, Fixed::one()}};
  for (int k = 0; k < 2; ++k) row.slide[k] = make_jacobian(setup.a, setup.b, arm_a, row.rb, across[k]);
  for (int k = 0; k < 3; ++k) row.slide[2 + k] = angular_row(setup.a, setup.b, unit[k]);
  Block k{};
  for (int p = 0; p < block_rows; ++p) {
    for (int q = 0; q <= p; ++q) k.at[p][q] = k.at[q][p] = coupling(row.slide[p], row.slide[q]);
  }
  row.slide_mass = inverse_spd(k, block_rows);
  const Vec3 turn = rotation_error(setup);
  const Fixed error[block_rows] = {-dot(gap, across[0]), -dot(gap, across[1]), turn.x, turn.y, turn.z};
  Fixed(&target)[block_rows] = setup.settings.baumgarte ? row.slide_target : row.slide_push_target;
  for (int p = 0; p < block_rows; ++p) target[p] = recovery(error[p], setup.factor, setup.inverse_dt, setup.max_speed);
}

// The axis row and its pairing with the block.
void prepare_axis(const JointSetup& setup, JointRow& row, Vec3 arm_a, Vec3 axis) {
  row.slide_axis = make_jacobian(setup.a, setup.b, arm_a, row.rb, axis);
  Fixed g[block_rows];
  for (int p = 0; p < block_rows; ++p) g[p] = coupling(row.slide[p], row.slide_axis);
  Fixed k = coupling(row.slide_axis, row.slide_axis);
  for (int p = 0; p < block_rows; ++p) {
    Fixed c;
    for (int q = 0; q < block_rows; ++q) c = mul_add(row.slide_mass.at[p][q], g[q], c);
    row.slide_axis_anchor[p] = -c;
    k -= c * g[p];
  }
  row.slide_axis_mass = k > Fixed{} ? Fixed::one() / k : Fixed{};
}

// The block's impulses lambda applied, and added to the joint's: the
// linear rows' as a world vector (point), the angular rows' (angular).
void apply_block(BodyRates& a, BodyRates& b, const JointRow& row, const Fixed (&lambda)[block_rows], Vec3& point,
                 Vec3& angular) {
  for (int p = 0; p < block_rows; ++p) apply_rate(a, b, row.slide[p], lambda[p]);
  add_block_impulses(row, lambda, point, angular);
}

// An impulse on the axis row with its paired block impulse.
void apply_axis(BodyRates& a, BodyRates& b, const JointRow& row, Fixed lambda, Vec3& point, Vec3& angular) {
  if (lambda == Fixed{}) return;
  apply_rate(a, b, row.slide_axis, lambda);
  Fixed paired[block_rows];
  for (int p = 0; p < block_rows; ++p) paired[p] = row.slide_axis_anchor[p] * lambda;
  apply_block(a, b, row, paired, point, angular);
}

// The axis row's accumulated impulse moved toward `target` (m/s) and
// clamped within [low, high].
void solve_axis_row(BodyRates& a, BodyRates& b, const JointRow& row, Fixed target, Fixed& accumulated, Fixed low,
                    Fixed high, Vec3& point, Vec3& angular) {
  const Fixed change = row.slide_axis_mass * (target - relative_rate(a, b, row.slide_axis));
  const Fixed total = max(min(bounded_total(accumulated, change), high), low);
  apply_axis(a, b, row, total - accumulated, point, angular);
  accumulated = total;
}

}  // namespace

Result<void> SliderJoint::validate(const JointDef& def) {
  if (length(def.axis) < 0.001_fx) return Error{"axis", "shorter than 0.001"};
  if (def.limited && (def.lower_translation < -1000.0_fx || def.lower_translation > Fixed{} ||
                      def.upper_translation < Fixed{} || def.upper_translation > 1000.0_fx)) {
    return Error{"limits", "lower_translation must be within -1000..0 m and upper_translation within 0..1000"};
  }
  return {};
}

Result<void> SliderJoint::check_motor(Fixed speed, Fixed max) {
  return bitstep::check_motor(speed, max, envelope::max_linear_speed);
}

const Vec3& SliderJoint::anchor_b(const JointDef& def) { return def.anchor_a; }

void SliderJoint::make_frames(const JointDef& def, const Body& a, const Body& b, Joint& joint) {
  set_axis_frames(def, a, b, joint);
  joint.limited = def.limited;
  if (joint.limited) {
    joint.lower_translation = def.lower_translation;
    joint.upper_translation = def.upper_translation;
  }
  joint.motor_speed = def.motor_speed;
  joint.motor_max = def.motor_max;
}

void SliderJoint::prepare(const JointSetup& setup, JointRow& row) {
  Joint& joint = setup.joint;
  const Vec3 gap = anchor_gap(setup, row);
  const Vec3 axis = rotate(setup.body_a.pose.orientation, joint.local_axis_a);
  Vec3 across[2];
  normal_pair(axis, across[0], across[1]);
  const Vec3 arm_a = row.ra + gap;  // the rows turn with a: their arm on a reaches b's anchor
  prepare_block(setup, row, arm_a, across, gap);
  prepare_axis(setup, row, arm_a, axis);
  row.slide_rows_in_tree = true;
  // Last step's impulse across the axis, on this step's directions.
  joint.point_impulse =
      across[0] * dot(joint.point_impulse, across[0]) + across[1] * dot(joint.point_impulse, across[1]);
  if (joint.limited) {
    const Fixed rate = relative_rate(body_rates(setup.body_a), body_rates(setup.body_b), row.slide_axis);
    const Fixed past =
        prepare_limit_side(setup, row, dot(gap, axis), rate, joint.lower_translation, joint.upper_translation);
    // In the tree where engaged; else row by row, and into the tree once
    // it acts (joint_solver.cpp).
    row.limit_in_tree = row.limit_side != 0 && limit_engaged(row, past, rate, joint.limit_impulse);
  }
  prepare_motor_limit(setup, row);
  if (joint.friction_torque > Fixed{}) {
    row.friction = true;
    row.friction_max = joint.friction_torque * setup.settings.dt;  // N s
  }
}

void SliderJoint::warm_start(SolverBody& sa, SolverBody& sb, const JointRow& row) {
  const Joint& joint = *row.joint;
  const Vec3 angular = joint.angular_impulse;
  const Fixed lambda[block_rows] = {dot(joint.point_impulse, row.slide[0].direction),
                                    dot(joint.point_impulse, row.slide[1].direction), angular.x, angular.y, angular.z};
  Vec3 unused_point, unused_angular;
  apply_block(sa.velocity, sb.velocity, row, lambda, unused_point, unused_angular);
  if (row.limit_side != 0) apply_rate(sa.velocity, sb.velocity, row.slide_axis, joint.limit_impulse);
  if (row.motor) apply_rate(sa.velocity, sb.velocity, row.slide_axis, joint.motor_impulse);
}

// The motor (velocity only), the limit, then the block, so that holding
// b on the axis has the last word (the tree's, where it takes them).
void SliderJoint::solve_rows(const SolverBody&, const SolverBody&, BodyRates& a, BodyRates& b, JointRow& row,
                             const Targets& target, Impulses impulse, bool in_tree) {
  if (target.motor_on) {
    solve_axis_row(a, b, row, target.motor, impulse.motor, -row.motor_limit, row.motor_limit, impulse.point,
                   impulse.angular);
  }
  if (target.limit_on && !(in_tree && row.limit_in_tree)) {
    const Fixed low = row.limit_side > 0 ? Fixed{} : Fixed::lowest();
    const Fixed high = row.limit_side > 0 ? Fixed::max() : Fixed{};
    solve_axis_row(a, b, row, target.limit, impulse.limit, low, high, impulse.point, impulse.angular);
  }
  if (in_tree) return;
  Fixed rhs[block_rows];
  for (int p = 0; p < block_rows; ++p) rhs[p] = target.slide[p] - relative_rate(a, b, row.slide[p]);
  Fixed lambda[block_rows];
  for (int p = 0; p < block_rows; ++p) {
    Fixed sum;
    for (int q = 0; q < block_rows; ++q) sum = mul_add(row.slide_mass.at[p][q], rhs[q], sum);
    lambda[p] = sum;
  }
  apply_block(a, b, row, lambda, impulse.point, impulse.angular);
}

// Against b sliding along the axis: from zero each step (no state), the
// total within friction dt (N s) either way; its paired block impulse is
// the joint's.
void SliderJoint::solve_friction(const SolverBody&, const SolverBody&, BodyRates& a, BodyRates& b, JointRow& row) {
  Joint& joint = *row.joint;
  solve_axis_row(a, b, row, Fixed{}, row.friction_impulse.x, -row.friction_max, row.friction_max, joint.point_impulse,
                 joint.angular_impulse);
}

bool SliderJoint::breaks(const Joint& joint) { return length(joint.point_impulse) > joint.break_impulse; }

// Its motor is a row of its own along the axis; an engaged limit must be
// in the tree.
bool SliderJoint::tree_alone(const JointRow& row) {
  return row.is_tree_node() && !row.motor && (row.limit_side == 0 || row.limit_in_tree);
}

// Its five rows and limit are not measured here: the projection builds its
// rows.
Fixed SliderJoint::position_error(const Joint&, const Body&, const Body&) { return Fixed::max(); }

Fixed slider_translation(const Joint& joint, const Body& a, const Body& b) {
  const Vec3 anchor_a = a.pose.apply(joint.local_anchor_a), anchor_b = b.pose.apply(joint.local_anchor_b);
  return dot(anchor_b - anchor_a, rotate(a.pose.orientation, joint.local_axis_a));
}

}  // namespace bitstep
