#include "core/joint_solver.h"

#include <algorithm>

#include "core/joint_parts.h"
#include "core/mass.h"
#include "core/joint_types.h"

namespace bitstep {

namespace {

Targets velocity_targets(const JointRow& row) {
  return {row.point_target,
          row.rope_target,
          {row.hinge_target[0], row.hinge_target[1]},
          row.limit_target,
          row.rope_active,
          row.limit_side != 0,
          row.swing_active,
          {row.slide_target[0], row.slide_target[1], row.slide_target[2], row.slide_target[3], row.slide_target[4]},
          row.joint->motor_speed,
          row.motor};
}
Targets push_targets(const JointRow& row) {
  return {row.point_push_target,
          row.rope_push_target,
          {row.hinge_push_target[0], row.hinge_push_target[1]},
          row.limit_push_target,
          row.rope_push_target != Fixed{},
          row.limit_side != 0,
          row.swing_active,
          {row.slide_push_target[0], row.slide_push_target[1], row.slide_push_target[2], row.slide_push_target[3],
           row.slide_push_target[4]},
          Fixed{},
          false};
}
Impulses velocity_impulses(JointRow& row) {
  Joint& joint = *row.joint;
  return {joint.point_impulse, joint.distance_impulse, joint.hinge_impulse, joint.limit_impulse,
          joint.angular_impulse, joint.motor_impulse};
}
Impulses push_impulses(JointRow& row) {
  return {row.point_push_impulse, row.rope_push_impulse,   row.hinge_push_impulse,
          row.limit_push_impulse, row.angular_push_impulse, row.motor_push_impulse};
}

// The joint's rows the tree leaves out (all of them where there is no
// tree), row by row, as its type solves them (core/joint_types.h).
void solve_rows(const SolverBody& sa, const SolverBody& sb, BodyRates& a, BodyRates& b, JointRow& row,
                const Targets& target, Impulses impulse, bool in_tree) {
  with_joint_type(row.joint->type,
                  [&](auto type) { decltype(type)::solve_rows(sa, sb, a, b, row, target, impulse, in_tree); });
}

// The tree node's rows in JointRow::tree_axes order: the point block's
// three, a hinge's two angular rows, the swing, the limit; or a slider's
// five, then its limit.
struct NodeLayout {
  int hinge = -1, swing = -1, limit = -1;  // the first row of each, -1: not in the node
  bool slide = false;                      // rows 0..4: a slider's block (no point block)
};
NodeLayout layout_of(const JointRow& row) {
  NodeLayout layout;
  if (row.slide_rows_in_tree) {
    layout.slide = true;
    if (row.limit_in_tree) layout.limit = 5;
    return layout;
  }
  int next = 3;
  if (row.hinge_rows_in_tree) {
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
    if (layout.swing >= 0 && bounded_total(impulse.hinge[0], tree.rhs[p].at[layout.swing]) < -pull_tolerance) {
      row.swing_in_tree = false;
      leaves = true;
    }
    if (layout.limit >= 0) {
      const Fixed total = bounded_total(impulse.limit, tree.rhs[p].at[layout.limit]);
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

// A slider's node solved: its block's impulses (across the axis: the
// joint's point impulse as a world vector; angular: about the world axes)
// and its limit's, what rounding left on the wrong side of zero taken back.
void apply_slide_node(BodyRates& a, BodyRates& b, const JointRow& row, const Column& lambda, const NodeLayout& layout,
                      Impulses& impulse) {
  for (int k = 0; k < 5; ++k) apply_rate(a, b, row.slide[k], lambda.at[k]);
  add_block_impulses(row, lambda.at, impulse.point, impulse.angular);
  if (layout.limit >= 0) {
    const Fixed total = clamp_limit(row, bounded_total(impulse.limit, lambda.at[layout.limit]));
    apply_rate(a, b, row.slide_axis, total - impulse.limit);
    impulse.limit = total;
  }
}

// A tree island's residual below which its tree is held for the rest of
// the solve on that rate (tree_islands.h): 2^-20 m/s or rad/s, a drift of
// about 1e-8 m a step at 60 Hz. A healthy tree's is a few ulp after one
// solve; a 10 g link holding a 100 t ball needs a few passes to reach it.
constexpr Fixed tree_residual_tolerance = Fixed::from_raw(int64_t{1} << 12);

// Each tree island's tree whose residual (tree.rhs, per row) is within
// tree_residual_tolerance is held: marked `held`, it takes part in no
// later pass, nor in the rest of this one. Uses tree.residual per
// position.
void hold_converged_trees(std::vector<JointRow>& rows, JointTree& tree, bool JointRow::*held) {
  const size_t n = tree.row_of.size();
  std::vector<Fixed>& largest = tree.residual;
  largest.assign(n, Fixed{});
  for (size_t p = 0; p < n; ++p) {
    Fixed& most = largest[tree.component[p]];
    for (int k = 0; k < tree.size[p]; ++k) most = max(most, abs(tree.rhs[p].at[k]));
  }
  for (size_t p = 0; p < n; ++p) {
    JointRow& row = rows[tree.row_of[p]];
    if (row.tree_island && largest[tree.component[p]] <= tree_residual_tolerance) row.*held = true;
  }
}

// Every joint's tree rows at once on one rate of the bodies: lambda = K^-1
// (target - J v), solved again while an engaged row pulls
// (release_pulling_rows), then each joint's impulses applied. Returns
// whether a row left the tree. A joint that takes no part in this pass
// (an island's extra pass: solve_joints; a held tree) gets b = 0: its
// tree's lambda is exactly 0 (no tree couples to another), and its bodies
// keep their bits.
template <class Rate, class TargetsOf, class ImpulsesOf, class TakesPart>
bool solve_tree(std::vector<SolverBody>& bodies, std::vector<JointRow>& rows, JointTree& tree, Rate rate_of,
                TargetsOf targets_of, ImpulsesOf impulses_of, TakesPart takes_part, bool JointRow::*held) {
  bool released = false;
  for (bool first = true;; first = false) {
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
      if (layout.slide) {
        for (int k = 0; k < 5; ++k) rhs.at[k] = target.slide[k] - relative_rate(a, b, row.slide[k]);
        if (layout.limit >= 0) rhs.at[layout.limit] = target.limit - relative_rate(a, b, row.slide_axis);
        continue;
      }
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
    if (first) {
      // Held rows now take no part; with none left, nothing is solved.
      hold_converged_trees(rows, tree, held);
      const auto left = [&](uint32_t r) { return takes_part(rows[r]); };
      if (std::none_of(tree.row_of.begin(), tree.row_of.end(), left)) return false;
      for (size_t p = 0; p < tree.row_of.size(); ++p) {
        if (!takes_part(rows[tree.row_of[p]])) tree.rhs[p] = Column{};
      }
    }
    solve_joint_tree(tree, tree.rhs);
    if (!release_pulling_rows(bodies, rows, tree, impulses_of, takes_part)) break;
    released = true;
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
    if (layout.slide) {
      apply_slide_node(a, b, row, lambda, layout, impulse);
      continue;
    }
    const Vec3 point = accumulate(impulse.point, Vec3{lambda.at[0], lambda.at[1], lambda.at[2]});
    apply_point(sa, sb, a, b, row.ra, row.rb, point);
    if (layout.hinge >= 0) {
      for (int k = 0; k < 2; ++k)
        apply_turn(a, b, row.hinge[k], accumulate(impulse.hinge[k], lambda.at[layout.hinge + k]));
    }
    // What rounding left on the wrong side of zero, taken back row by row.
    if (layout.swing >= 0) {
      const Fixed total = clamp_swing(bounded_total(impulse.hinge[0], lambda.at[layout.swing]));
      apply_turn(a, b, row.hinge[0], total - impulse.hinge[0]);
      impulse.hinge[0] = total;
    }
    if (layout.limit >= 0) {
      const Fixed total = clamp_limit(row, bounded_total(impulse.limit, lambda.at[layout.limit]));
      apply_turn(a, b, row.limit, total - impulse.limit);
      impulse.limit = total;
    }
  }
  return released;
}

// A row that left the tree in a tree island (tree_islands.h) is solved
// row by row from here on: its tree takes every pass. (A row that joins
// the tree was not tree_alone, so its island was never a tree island.)
void end_tree_island(std::vector<JointRow>& rows, const JointTree& tree) {
  for (size_t p = 0; p < tree.row_of.size(); ++p) {
    const JointRow& left = rows[tree.row_of[p]];
    if (!left.released || !left.tree_island) continue;
    for (size_t q = 0; q < tree.row_of.size(); ++q) {
      if (tree.component[q] == tree.component[p]) rows[tree.row_of[q]].tree_island = false;
    }
  }
}

// Whether a swing or limit row that binds in a pass joins the tree for the
// rest of the step (Promote::binding), or stays a one-sided row of its own.
// The velocity passes promote: a blow this step drives a limb into its
// limit, and the tree must hold it against the limb's other joints. The
// position passes do not: a limit that only the pushes reach is a small
// correction, which its own row settles, and each row joining costs a new
// factorisation of its whole tree (several a step in a tumbling ragdoll,
// more than all of its other joint work).
enum class Promote : bool { none, binding };

// One pass over the joints on one rate: the rows the tree leaves out one
// by one, then the tree (or, where the joints close a loop, every row one
// by one).
template <class Rate, class TargetsOf, class ImpulsesOf, class TakesPart>
void solve_pass(std::vector<SolverBody>& bodies, std::vector<JointRow>& rows, JointTree& tree, Rate rate_of,
                TargetsOf targets_of, ImpulsesOf impulses_of, TakesPart takes_part, Promote promote,
                bool JointRow::*held) {
  // Nothing takes part: the tree's lambda would be exactly 0 (solve_tree).
  if (std::none_of(rows.begin(), rows.end(), takes_part)) return;
  bool promoted = false;
  for (JointRow& row : rows) {
    if (!takes_part(row)) continue;
    SolverBody& a = bodies[row.a];
    SolverBody& b = bodies[row.b];
    const Impulses impulse = impulses_of(row);
    solve_rows(a, b, rate_of(a), rate_of(b), row, targets_of(row), impulse, tree.exact);
    // A swing or limit that the step's start did not engage and that now
    // binds (a blow this step drove the limb into it) joins the tree.
    if (!tree.exact || row.released || promote == Promote::none) continue;
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
  if (solve_tree(bodies, rows, tree, rate_of, targets_of, impulses_of, takes_part, held)) end_tree_island(rows, tree);
}

BodyRates& velocity_of(SolverBody& body) { return body.velocity; }
BodyRates& push_of(SolverBody& body) { return body.push; }

// The joint's rows in the tree solve (JointRow::tree_axes), their angular
// parts on each body.
void set_tree_axes(JointRow& row) {
  const NodeLayout layout = layout_of(row);
  if (layout.slide) {
    // J v = d . (v_b - v_a) + arm_b . w_b - arm_a . w_a (solver_rows.h).
    const auto axis_of = [](const Jacobian& j) { return TreeAxis{-j.arm_a, j.arm_b, j.direction}; };
    for (int k = 0; k < 5; ++k) row.tree_axes[k] = axis_of(row.slide[k]);
    if (layout.limit >= 0) row.tree_axes[layout.limit] = axis_of(row.slide_axis);
    row.tree_size = static_cast<uint8_t>(layout.limit >= 0 ? 6 : 5);
    return;
  }
  const Vec3 unit[3] = {{Fixed::one(), {}, {}}, {{}, Fixed::one(), {}}, {{}, {}, Fixed::one()}};
  // The point block: e . (v_b + w_b x r_b - v_a - w_a x r_a) per axis e.
  for (int k = 0; k < 3; ++k) row.tree_axes[k] = {-cross(row.ra, unit[k]), cross(row.rb, unit[k]), unit[k]};
  const auto angular = [](const AngularPart& part) { return TreeAxis{-part.axis, part.axis, Vec3{}}; };
  if (layout.hinge >= 0) {
    for (int k = 0; k < 2; ++k) row.tree_axes[layout.hinge + k] = angular(row.hinge[k]);
  }
  if (layout.swing >= 0) row.tree_axes[layout.swing] = angular(row.hinge[0]);
  if (layout.limit >= 0) row.tree_axes[layout.limit] = angular(row.limit);
  row.tree_size = static_cast<uint8_t>(3 + (layout.hinge >= 0 ? 2 : 0) + (layout.swing >= 0 ? 1 : 0) +
                                       (layout.limit >= 0 ? 1 : 0));
}

}  // namespace

void build_joint_rows(const Settings& settings, const std::vector<Body>& bodies, std::vector<Joint>& joints,
                      const std::vector<SolverBody>& solver_bodies, std::vector<JointRow>& rows) {
  rows.clear();
  const Fixed inverse_dt = Fixed::one() / settings.dt;
  const Fixed factor = settings.baumgarte ? settings.baumgarte_factor : settings.split_impulse_factor;
  const Fixed max_speed = settings.max_push_out_speed;
  for (Joint& joint : joints) {
    if (!joint.alive) continue;
    const Body& body_a = bodies[joint.body_a];
    const Body& body_b = bodies[joint.body_b];
    if (!is_awake_dynamic(body_a) && !is_awake_dynamic(body_b)) continue;
    const JointSetup setup{settings, inverse_dt, factor, max_speed, body_a, body_b,
                           solver_bodies[joint.body_a], solver_bodies[joint.body_b], joint};
    JointRow row;
    row.a = joint.body_a;
    row.b = joint.body_b;
    row.joint = &joint;
    row.ra = rotate(body_a.pose.orientation, joint.local_anchor_a);
    row.rb = rotate(body_b.pose.orientation, joint.local_anchor_b);
    with_joint_type(joint.type, [&](auto type) { decltype(type)::prepare(setup, row); });
    rows.push_back(row);
  }
  for (JointRow& row : rows) {
    if (row.is_tree_node()) set_tree_axes(row);
  }
}

void prepare_joint_rows(const Settings& settings, const std::vector<Body>& bodies, std::vector<Joint>& joints,
                        const std::vector<SolverBody>& solver_bodies, std::vector<JointRow>& rows, JointTree& tree) {
  build_joint_rows(settings, bodies, joints, solver_bodies, rows);
  factor_joint_tree(solver_bodies, rows, tree);
}

namespace {

// The most one joint's warm start may change a body's rates: 2^28 m/s or
// rad/s per component, so that the warm starts of up to seven joints on one
// body sum inside the range (2^31).
constexpr Fixed most_warm_response = Fixed::from_raw(int64_t{1} << 60);
constexpr Fixed impulse_sum_cap = Fixed::from_raw(int64_t{1} << 62);  // 2^30 N s

Fixed saturating_sum(Fixed sum, Fixed x) { return sum > impulse_sum_cap - x ? impulse_sum_cap : sum + x; }

// A bound on any component of I^-1 v per unit of v's largest: 3 max|I^-1_ij|.
Fixed inertia_bound(const Mat33& inverse_inertia) {
  Fixed largest;
  for (const Vec3& row : inverse_inertia.rows) largest = max(largest, max(abs(row.x), max(abs(row.y), abs(row.z))));
  return largest * 3.0_fx;
}

// How much one N s at the anchor r can change a body's rates, per
// component, at most: 1/m + 3 max|I^-1_ij| 2 max|r_k| (through I^-1 (r x
// lambda)); saturated at 2^30 for a far anchor on a tiny body.
Fixed anchor_response(const SolverBody& body, Vec3 r, Fixed inertia) {
  const Fixed lever = max(abs(r.x), max(abs(r.y), abs(r.z))) * 2.0_fx;
  if (product_exceeds(inertia, lever, impulse_sum_cap)) return impulse_sum_cap;
  return saturating_sum(body.inverse_mass, inertia * lever);
}

// Last step's impulses, halved until their warm start stays inside the
// number range. Two heavy bodies joined through a light one and swung
// apart (two 1,000 kg boxes through a 10 g die at 250 m/s) leave joint
// impulses of ~1e5 N s on the die's faces: they nearly cancel in sum, but
// applied one joint at a time each turns the die by ~1e9 rad/s, and two
// of them pass 2^31. A warm start is a guess that the solve corrects, so
// a joint's is scaled down (all its impulses alike, by a power of two)
// until the bound on its change to either body's rates, linear impulses
// times anchor_response plus angular ones times 3 max|I^-1_ij|, is at
// most most_warm_response. Far from it (a ragdoll's hand under its
// torso's pull: ~2^20) the impulses keep their bits.
void keep_warm_start_in_range(const SolverBody& a, const SolverBody& b, const JointRow& row) {
  Joint& joint = *row.joint;
  Fixed* const linear[] = {&joint.point_impulse.x, &joint.point_impulse.y, &joint.point_impulse.z,
                           &joint.distance_impulse, &joint.limit_impulse, &joint.motor_impulse};
  Fixed* const angular[] = {&joint.hinge_impulse[0], &joint.hinge_impulse[1], &joint.angular_impulse.x,
                            &joint.angular_impulse.y, &joint.angular_impulse.z, &joint.limit_impulse,
                            &joint.motor_impulse};
  Fixed linear_sum, angular_sum;
  for (const Fixed* x : linear) linear_sum = saturating_sum(linear_sum, abs(*x));
  for (const Fixed* x : angular) angular_sum = saturating_sum(angular_sum, abs(*x));
  if (linear_sum == Fixed{} && angular_sum == Fixed{}) return;
  const Fixed inertia = max(inertia_bound(a.inverse_inertia), inertia_bound(b.inverse_inertia));
  const Fixed response = max(anchor_response(a, row.ra, inertia), anchor_response(b, row.rb, inertia));
  // A limit's and a motor's impulse is linear on a slider, angular on a
  // hinge: each is counted on both sides, which only raises the bound.
  // Each of the two products is held to half of most_warm_response.
  int halvings = 0;
  const Fixed half_cap = Fixed::from_raw(most_warm_response.raw() >> 1);
  while (halvings < 62 && (product_exceeds(response, linear_sum, half_cap) || product_exceeds(inertia, angular_sum, half_cap))) {
    ++halvings;
    linear_sum = Fixed::from_raw(linear_sum.raw() >> 1);
    angular_sum = Fixed::from_raw(angular_sum.raw() >> 1);
  }
  if (halvings == 0) return;
  const int64_t divisor = int64_t{1} << halvings;
  for (Fixed* x : kept_impulses(joint)) *x = Fixed::from_raw(x->raw() / divisor);  // toward zero: either sign alike
}

}  // namespace

void warm_start_joints(std::vector<SolverBody>& bodies, const std::vector<JointRow>& rows) {
  for (const JointRow& row : rows) {
    SolverBody& a = bodies[row.a];
    SolverBody& b = bodies[row.b];
    keep_warm_start_in_range(a, b, row);
    with_joint_type(row.joint->type, [&](auto type) { decltype(type)::warm_start(a, b, row); });
  }
}

void solve_joints(std::vector<SolverBody>& bodies, std::vector<JointRow>& rows, JointTree& tree, int extra_pass) {
  const auto takes_part = [extra_pass](const JointRow& row) {
    return !row.velocity_held && (extra_pass < 0 || row.extra_velocity_passes > extra_pass);
  };
  for (JointRow& row : rows) {
    if (!row.friction || !takes_part(row)) continue;
    SolverBody& a = bodies[row.a];
    SolverBody& b = bodies[row.b];
    with_joint_type(row.joint->type,
                    [&](auto type) { decltype(type)::solve_friction(a, b, a.velocity, b.velocity, row); });
  }
  solve_pass(bodies, rows, tree, velocity_of, velocity_targets, velocity_impulses, takes_part, Promote::binding,
             &JointRow::velocity_held);
}

void push_joints(std::vector<SolverBody>& bodies, std::vector<JointRow>& rows, JointTree& tree, int extra_pass) {
  const auto takes_part = [extra_pass](const JointRow& row) {
    return !row.push_held && (extra_pass < 0 || row.extra_position_passes > extra_pass);
  };
  solve_pass(bodies, rows, tree, push_of, push_targets, push_impulses, takes_part, Promote::none, &JointRow::push_held);
}

bool joints_to_push(const std::vector<JointRow>& rows) {
  for (const JointRow& row : rows) {
    if (row.point_push_target != Vec3{} || row.rope_push_target != Fixed{} || row.hinge_push_target[0] != Fixed{} ||
        row.hinge_push_target[1] != Fixed{} || row.limit_push_target != Fixed{}) {
      return true;
    }
    for (const Fixed target : row.slide_push_target) {
      if (target != Fixed{}) return true;
    }
  }
  return false;
}

bool over_break_impulse(const Joint& joint) {
  if (joint.break_impulse == Fixed{}) return false;
  return with_joint_type(joint.type, [&](auto type) { return decltype(type)::breaks(joint); });
}

}  // namespace bitstep
