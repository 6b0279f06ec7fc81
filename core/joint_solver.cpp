#include "core/joint_solver.h"

#include <tuple>

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

Fixed spin(const BodyRates& a, const BodyRates& b, const AngularPart& part) {
  return dot(b.angular - a.angular, part.axis);
}

BodyRates body_rates(const Body& body) { return {body.linear_velocity, body.angular_velocity}; }

// Folds a hinge's two angular rows into its point block (JointRow::
// hinge_coupling): after make_twist built the rows and point_k holds K.
void fold_hinge_rows(JointRow& row) {
  for (int k = 0; k < 2; ++k) row.hinge_coupling[k] = cross(row.hinge[k].turn_b, row.rb) + cross(row.hinge[k].turn_a, row.ra);
  const auto entry = [&](int i, int j) { return dot(row.hinge[i].axis, row.hinge[j].turn_a + row.hinge[j].turn_b); };
  const Fixed a00 = entry(0, 0), a01 = entry(0, 1), a11 = entry(1, 1);
  const Fixed det = a00 * a11 - a01 * a01;
  if (det <= Fixed{}) return;  // an immovable pair: nothing to fold
  row.hinge_block[0] = a11 / det;
  row.hinge_block[1] = -a01 / det;
  row.hinge_block[2] = a00 / det;
  const Vec3 g0 = row.hinge_coupling[0], g1 = row.hinge_coupling[1];
  // sum g_i (A^-1)_ij g_j^T, row by row.
  const Vec3 c0 = g0 * row.hinge_block[0] + g1 * row.hinge_block[1];
  const Vec3 c1 = g0 * row.hinge_block[1] + g1 * row.hinge_block[2];
  Mat33 fold;
  for (int r = 0; r < 3; ++r) {
    const Fixed g0r = r == 0 ? g0.x : (r == 1 ? g0.y : g0.z);
    const Fixed g1r = r == 0 ? g1.x : (r == 1 ? g1.y : g1.z);
    fold.rows[static_cast<size_t>(r)] = c0 * g0r + c1 * g1r;
  }
  row.point_k = row.point_k - fold;
  row.point_mass = inverse_spd(row.point_k);
}

// A^-1 v for a hinge's 2x2 block.
void apply_block(const Fixed (&block)[3], const Fixed (&v)[2], Fixed (&out)[2]) {
  out[0] = block[0] * v[0] + block[1] * v[1];
  out[1] = block[1] * v[0] + block[2] * v[1];
}

// The point block's right-hand side for a row, b_p = target - J_p v, folded
// with a hinge's angular rows: b_p - sum g_k (A^-1 b_a)_k, b_a the rows'.
Vec3 point_rhs(const JointRow& row, const BodyRates& a, const BodyRates& b, Vec3 target, const Fixed (&hinge_target)[2],
               Fixed (&angular_rhs)[2]) {
  Vec3 rhs = target - anchor_rate(a, b, row.ra, row.rb);
  if (!row.folded) return rhs;
  for (int k = 0; k < 2; ++k) angular_rhs[k] = hinge_target[k] - spin(a, b, row.hinge[k]);
  Fixed scaled[2];
  apply_block(row.hinge_block, angular_rhs, scaled);
  return rhs - row.hinge_coupling[0] * scaled[0] - row.hinge_coupling[1] * scaled[1];
}

// Applies a point impulse, and a hinge's angular impulses that go with it:
// A^-1 (b_a - G lambda_p).
void apply_point_block(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b, const JointRow& row,
                       Vec3 lambda, const Fixed (&angular_rhs)[2], Vec3& point_impulse, Fixed (&hinge_impulse)[2]) {
  point_impulse += lambda;
  apply_point(sa, sb, a, b, row.ra, row.rb, lambda);
  if (!row.folded) return;
  const Fixed rest[2] = {angular_rhs[0] - dot(row.hinge_coupling[0], lambda),
                         angular_rhs[1] - dot(row.hinge_coupling[1], lambda)};
  Fixed turn[2];
  apply_block(row.hinge_block, rest, turn);
  for (int k = 0; k < 2; ++k) {
    hinge_impulse[k] += turn[k];
    apply_turn(a, b, row.hinge[k], turn[k]);
  }
}

// The rows of one joint on one rate of the bodies (velocity or push):
// the limit, the hinge's two angular rows, the rope, then the point block,
// so that the anchors' coincidence has the last word.
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

void solve_rows(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b, const JointRow& row,
                const Targets& target, Impulses impulse, bool point_block) {
  const JointType type = row.joint->type;
  if (type == JointType::cone && target.swing_on) {
    // The swing back toward the cone: an impulse >= 0 about s.
    const Fixed total = max(impulse.hinge[0] + row.hinge_mass[0] * (target.hinge[0] - spin(a, b, row.hinge[0])), Fixed{});
    apply_paired(sa, sb, a, b, row, row.hinge[0], row.hinge_anchor[0], total - impulse.hinge[0], impulse.point);
    impulse.hinge[0] = total;
  }
  if (type == JointType::hinge || type == JointType::cone) {
    for (int k = 0; k < 2 && type == JointType::hinge && !row.folded; ++k) {
      const Fixed lambda = row.hinge_mass[k] * (target.hinge[k] - spin(a, b, row.hinge[k]));
      impulse.hinge[k] += lambda;
      apply_paired(sa, sb, a, b, row, row.hinge[k], row.hinge_anchor[k], lambda, impulse.point);
    }
    if (target.limit_on) {
      Fixed total = impulse.limit + row.limit_mass * (target.limit - spin(a, b, row.limit));
      total = row.limit_side > 0 ? max(total, Fixed{}) : min(total, Fixed{});
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
  if (!point_block) return;
  Fixed angular_rhs[2] = {};
  const Vec3 lambda = row.point_mass * point_rhs(row, a, b, target.point, target.hinge, angular_rhs);
  apply_point_block(sa, sb, a, b, row, lambda, angular_rhs, impulse.point, impulse.hinge);
}

// Every point block at once on one rate of the bodies: lambda = K^-1 (target
// - J v), then each joint's impulse applied.
template <class Rate, class Target, class Impulse>
void solve_tree(std::vector<SolverBody>& bodies, std::vector<JointRow>& rows, JointTree& tree, Rate rate_of,
                Target target_of, Impulse impulse_of) {
  for (size_t p = 0; p < tree.row_of.size(); ++p) {
    JointRow& row = rows[tree.row_of[p]];
    Fixed hinge_target[2];
    const Vec3 point_target = target_of(row, hinge_target);
    tree.rhs[p] = point_rhs(row, rate_of(bodies[row.a]), rate_of(bodies[row.b]), point_target, hinge_target,
                            tree.angular_rhs[p].value);
  }
  solve_joint_tree(tree);
  for (size_t p = 0; p < tree.row_of.size(); ++p) {
    JointRow& row = rows[tree.row_of[p]];
    SolverBody& a = bodies[row.a];
    SolverBody& b = bodies[row.b];
    auto [point_impulse, hinge_impulse] = impulse_of(row);
    apply_point_block(a, b, rate_of(a), rate_of(b), row, tree.rhs[p], tree.angular_rhs[p].value, point_impulse, hinge_impulse);
  }
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
        // A cone twists about the mean of its two axes (b's own axis when
        // swung, a's at rest); a hinge's axes agree.
        const Vec3 twist_axis = joint.type == JointType::cone ? axis_b : axis_a;
        row.limit = make_twist(a, b, twist_axis);
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
      }
    }
    rows.push_back(row);
  }
  // Hinges alone on their movable bodies are folded (JointRow::folded).
  std::vector<uint32_t>& blocks_on = tree.queue;  // per slot: point blocks on the body
  blocks_on.assign(bodies.size(), 0);
  for (const JointRow& row : rows) {
    if (row.joint->type == JointType::max_distance) continue;
    for (const uint32_t body : {row.a, row.b}) {
      if (!immovable(solver_bodies[body])) ++blocks_on[body];
    }
  }
  for (JointRow& row : rows) {
    if (row.joint->type != JointType::hinge) continue;
    const bool alone = (immovable(solver_bodies[row.a]) || blocks_on[row.a] == 1) &&
                       (immovable(solver_bodies[row.b]) || blocks_on[row.b] == 1);
    if (alone) {
      row.folded = true;
      fold_hinge_rows(row);
    }
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

void solve_joints(std::vector<SolverBody>& bodies, std::vector<JointRow>& rows, JointTree& tree) {
  for (JointRow& row : rows) {
    SolverBody& a = bodies[row.a];
    SolverBody& b = bodies[row.b];
    Joint& joint = *row.joint;
    const Targets target{row.point_target, row.rope_target, {row.hinge_target[0], row.hinge_target[1]},
                         row.limit_target, row.rope_active, row.limit_side != 0, row.swing_active};
    solve_rows(a, b, a.velocity, b.velocity, row, target,
               {joint.point_impulse, joint.distance_impulse, joint.hinge_impulse, joint.limit_impulse}, !tree.exact);
  }
  if (!tree.exact) return;
  solve_tree(
      bodies, rows, tree, [](SolverBody& body) -> BodyRates& { return body.velocity; },
      [](const JointRow& row, Fixed (&hinge)[2]) {
        hinge[0] = row.hinge_target[0];
        hinge[1] = row.hinge_target[1];
        return row.point_target;
      },
      [](JointRow& row) { return std::tie(row.joint->point_impulse, row.joint->hinge_impulse); });
}

void push_joints(std::vector<SolverBody>& bodies, std::vector<JointRow>& rows, JointTree& tree) {
  for (JointRow& row : rows) {
    SolverBody& a = bodies[row.a];
    SolverBody& b = bodies[row.b];
    const Targets target{row.point_push_target, row.rope_push_target,
                         {row.hinge_push_target[0], row.hinge_push_target[1]}, row.limit_push_target,
                         row.rope_push_target != Fixed{}, row.limit_side != 0, row.swing_active};
    solve_rows(a, b, a.push, b.push, row, target,
               {row.point_push_impulse, row.rope_push_impulse, row.hinge_push_impulse, row.limit_push_impulse},
               !tree.exact);
  }
  if (!tree.exact) return;
  solve_tree(
      bodies, rows, tree, [](SolverBody& body) -> BodyRates& { return body.push; },
      [](const JointRow& row, Fixed (&hinge)[2]) {
        hinge[0] = row.hinge_push_target[0];
        hinge[1] = row.hinge_push_target[1];
        return row.point_push_target;
      },
      [](JointRow& row) { return std::tie(row.point_push_impulse, row.hinge_push_impulse); });
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
