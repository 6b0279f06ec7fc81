// The constraint parts every joint type is built from (core/joint_types.h):
// the 3x3 point block, angular rows paired with the point impulse, the
// recovery rates, the one-sided clamps, and what a type's rows read and
// write on one rate of the bodies (Targets, Impulses). Shared by the
// type files (joint_point.cpp, joint_rope.cpp, joint_hinge.cpp,
// joint_cone.cpp) and the solve that runs them
// (joint_solver.cpp). Internal to core/.
#pragma once

#include "core/joint_solver.h"

namespace bitstep {

// What a type's prepare reads: the step's rates and factors, the two
// bodies (their poses, and as the solve sees them), and the joint, whose
// impulses it may reset (a row that does not act this step).
struct JointSetup {
  const Settings& settings;
  Fixed inverse_dt;  // 1/s
  Fixed factor;      // the share of an error closed per step (split impulse or Baumgarte)
  Fixed max_speed;   // m/s or rad/s: the most a recovery rate may be
  const Body& body_a;
  const Body& body_b;
  const SolverBody& a;
  const SolverBody& b;
  Joint& joint;
};

// b's anchor from a's (m) at the step's poses.
inline Vec3 anchor_gap(const JointSetup& setup, const JointRow& row) {
  return (setup.body_b.pose.position + row.rb) - (setup.body_a.pose.position + row.ra);
}

// b's anchor from a's (m) at the bodies' poses, from the joint alone.
inline Vec3 anchor_gap(const Joint& joint, const Body& a, const Body& b) {
  return (b.pose.position + rotate(b.pose.orientation, joint.local_anchor_b)) -
         (a.pose.position + rotate(a.pose.orientation, joint.local_anchor_a));
}

// Its largest component (m).
inline Fixed largest_gap(const Joint& joint, const Body& a, const Body& b) {
  const Vec3 gap = anchor_gap(joint, a, b);
  return max(max(abs(gap.x), abs(gap.y)), abs(gap.z));
}

// The joint's axis as each body carries it (local_axis_a, local_axis_b),
// in the world frame at the step's poses.
struct AxisPair {
  Vec3 a, b;
};
inline AxisPair world_axes(const JointSetup& setup) {
  return {rotate(setup.body_a.pose.orientation, setup.joint.local_axis_a),
          rotate(setup.body_b.pose.orientation, setup.joint.local_axis_b)};
}

// The rows of one joint on one rate of the bodies (velocity or push).
struct Targets {
  Vec3 point;
  Fixed rope, hinge[2], limit;
  // A rope or limit row acts. In the position passes a rope acts only past
  // its length; a limit always: the push that closes the anchors' gap may
  // turn the arm, and may not turn it toward its nearer limit (it did, 3
  // degrees past under a 1,000 N m torque).
  bool rope_on, limit_on, swing_on;
  // A slider's block: its two rows across the axis, then its three
  // angular rows. The motor's speed where it drives (velocity only).
  Fixed slide[5];
  Fixed motor;
  bool motor_on;
};
struct Impulses {
  Vec3& point;
  Fixed& rope;
  Fixed (&hinge)[2];
  Fixed& limit;
  Vec3& angular;  // a slider's three angular rows (N m s, world axes)
  Fixed& motor;
};

// Whether total + change (raw, into `sum`) neither wraps nor leaves
// +-max_joint_impulse: one add and one compare (sum + bound in 0..2 bound,
// unsigned), the case of every joint that holds.
inline bool sum_within_bound(Fixed total, Fixed change, int64_t& sum) {
  constexpr uint64_t bound = max_joint_impulse.raw();
  return !__builtin_add_overflow(total.raw(), change.raw(), &sum) && static_cast<uint64_t>(sum) + bound <= 2 * bound;
}
// An accumulated impulse of a joint row after a change: total + change
// held within +-max_joint_impulse (core/joint.h: more than any step gives
// at the envelope's bounds). Joints whose rows contradict each other (two
// hinges on one pair of bodies whose axes differ in one body's frame: the
// C API fuzz target's finding) otherwise trade ever larger impulses, pass
// after pass and step after step, until a sum wraps. Past the bound,
// `change` is held to twice it first, so the sum cannot wrap. Below it the
// result is total + change, bit for bit. The one-sided clamps
// (clamp_swing, clamp_limit, a rope's, a motor's) apply to the result,
// which they keep within the bound.
inline Fixed bounded_total(Fixed total, Fixed change) {
  int64_t sum = 0;
  if (sum_within_bound(total, change, sum)) return Fixed::from_raw(sum);
  constexpr Fixed reach = Fixed::from_raw(max_joint_impulse.raw() * 2);
  return clamp(total + clamp(change, -reach, reach), -max_joint_impulse, max_joint_impulse);
}

// total += change within the bound (bounded_total); returns the change made,
// which is what the row applies to the bodies (`change` itself below the
// bound, without the subtraction).
inline Fixed accumulate(Fixed& total, Fixed change) {
  int64_t sum = 0;
  if (sum_within_bound(total, change, sum)) {
    total = Fixed::from_raw(sum);
    return change;
  }
  const Fixed next = bounded_total(total, change);
  const Fixed made = next - total;
  total = next;
  return made;
}
inline Vec3 accumulate(Vec3& total, Vec3 change) {
  return {accumulate(total.x, change.x), accumulate(total.y, change.y), accumulate(total.z, change.z)};
}

// A slider block's impulses (two rows across its axis, three angular
// rows; core/joint_slider.cpp) added to the joint's: the linear rows' as a
// world vector, the angular rows' about the world axes, each component
// within the bound (bounded_total). The bodies take the lambdas as solved:
// the world vector's components do not map back to the two rows.
template <class Lambdas>
void add_block_impulses(const JointRow& row, const Lambdas& lambda, Vec3& point, Vec3& angular) {
  accumulate(point, row.slide[0].direction * lambda[0] + row.slide[1].direction * lambda[1]);
  accumulate(angular, Vec3{lambda[2], lambda[3], lambda[4]});
}

// pi (rad) rounded to Q32.32: the angle limits' range.
inline constexpr Fixed half_turn = Fixed::from_raw(0x3243F6A89);

// K = (1/m_a + 1/m_b) 1 - [r_a]x I_a^-1 [r_a]x - [r_b]x I_b^-1 [r_b]x: the
// relative velocity of the two anchors that a unit impulse gives, per axis
// (symmetric, positive definite while a body can move).
inline Mat33 point_block(const SolverBody& a, const SolverBody& b, Vec3 ra, Vec3 rb) {
  const Fixed m = a.inverse_mass + b.inverse_mass;
  Mat33 k{{Vec3{m, Fixed{}, Fixed{}}, Vec3{Fixed{}, m, Fixed{}}, Vec3{Fixed{}, Fixed{}, m}}};
  if (!immovable(a)) k = k - skew(ra) * (a.inverse_inertia * skew(ra));
  if (!immovable(b)) k = k - skew(rb) * (b.inverse_inertia * skew(rb));
  return k;
}

// An orthonormal pair normal to the unit vector n (a fixed choice).
inline void normal_pair(Vec3 n, Vec3& p1, Vec3& p2) {
  const Vec3 other = abs(n.x) < 0.57735_fx ? Vec3{Fixed::one(), {}, {}} : Vec3{{}, Fixed::one(), {}};
  p1 = normalize(cross(n, other));
  p2 = cross(n, p1);
}

// A rate that closes `error` (m or rad) by `factor` of it per step, at most
// max_speed.
inline Fixed recovery(Fixed error, Fixed factor, Fixed inverse_dt, Fixed max_speed) {
  const Fixed rate = error * factor * inverse_dt;
  return max(min(rate, max_speed), -max_speed);
}
inline Vec3 recovery(Vec3 error, Fixed factor, Fixed inverse_dt, Fixed max_speed) {
  const Vec3 rate = error * (factor * inverse_dt);
  const Fixed speed = length(rate);
  return speed > max_speed ? rate * (max_speed / speed) : rate;
}

// The anchors' relative velocity (b's minus a's) on one rate of the bodies.
inline Vec3 anchor_rate(const BodyRates& a, const BodyRates& b, Vec3 ra, Vec3 rb) {
  return (b.linear + cross(b.angular, rb)) - (a.linear + cross(a.angular, ra));
}

// Applies the impulse lambda at the anchors: -lambda to a, +lambda to b.
inline void apply_point(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b, Vec3 ra, Vec3 rb,
                        Vec3 lambda) {
  if (lambda == Vec3{}) return;
  a.linear -= lambda * sa.inverse_mass;
  a.angular -= sa.inverse_inertia * cross(ra, lambda);
  b.linear += lambda * sb.inverse_mass;
  b.angular += sb.inverse_inertia * cross(rb, lambda);
}

inline void apply_turn(BodyRates& a, BodyRates& b, const AngularPart& part, Fixed lambda) {
  if (lambda == Fixed{}) return;
  a.angular -= part.turn_a * lambda;
  b.angular += part.turn_b * lambda;
}

inline Fixed spin(const BodyRates& a, const BodyRates& b, const AngularPart& part) {
  return dot(b.angular - a.angular, part.axis);
}

inline BodyRates body_rates(const Body& body) { return {body.linear_velocity, body.angular_velocity}; }

// An angular row of a hinge paired with the point impulse that leaves the
// anchors' rate unchanged: g = the anchors' rate change per unit angular
// impulse, c = -K^-1 g, and the pair's effective mass 1 / (u . I_a^-1 u +
// u . I_b^-1 u - g . K^-1 g) (the Schur complement of the point block).
inline void pair_with_point(const JointRow& row, const AngularPart& part, Vec3& anchor, Fixed& mass) {
  const Vec3 g = cross(part.turn_b, row.rb) + cross(part.turn_a, row.ra);
  anchor = -(row.point_mass * g);
  const Fixed k = dot(part.axis, part.turn_a) + dot(part.axis, part.turn_b) + dot(anchor, g);
  mass = k > Fixed{} ? Fixed::one() / k : Fixed{};
}

// Applies an angular row's impulse with its paired point impulse.
inline void apply_paired(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b, const JointRow& row,
                         const AngularPart& part, Vec3 anchor, Fixed lambda, Vec3& point_impulse) {
  if (lambda == Fixed{}) return;
  apply_turn(a, b, part, lambda);
  const Vec3 point = accumulate(point_impulse, anchor * lambda);
  apply_point(sa, sb, a, b, row.ra, row.rb, point);
}

// One-sided rows: the swing's impulse >= 0, a limit's of its side's sign.
inline Fixed clamp_swing(Fixed total) { return max(total, Fixed{}); }
inline Fixed clamp_limit(const JointRow& row, Fixed total) {
  return row.limit_side > 0 ? max(total, Fixed{}) : min(total, Fixed{});
}

// The axis frames of a hinge or cone (and a slider): def.axis made unit,
// and a unit reference normal to it, in each body's frame (equal now).
void set_axis_frames(const JointDef& def, const Body& a, const Body& b, Joint& joint);

// The point block's rows (point, hinge and cone joints): K, K^-1, and the
// rates that close the anchors' gap (m, b's anchor from a's), with the
// step's own curvature in the velocity target.
void prepare_point_rows(const JointSetup& setup, JointRow& row, Vec3 gap);

// The side of a limit row (JointRow::limit_side, limit_target,
// limit_push_target) for a value (rad or m) moving at `rate` between
// lower_bound and upper_bound; resets Joint::limit_impulse held on the
// other side. Returns how far the value is past the bound (> 0: past).
Fixed prepare_limit_side(const JointSetup& setup, JointRow& row, Fixed value, Fixed rate, Fixed lower_bound,
                         Fixed upper_bound);

// Whether a limit row is engaged at the step's start (in the tree
// solve): it binds at the rates the step starts with (`rate` against
// limit_target), or is past, or held last step (`held`).
inline bool limit_engaged(const JointRow& row, Fixed past, Fixed rate, Fixed held) {
  return past > Fixed{} || (row.limit_side > 0 ? rate <= row.limit_target : rate >= row.limit_target) ||
         held != Fixed{};
}

// An angle's limit row about `axis` (a hinge's angle, a cone's twist; rad):
// one-sided, speculative, on the limit the angle is heading to, paired
// with the point impulse.
void prepare_angle_limit(const JointSetup& setup, JointRow& row, Fixed angle, Vec3 axis);

// Friction against b turning relative to a (Joint::friction_torque): about
// `axis` (a hinge's), or about every axis at once where axis is null.
void prepare_turn_friction(const JointSetup& setup, JointRow& row, const Vec3* axis);
void solve_turn_friction(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b, JointRow& row);

// A motor's settings checked (JointDef::motor_speed, motor_max; max_speed
// the world's largest, rad/s or m/s), and a type's without a motor:
// refused ("motor"), or fine.
Result<void> check_motor(Fixed speed, Fixed max, Fixed max_speed);
Result<void> check_no_motor(Fixed speed, Fixed max);

// JointRow::motor and motor_limit (motor_max dt), last step's impulse kept
// within it; without a motor the impulse is 0.
void prepare_motor_limit(const JointSetup& setup, JointRow& row);

// The point block's own row-by-row solve (where the tree does not take it).
inline void solve_point_rows(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b,
                             const JointRow& row, const Targets& target, Impulses& impulse) {
  const Vec3 lambda = accumulate(impulse.point, row.point_mass * (target.point - anchor_rate(a, b, row.ra, row.rb)));
  apply_point(sa, sb, a, b, row.ra, row.rb, lambda);
}

// The limit row of an angle (hinge, cone twist), row by row where the tree
// does not take it.
inline void solve_angle_limit(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b,
                              const JointRow& row, const Targets& target, Impulses& impulse, bool in_tree) {
  if (!target.limit_on || (in_tree && row.limit_in_tree)) return;
  const Fixed total =
      clamp_limit(row, bounded_total(impulse.limit, row.limit_mass * (target.limit - spin(a, b, row.limit))));
  apply_paired(sa, sb, a, b, row, row.limit, row.limit_anchor, total - impulse.limit, impulse.point);
  impulse.limit = total;
}

}  // namespace bitstep
