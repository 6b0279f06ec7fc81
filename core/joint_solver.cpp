#include "core/joint_solver.h"

#include <algorithm>

namespace bitstep {

namespace {

// Below this the rope's direction is not defined (m); it is slack there.
constexpr Fixed rope_min_length = 0.0001_fx;

// [r]x, the matrix of r x (.).
Mat33 skew(Vec3 r) {
  return {{Vec3{Fixed{}, -r.z, r.y}, Vec3{r.z, Fixed{}, -r.x}, Vec3{-r.y, r.x, Fixed{}}}};
}

// K = (1/m_a + 1/m_b) 1 - [r_a]x I_a^-1 [r_a]x - [r_b]x I_b^-1 [r_b]x: the
// relative velocity of the two anchors that a unit impulse gives, per axis
// (symmetric, positive definite while a body can move).
Mat33 point_block(const SolverBody& a, const SolverBody& b, Vec3 ra, Vec3 rb) {
  const Fixed m = a.inverse_mass + b.inverse_mass;
  Mat33 k{{Vec3{m, Fixed{}, Fixed{}}, Vec3{Fixed{}, m, Fixed{}}, Vec3{Fixed{}, Fixed{}, m}}};
  if (!immovable(a)) k = k - skew(ra) * (a.inverse_inertia * skew(ra));
  if (!immovable(b)) k = k - skew(rb) * (b.inverse_inertia * skew(rb));
  return k;
}

// An orthonormal pair normal to the unit vector n (a fixed choice).
void normal_pair(Vec3 n, Vec3& p1, Vec3& p2) {
  const Vec3 other = abs(n.x) < 0.57735_fx ? Vec3{Fixed::one(), {}, {}} : Vec3{{}, Fixed::one(), {}};
  p1 = normalize(cross(n, other));
  p2 = cross(n, p1);
}

// A rate that closes `error` (m or rad) by `factor` of it per step, at most
// max_speed.
Fixed recovery(Fixed error, Fixed factor, Fixed inverse_dt, Fixed max_speed) {
  const Fixed rate = error * factor * inverse_dt;
  return max(min(rate, max_speed), -max_speed);
}
Vec3 recovery(Vec3 error, Fixed factor, Fixed inverse_dt, Fixed max_speed) {
  const Vec3 rate = error * (factor * inverse_dt);
  const Fixed speed = length(rate);
  return speed > max_speed ? rate * (max_speed / speed) : rate;
}

// The anchors' relative velocity (b's minus a's) on one rate of the bodies.
Vec3 anchor_rate(const BodyRates& a, const BodyRates& b, Vec3 ra, Vec3 rb) {
  return (b.linear + cross(b.angular, rb)) - (a.linear + cross(a.angular, ra));
}

// Applies the impulse lambda at the anchors: -lambda to a, +lambda to b.
void apply_point(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b, Vec3 ra, Vec3 rb,
                 Vec3 lambda) {
  if (lambda == Vec3{}) return;
  a.linear -= lambda * sa.inverse_mass;
  a.angular -= sa.inverse_inertia * cross(ra, lambda);
  b.linear += lambda * sb.inverse_mass;
  b.angular += sb.inverse_inertia * cross(rb, lambda);
}

void apply_turn(BodyRates& a, BodyRates& b, const AngularPart& part, Fixed lambda) {
  if (lambda == Fixed{}) return;
  a.angular -= part.turn_a * lambda;
  b.angular += part.turn_b * lambda;
}

// An angular row of a hinge paired with the point impulse that leaves the
// anchors' rate unchanged: g = the anchors' rate change per unit angular
// impulse, c = -K^-1 g, and the pair's effective mass 1 / (u . I_a^-1 u +
// u . I_b^-1 u - g . K^-1 g) (the Schur complement of the point block).
void pair_with_point(const JointRow& row, const AngularPart& part, Vec3& anchor, Fixed& mass) {
  const Vec3 g = cross(part.turn_b, row.rb) + cross(part.turn_a, row.ra);
  anchor = -(row.point_mass * g);
  const Fixed k = dot(part.axis, part.turn_a) + dot(part.axis, part.turn_b) + dot(anchor, g);
  mass = k > Fixed{} ? Fixed::one() / k : Fixed{};
}

// Applies an angular row's impulse with its paired point impulse.
void apply_paired(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b, const JointRow& row,
                  const AngularPart& part, Vec3 anchor, Fixed lambda, Vec3& point_impulse) {
  if (lambda == Fixed{}) return;
  apply_turn(a, b, part, lambda);
  const Vec3 point = anchor * lambda;
  point_impulse += point;
  apply_point(sa, sb, a, b, row.ra, row.rb, point);
}

// The row whose rate is a cone's twist rate (hinge_angle's): t = (a + b) /
// (1 + a . b) for the two bodies' axes a and b. The twist is b's reference
// against a's carried by the shortest turn S from a to b, so it turns with
// w . b (w = w_b - w_a) less the frame S's own turn about b, which is
// -(a x b) . (w x b) / (1 + a . b) = -(w . a - (a . b)(w . b)) / (1 + a . b);
// together (a + b) . w / (1 + a . b). b alone (the rate about b's axis)
// left out a swing's sweep around the cone: a shoulder swung 80 degrees and
// circling twisted 93 degrees past its limit while its row saw no twist.
// |t| = sqrt(2 / (1 + a . b)), 1.55 at the widest cone a ragdoll has (80
// degrees); near a swing of 180 degrees, where the twist is undefined, b.
Vec3 twist_rate_axis(Vec3 axis_a, Vec3 axis_b) {
  const Fixed one_plus_cosine = Fixed::one() + dot(axis_a, axis_b);
  if (one_plus_cosine < 0.01_fx) return axis_b;
  return (axis_a + axis_b) / one_plus_cosine;
}

Fixed spin(const BodyRates& a, const BodyRates& b, const AngularPart& part) {
  return dot(b.angular - a.angular, part.axis);
}

BodyRates body_rates(const Body& body) { return {body.linear_velocity, body.angular_velocity}; }

// The rows of one joint on one rate of the bodies (velocity or push).
struct Targets {
  Vec3 point;
  Fixed rope, hinge[2], limit;
  // A rope or limit row acts. In the position passes a rope acts only past
  // its length; a limit always: the push that closes the anchors' gap may
  // turn the arm, and may not turn it toward its nearer limit (it did, 3
  // degrees past under a 1,000 N m torque).
  bool rope_on, limit_on, swing_on;
};
struct Impulses {
  Vec3& point;
  Fixed& rope;
  Fixed (&hinge)[2];
  Fixed& limit;
};

Targets velocity_targets(const JointRow& row) {
  return {row.point_target,   row.rope_target,       {row.hinge_target[0], row.hinge_target[1]},
          row.limit_target,   row.rope_active,       row.limit_side != 0,
          row.swing_active};
}
Targets push_targets(const JointRow& row) {
  return {row.point_push_target,  row.rope_push_target,           {row.hinge_push_target[0], row.hinge_push_target[1]},
          row.limit_push_target,  row.rope_push_target != Fixed{}, row.limit_side != 0,
          row.swing_active};
}
Impulses velocity_impulses(JointRow& row) {
  Joint& joint = *row.joint;
  return {joint.point_impulse, joint.distance_impulse, joint.hinge_impulse, joint.limit_impulse};
}
Impulses push_impulses(JointRow& row) {
  return {row.point_push_impulse, row.rope_push_impulse, row.hinge_push_impulse, row.limit_push_impulse};
}

// One-sided rows: the swing's impulse >= 0, a limit's of its side's sign.
Fixed clamp_swing(Fixed total) { return max(total, Fixed{}); }
Fixed clamp_limit(const JointRow& row, Fixed total) { return row.limit_side > 0 ? max(total, Fixed{}) : min(total, Fixed{}); }

// The joint's friction on the velocities: the impulse that stops b
// turning relative to a, its accumulated total kept within friction_torque
// dt (a hinge's about its axis, the others' by the total's length).
void solve_friction(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b, JointRow& row) {
  const Fixed max_impulse = row.friction_max;
  if (row.joint->type == JointType::hinge) {  // the total about the axis in friction_impulse.x
    const Fixed total = max(min(row.friction_impulse.x - row.friction_hinge.mass * spin(a, b, row.friction_hinge), max_impulse),
                            -max_impulse);
    apply_turn(a, b, row.friction_hinge, total - row.friction_impulse.x);
    row.friction_impulse.x = total;
    return;
  }
  Vec3 total = row.friction_impulse - row.friction_mass * (b.angular - a.angular);
  const Fixed size = length(total);
  if (size > max_impulse) total = total * (max_impulse / size);
  const Vec3 change = total - row.friction_impulse;
  a.angular -= sa.inverse_inertia * change;
  b.angular += sb.inverse_inertia * change;
  row.friction_impulse = total;
}

// The rows of one joint solved one by one: the swing, the hinge's two
// angular rows, the limit, the rope, then the point block, so that the
// anchors' coincidence has the last word. With the tree solve (in_tree),
// only the rows it leaves out: a rope, and a swing or limit not engaged.
void solve_rows(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b, const JointRow& row,
                const Targets& target, Impulses impulse, bool in_tree) {
  const JointType type = row.joint->type;
  if (type == JointType::cone && target.swing_on && !(in_tree && row.swing_in_tree)) {
    // The swing back toward the cone: an impulse >= 0 about s.
    const Fixed total = clamp_swing(impulse.hinge[0] + row.hinge_mass[0] * (target.hinge[0] - spin(a, b, row.hinge[0])));
    apply_paired(sa, sb, a, b, row, row.hinge[0], row.hinge_anchor[0], total - impulse.hinge[0], impulse.point);
    impulse.hinge[0] = total;
  }
  if (type == JointType::hinge || type == JointType::cone) {
    for (int k = 0; k < 2 && type == JointType::hinge && !in_tree; ++k) {
      const Fixed lambda = row.hinge_mass[k] * (target.hinge[k] - spin(a, b, row.hinge[k]));
      impulse.hinge[k] += lambda;
      apply_paired(sa, sb, a, b, row, row.hinge[k], row.hinge_anchor[k], lambda, impulse.point);
    }
    if (target.limit_on && !(in_tree && row.limit_in_tree)) {
      const Fixed total = clamp_limit(row, impulse.limit + row.limit_mass * (target.limit - spin(a, b, row.limit)));
      apply_paired(sa, sb, a, b, row, row.limit, row.limit_anchor, total - impulse.limit, impulse.point);
      impulse.limit = total;
    }
  }
  if (type == JointType::max_distance) {
    if (!target.rope_on) return;
    // Pulling only: the impulse along the line from a to b is <= 0.
    const Fixed rate = relative_rate(a, b, row.rope);
    const Fixed total = min(impulse.rope + row.rope.mass * (target.rope - rate), Fixed{});
    apply_rate(a, b, row.rope, total - impulse.rope);
    impulse.rope = total;
    return;
  }
  if (in_tree) return;
  const Vec3 lambda = row.point_mass * (target.point - anchor_rate(a, b, row.ra, row.rb));
  impulse.point += lambda;
  apply_point(sa, sb, a, b, row.ra, row.rb, lambda);
}

// The tree node's rows in JointRow::tree_axes order: the point block's
// three, a hinge's two angular rows, the swing, the limit.
struct NodeLayout {
  int hinge = -1, swing = -1, limit = -1;  // the first row of each, -1: not in the node
};
NodeLayout layout_of(const JointRow& row) {
  NodeLayout layout;
  int next = 3;
  if (row.joint->type == JointType::hinge) {
    layout.hinge = next;
    next += 2;
  }
  if (row.swing_in_tree) layout.swing = next++;
  if (row.limit_in_tree) layout.limit = next++;
  return layout;
}

void set_tree_axes(JointRow& row);

// The tree solves an engaged swing or limit row as an equality. Where the
// solution pulls (the row's total impulse on the wrong side of zero: a blow
// this step took the limb away from the limit the step's start was heading
// for), the row leaves the tree for the rest of the step, where it is
// solved row by row and one-sided, and the tree is factorised again and
// solved again. Clamping the total alone (the tree's other rows computed
// with the pull in them) made ragdolls gain energy and fold limbs 180
// degrees; releasing rows within the factorisation (K^-1 e_j per row, one
// at a time) took the pull back and forth between two hips on one pelvis.
// Returns whether a row left.
constexpr Fixed pull_tolerance = Fixed::from_raw(1 << 12);  // N m s: rounding, left to solve_tree's clamp

template <class ImpulsesOf, class TakesPart>
bool release_pulling_rows(std::vector<SolverBody>& bodies, std::vector<JointRow>& rows, JointTree& tree,
                          ImpulsesOf impulses_of, TakesPart takes_part) {
  bool released = false;
  for (size_t p = 0; p < tree.row_of.size(); ++p) {
    JointRow& row = rows[tree.row_of[p]];
    if (!takes_part(row)) continue;
    const NodeLayout layout = layout_of(row);
    if (layout.swing < 0 && layout.limit < 0) continue;
    const Impulses impulse = impulses_of(row);
    bool leaves = false;
    if (layout.swing >= 0 && impulse.hinge[0] + tree.rhs[p].at[layout.swing] < -pull_tolerance) {
      row.swing_in_tree = false;
      leaves = true;
    }
    if (layout.limit >= 0) {
      const Fixed total = impulse.limit + tree.rhs[p].at[layout.limit];
      if (row.limit_side > 0 ? total < -pull_tolerance : total > pull_tolerance) {
        row.limit_in_tree = false;
        leaves = true;
      }
    }
    if (!leaves) continue;
    row.released = released = true;  // not engaged again this step
    set_tree_axes(row);
  }
  if (released) refactor_joint_tree(bodies, rows, tree);
  return released;
}

// Every joint's tree rows at once on one rate of the bodies: lambda = K^-1
// (target - J v), solved again while an engaged row pulls
// (release_pulling_rows), then each joint's impulses applied. A joint
// that takes no part in this pass (an island's extra pass: solve_joints)
// gets b = 0: its tree's lambda is exactly 0 (no tree couples to another),
// and its bodies keep their bits.
template <class Rate, class TargetsOf, class ImpulsesOf, class TakesPart>
void solve_tree(std::vector<SolverBody>& bodies, std::vector<JointRow>& rows, JointTree& tree, Rate rate_of,
                TargetsOf targets_of, ImpulsesOf impulses_of, TakesPart takes_part) {
  for (;;) {
    for (size_t p = 0; p < tree.row_of.size(); ++p) {
      const JointRow& row = rows[tree.row_of[p]];
      if (!takes_part(row)) {
        tree.rhs[p] = Column{};
        continue;
      }
      const BodyRates& a = rate_of(bodies[row.a]);
      const BodyRates& b = rate_of(bodies[row.b]);
      const Targets target = targets_of(row);
      const NodeLayout layout = layout_of(row);
      Column& rhs = tree.rhs[p];
      const Vec3 point = target.point - anchor_rate(a, b, row.ra, row.rb);
      rhs.at[0] = point.x;
      rhs.at[1] = point.y;
      rhs.at[2] = point.z;
      if (layout.hinge >= 0) {
        for (int k = 0; k < 2; ++k) rhs.at[layout.hinge + k] = target.hinge[k] - spin(a, b, row.hinge[k]);
      }
      if (layout.swing >= 0) rhs.at[layout.swing] = target.hinge[0] - spin(a, b, row.hinge[0]);
      if (layout.limit >= 0) rhs.at[layout.limit] = target.limit - spin(a, b, row.limit);
    }
    solve_joint_tree(tree, tree.rhs);
    if (!release_pulling_rows(bodies, rows, tree, impulses_of, takes_part)) break;
  }
  for (size_t p = 0; p < tree.row_of.size(); ++p) {
    JointRow& row = rows[tree.row_of[p]];
    if (!takes_part(row)) continue;
    SolverBody& sa = bodies[row.a];
    SolverBody& sb = bodies[row.b];
    BodyRates& a = rate_of(sa);
    BodyRates& b = rate_of(sb);
    Impulses impulse = impulses_of(row);
    const NodeLayout layout = layout_of(row);
    const Column& lambda = tree.rhs[p];
    const Vec3 point{lambda.at[0], lambda.at[1], lambda.at[2]};
    impulse.point += point;
    apply_point(sa, sb, a, b, row.ra, row.rb, point);
    if (layout.hinge >= 0) {
      for (int k = 0; k < 2; ++k) {
        impulse.hinge[k] += lambda.at[layout.hinge + k];
        apply_turn(a, b, row.hinge[k], lambda.at[layout.hinge + k]);
      }
    }
    // What rounding left on the wrong side of zero, taken back row by row.
    if (layout.swing >= 0) {
      const Fixed total = clamp_swing(impulse.hinge[0] + lambda.at[layout.swing]);
      apply_turn(a, b, row.hinge[0], total - impulse.hinge[0]);
      impulse.hinge[0] = total;
    }
    if (layout.limit >= 0) {
      const Fixed total = clamp_limit(row, impulse.limit + lambda.at[layout.limit]);
      apply_turn(a, b, row.limit, total - impulse.limit);
      impulse.limit = total;
    }
  }
}

// One pass over the joints on one rate: the rows the tree leaves out one
// by one, then the tree (or, where the joints close a loop, every row one
// by one).
template <class Rate, class TargetsOf, class ImpulsesOf, class TakesPart>
void solve_pass(std::vector<SolverBody>& bodies, std::vector<JointRow>& rows, JointTree& tree, Rate rate_of,
                TargetsOf targets_of, ImpulsesOf impulses_of, TakesPart takes_part) {
  bool promoted = false;
  for (JointRow& row : rows) {
    if (!takes_part(row)) continue;
    SolverBody& a = bodies[row.a];
    SolverBody& b = bodies[row.b];
    const Impulses impulse = impulses_of(row);
    solve_rows(a, b, rate_of(a), rate_of(b), row, targets_of(row), impulse, tree.exact);
    // A swing or limit that the step's start did not engage and that now
    // binds (a blow this step drove the limb into it) joins the tree.
    if (!tree.exact || row.released) continue;
    const bool swing_joins = row.swing_active && !row.swing_in_tree && impulse.hinge[0] != Fixed{};
    const bool limit_joins = row.limit_side != 0 && !row.limit_in_tree && impulse.limit != Fixed{};
    if (!swing_joins && !limit_joins) continue;
    row.swing_in_tree = row.swing_in_tree || swing_joins;
    row.limit_in_tree = row.limit_in_tree || limit_joins;
    set_tree_axes(row);
    promoted = true;
  }
  if (!tree.exact) return;
  if (promoted) refactor_joint_tree(bodies, rows, tree);
  solve_tree(bodies, rows, tree, rate_of, targets_of, impulses_of, takes_part);
}

BodyRates& velocity_of(SolverBody& body) { return body.velocity; }
BodyRates& push_of(SolverBody& body) { return body.push; }

// The joint's rows in the tree solve (JointRow::tree_axes), their angular
// parts on each body.
void set_tree_axes(JointRow& row) {
  const Vec3 unit[3] = {{Fixed::one(), {}, {}}, {{}, Fixed::one(), {}}, {{}, {}, Fixed::one()}};
  // The point block: e . (v_b + w_b x r_b - v_a - w_a x r_a) per axis e.
  for (int k = 0; k < 3; ++k) row.tree_axes[k] = {-cross(row.ra, unit[k]), cross(row.rb, unit[k])};
  const auto angular = [](const AngularPart& part) { return TreeAxis{-part.axis, part.axis}; };
  const NodeLayout layout = layout_of(row);
  if (layout.hinge >= 0) {
    for (int k = 0; k < 2; ++k) row.tree_axes[layout.hinge + k] = angular(row.hinge[k]);
  }
  if (layout.swing >= 0) row.tree_axes[layout.swing] = angular(row.hinge[0]);
  if (layout.limit >= 0) row.tree_axes[layout.limit] = angular(row.limit);
  row.tree_size = static_cast<uint8_t>(3 + (layout.hinge >= 0 ? 2 : 0) + (layout.swing >= 0 ? 1 : 0) +
                                       (layout.limit >= 0 ? 1 : 0));
}

}  // namespace

Fixed hinge_angle(const Joint& joint, const Body& a, const Body& b) {
  const Vec3 axis = rotate(a.pose.orientation, joint.local_axis_a);
  Vec3 ref_a = rotate(a.pose.orientation, joint.local_reference_a);
  const Vec3 ref_b = rotate(b.pose.orientation, joint.local_reference_b);
  if (joint.type != JointType::cone) return atan2(dot(cross(ref_a, ref_b), axis), dot(ref_a, ref_b));
  // A cone's twist: a's reference carried by the swing (the shortest turn
  // taking a's axis onto b's, about k = axis_a x axis_b / sin, by Rodrigues'
  // formula), then its angle to b's reference about b's axis. Measured
  // about a's axis instead, a 60 degree swing read as 80 degrees of twist.
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

void prepare_joint_rows(const Settings& settings, const std::vector<Body>& bodies, std::vector<Joint>& joints,
                        const std::vector<SolverBody>& solver_bodies, std::vector<JointRow>& rows, JointTree& tree) {
  rows.clear();
  const Fixed inverse_dt = Fixed::one() / settings.dt;
  const Fixed factor = settings.baumgarte ? settings.baumgarte_factor : settings.split_impulse_factor;
  const Fixed max_speed = settings.max_push_out_speed;
  for (Joint& joint : joints) {
    if (!joint.alive) continue;
    const Body& body_a = bodies[joint.body_a];
    const Body& body_b = bodies[joint.body_b];
    if (!is_awake_dynamic(body_a) && !is_awake_dynamic(body_b)) continue;
    const SolverBody& a = solver_bodies[joint.body_a];
    const SolverBody& b = solver_bodies[joint.body_b];
    JointRow row;
    row.a = joint.body_a;
    row.b = joint.body_b;
    row.joint = &joint;
    row.ra = rotate(body_a.pose.orientation, joint.local_anchor_a);
    row.rb = rotate(body_b.pose.orientation, joint.local_anchor_b);
    const Vec3 gap = (body_b.pose.position + row.rb) - (body_a.pose.position + row.ra);  // b's anchor from a's
    if (joint.type == JointType::max_distance) {
      const Fixed distance = length(gap);
      row.rope_active = distance > rope_min_length;
      if (row.rope_active) {
        row.rope = make_jacobian(a, b, row.ra, row.rb, gap / distance);
        // Slack: the anchors may separate by what is left of the length
        // this step. Taut beyond it: they stop separating, and the excess
        // is pushed out (or, Baumgarte, pulled in by the velocity).
        const Fixed excess = distance - joint.length;
        if (excess <= Fixed{}) {
          row.rope_target = -excess * inverse_dt;
        } else if (settings.baumgarte) {
          row.rope_target = -recovery(excess, factor, inverse_dt, max_speed);
        } else {
          row.rope_push_target = -recovery(excess, factor, inverse_dt, max_speed);
        }
      } else {
        joint.distance_impulse = Fixed{};
      }
    } else {
      row.point_k = point_block(a, b, row.ra, row.rb);
      row.point_mass = inverse_spd(row.point_k);
      const Vec3 closing = -recovery(gap, factor, inverse_dt, max_speed);
      (settings.baumgarte ? row.point_target : row.point_push_target) = closing;
      // The constraint held at the step's end pose, not only in the
      // direction it has now: over the step an arm r turning at w moves
      // its anchor by w x (w x r) dt^2 / 2 beyond (w x r) dt (the anchor's
      // centripetal path), so the anchors' rate is to undo that. Without it
      // each step's projection onto the constraint as it stands took away
      // about (v dt / L)^2 of the kinetic energy: a chain swinging from 45
      // degrees lost 15% of its energy in 10 s; with it, 1.3%.
      const Vec3 curve_a = cross(body_a.angular_velocity, cross(body_a.angular_velocity, row.ra));
      const Vec3 curve_b = cross(body_b.angular_velocity, cross(body_b.angular_velocity, row.rb));
      row.point_target -= (curve_b - curve_a) * (settings.dt / 2.0_fx);
    }
    if (joint.type == JointType::cone) {
      // The swing: b's axis turned back toward a's about s = axis_b x axis_a
      // (normalised), one-sided, speculative like the limits; undefined
      // (and far inside any cone wider than 0.06 degrees) below 1e-3 rad.
      const Vec3 axis_a = rotate(body_a.pose.orientation, joint.local_axis_a);
      const Vec3 axis_b = rotate(body_b.pose.orientation, joint.local_axis_b);
      const Vec3 s = cross(axis_b, axis_a);
      const Fixed sine = length(s);
      row.swing_active = sine > 0.001_fx;
      if (row.swing_active) {
        const Fixed swing = atan2(sine, dot(axis_a, axis_b));
        row.hinge[0] = make_twist(a, b, s / sine);
        pair_with_point(row, row.hinge[0], row.hinge_anchor[0], row.hinge_mass[0]);
        const Fixed past = swing - joint.swing_angle;
        if (past <= Fixed{}) {
          row.hinge_target[0] = past * inverse_dt;
        } else if (settings.baumgarte) {
          row.hinge_target[0] = recovery(past, factor, inverse_dt, max_speed);
        } else {
          row.hinge_push_target[0] = recovery(past, factor, inverse_dt, max_speed);
        }
        // In the tree solve (engaged) where it binds at the rates the step
        // starts with, or is past, or held last step; else row by row.
        const Fixed rate = spin(body_rates(body_a), body_rates(body_b), row.hinge[0]);
        row.swing_in_tree = past > Fixed{} || rate <= row.hinge_target[0] || joint.hinge_impulse[0] > Fixed{};
      } else {
        joint.hinge_impulse[0] = Fixed{};
      }
    }
    if (joint.type == JointType::hinge || joint.type == JointType::cone) {
      const Vec3 axis_a = rotate(body_a.pose.orientation, joint.local_axis_a);
      const Vec3 axis_b = rotate(body_b.pose.orientation, joint.local_axis_b);
      Vec3 p[2];
      normal_pair(axis_a, p[0], p[1]);
      // b's axis is turned onto a's by a rotation about axis_b x axis_a
      // (its length the sine of the angle between them).
      const Vec3 misalignment = cross(axis_b, axis_a);
      for (int k = 0; k < 2 && joint.type == JointType::hinge; ++k) {
        row.hinge[k] = make_twist(a, b, p[k]);
        const Fixed rate = recovery(dot(misalignment, p[k]), factor, inverse_dt, max_speed);
        (settings.baumgarte ? row.hinge_target[k] : row.hinge_push_target[k]) = rate;
      }
      if (joint.type == JointType::hinge) {
        for (int k = 0; k < 2; ++k) pair_with_point(row, row.hinge[k], row.hinge_anchor[k], row.hinge_mass[k]);
      }
      if (joint.limited) {
        const Fixed angle = hinge_angle(joint, body_a, body_b);
        row.limit = make_twist(a, b, joint.type == JointType::cone ? twist_rate_axis(axis_a, axis_b) : axis_a);
        pair_with_point(row, row.limit, row.limit_anchor, row.limit_mass);
        // The limit nearer to where the angle is heading (its rate at the
        // velocities the step starts the solve with: a fast turn toward the
        // far limit went past it while the near one was watched), as a
        // speculative row: the angle may approach it by what is left this
        // step; past it, it stops, and the excess is pushed back.
        const Fixed heading = angle + spin(body_rates(body_a), body_rates(body_b), row.limit) * settings.dt;
        const bool lower = heading - joint.lower_angle < joint.upper_angle - heading;
        row.limit_side = lower ? 1 : -1;
        const Fixed bound = lower ? joint.lower_angle : joint.upper_angle;
        const Fixed past = lower ? bound - angle : angle - bound;  // > 0: beyond the limit
        if (past <= Fixed{}) {
          row.limit_target = (bound - angle) * inverse_dt;
        } else if (settings.baumgarte) {
          row.limit_target = recovery(bound - angle, factor, inverse_dt, max_speed);
        } else {
          row.limit_push_target = recovery(bound - angle, factor, inverse_dt, max_speed);
        }
        // Last step's impulse held the other limit: it does not carry over.
        if ((lower && joint.limit_impulse < Fixed{}) || (!lower && joint.limit_impulse > Fixed{})) {
          joint.limit_impulse = Fixed{};
        }
        // Engaged (in the tree solve) as the swing is.
        const Fixed rate = spin(body_rates(body_a), body_rates(body_b), row.limit);
        row.limit_in_tree = past > Fixed{} || (lower ? rate <= row.limit_target : rate >= row.limit_target) ||
                            joint.limit_impulse != Fixed{};
      }
    }
    if (joint.friction_torque > Fixed{} && joint.type != JointType::max_distance) {
      row.friction = true;
      row.friction_max = joint.friction_torque * settings.dt;
      if (joint.type == JointType::hinge) {
        row.friction_hinge = make_twist(a, b, rotate(body_a.pose.orientation, joint.local_axis_a));
      } else {
        row.friction_mass = inverse_spd(a.inverse_inertia + b.inverse_inertia);
      }
    }
    rows.push_back(row);
  }
  for (JointRow& row : rows) {
    if (row.joint->type != JointType::max_distance) set_tree_axes(row);
  }
  factor_joint_tree(solver_bodies, rows, tree);
}

void warm_start_joints(std::vector<SolverBody>& bodies, const std::vector<JointRow>& rows) {
  for (const JointRow& row : rows) {
    SolverBody& a = bodies[row.a];
    SolverBody& b = bodies[row.b];
    const Joint& joint = *row.joint;
    if (joint.type == JointType::max_distance) {
      if (row.rope_active) apply_rate(a.velocity, b.velocity, row.rope, joint.distance_impulse);
      continue;
    }
    apply_point(a, b, a.velocity, b.velocity, row.ra, row.rb, joint.point_impulse);
    if (joint.type == JointType::hinge) {
      apply_turn(a.velocity, b.velocity, row.hinge[0], joint.hinge_impulse[0]);
      apply_turn(a.velocity, b.velocity, row.hinge[1], joint.hinge_impulse[1]);
    }
    if (joint.type == JointType::cone && row.swing_active) {
      apply_turn(a.velocity, b.velocity, row.hinge[0], joint.hinge_impulse[0]);
    }
    if (row.limit_side != 0) apply_turn(a.velocity, b.velocity, row.limit, joint.limit_impulse);
  }
}

void solve_joints(std::vector<SolverBody>& bodies, std::vector<JointRow>& rows, JointTree& tree, int extra_pass) {
  const auto takes_part = [extra_pass](const JointRow& row) {
    return extra_pass < 0 || row.extra_velocity_passes > extra_pass;
  };
  for (JointRow& row : rows) {
    if (!row.friction || !takes_part(row)) continue;
    SolverBody& a = bodies[row.a];
    SolverBody& b = bodies[row.b];
    solve_friction(a, b, a.velocity, b.velocity, row);
  }
  solve_pass(bodies, rows, tree, velocity_of, velocity_targets, velocity_impulses, takes_part);
}

void push_joints(std::vector<SolverBody>& bodies, std::vector<JointRow>& rows, JointTree& tree, int extra_pass) {
  const auto takes_part = [extra_pass](const JointRow& row) {
    return extra_pass < 0 || row.extra_position_passes > extra_pass;
  };
  solve_pass(bodies, rows, tree, push_of, push_targets, push_impulses, takes_part);
}

bool joints_to_push(const std::vector<JointRow>& rows) {
  for (const JointRow& row : rows) {
    if (row.point_push_target != Vec3{} || row.rope_push_target != Fixed{} || row.hinge_push_target[0] != Fixed{} ||
        row.hinge_push_target[1] != Fixed{} || row.limit_push_target != Fixed{}) {
      return true;
    }
  }
  return false;
}

bool over_break_impulse(const Joint& joint) {
  if (joint.break_impulse == Fixed{}) return false;
  if (joint.type == JointType::max_distance) return -joint.distance_impulse > joint.break_impulse;
  return length(joint.point_impulse) > joint.break_impulse;
}

}  // namespace bitstep
