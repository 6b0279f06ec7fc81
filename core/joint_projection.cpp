#include "core/joint_projection.h"

#include <algorithm>

#include "core/islands.h"
#include "core/joint_types.h"
#include "fixed/mat33.h"
#include "fixed/quat.h"

namespace bitstep {

namespace {

// The projection's pseudo-velocity cap (m/s along an anchor's gap, rad/s
// about an axis): 1.7 m or 95 degrees a step at 60 Hz, a bound against a
// joint torn far apart, not a rate (capped at the split impulse's 3, or
// even at 10, a heap of ragdolls keeps limbs degrees past their limits).
constexpr Fixed projection_max_speed = 100.0_fx;

// A pass that turned a body by more than this (rad) left an error of about
// its square (the rows are linear at the poses they start from), so a
// second pass follows. With one pass a hard impact leaves a limb degrees
// past its limit; the second brings it back within a fraction of one. It
// runs in few of the steps that project (mostly in a ragdoll's first
// impacts), so it costs little.
constexpr Fixed second_pass_turn = 0.02_fx;
constexpr int max_passes = 2;

// A tree whose errors are all below this (m along an anchor's gap, rad
// about an axis: 2^-18, about 4 micrometres and 0.0002 degrees) is left
// to the next step's split impulse, where the step's solve held it as a
// tree island (a swinging chain, a pendulum: their joints part by less
// after the exact solve, and projecting them took a factorisation of the
// tree and a tree solve in most steps for nothing visible). Trees with
// contacts are projected whatever their error: a ragdoll heap left so
// (any tree within tolerance) fell asleep later (one heap of 16 after 7
// s) and one of the playground's ragdolls came to rest with a forearm 18
// mm into its chest.
constexpr Fixed projection_tolerance = Fixed::from_raw(int64_t{1} << 14);

// A live joint on an awake dynamic body: one the projection moves.
bool holds_awake_body(const Joint& joint, const std::vector<Body>& bodies) {
  return joint.alive && (is_awake_dynamic(bodies[joint.body_a]) || is_awake_dynamic(bodies[joint.body_b]));
}

// Takes out of the projection (marks not alive, in scratch.joints, the
// joints' copy) the trees (joints joined through awake dynamic bodies)
// whose joints all were in tree islands in the step's solve and are all
// within projection_tolerance of holding (each type's position_error).
// Trees are factorised and solved apart (joint_tree.h), so the others'
// projection has the bits it would have with them.
void leave_settled_trees(const std::vector<Body>& bodies, JointProjection& scratch) {
  std::vector<Joint>& joints = scratch.joints;
  std::vector<uint32_t>& parent = scratch.parent;
  parent.resize(bodies.size());
  for (uint32_t i = 0; i < parent.size(); ++i) parent[i] = i;
  for (const Joint& joint : joints) {
    if (joint.alive && is_awake_dynamic(bodies[joint.body_a]) && is_awake_dynamic(bodies[joint.body_b])) {
      unite(parent, joint.body_a, joint.body_b);
    }
  }
  const auto root_of = [&](const Joint& joint) {
    return find_root(parent, is_awake_dynamic(bodies[joint.body_a]) ? joint.body_a : joint.body_b);
  };
  std::vector<uint8_t>& settled = scratch.settled;
  settled.assign(bodies.size(), 1);
  for (size_t j = 0; j < joints.size(); ++j) {
    const Joint& joint = joints[j];
    if (!holds_awake_body(joint, bodies)) continue;
    uint8_t& tree = settled[root_of(joint)];
    if (!tree) continue;
    const Body& a = bodies[joint.body_a];
    const Body& b = bodies[joint.body_b];
    tree = scratch.tree_island[j] && with_joint_type(joint.type, [&](auto type) {
                                       return decltype(type)::position_error(joint, a, b);
                                     }) < projection_tolerance;
  }
  for (Joint& joint : joints) {
    if (holds_awake_body(joint, bodies) && settled[root_of(joint)]) joint.alive = false;
  }
}

// One projection: the joints' position rows at the current poses (but the
// settled trees'), solved exactly for pseudo-velocities that close them in
// one step, applied to the poses. Returns the largest turn (rad) of a
// body, or -1 when no row had anything to push.
Fixed project_once(const Settings& settings, std::vector<Body>& bodies, const std::vector<Joint>& joints,
                   JointProjection& scratch) {
  // The bodies a joint holds, with their inverse inertia at the current
  // orientation; every other body stands still.
  scratch.joints = joints;
  leave_settled_trees(bodies, scratch);
  std::vector<SolverBody>& solver_bodies = scratch.bodies;
  solver_bodies.assign(bodies.size(), SolverBody{});
  for (const Joint& joint : scratch.joints) {
    if (!joint.alive) continue;
    for (const uint32_t slot : {joint.body_a, joint.body_b}) {
      const Body& body = bodies[slot];
      if (!is_awake_dynamic(body) || solver_bodies[slot].inverse_mass != Fixed{}) continue;
      const Mat33 r = rotation(body.pose.orientation);
      solver_bodies[slot].inverse_mass = body.inverse_mass;
      solver_bodies[slot].inverse_inertia = r * body.inverse_inertia_local * transpose(r);
    }
  }
  for (SolverBody& body : solver_bodies) body.still = immovable(body);
  // The rows at these poses, their whole error closed in one step.
  Settings closing = settings;
  closing.split_impulse_factor = Fixed::one();
  closing.max_push_out_speed = projection_max_speed;
  build_joint_rows(closing, bodies, scratch.joints, solver_bodies, scratch.rows);
  if (!joints_to_push(scratch.rows)) return -Fixed::one();
  const Fixed dt = settings.dt;
  factor_joint_tree(solver_bodies, scratch.rows, scratch.tree);
  push_joints(solver_bodies, scratch.rows, scratch.tree);
  Fixed largest_rate;
  for (size_t i = 0; i < bodies.size(); ++i) {
    if (solver_bodies[i].still) continue;
    Body& body = bodies[i];
    const BodyRates& push = solver_bodies[i].push;
    const Vec3 rate = abs(push.angular);
    largest_rate = max(largest_rate, max(rate.x, max(rate.y, rate.z)));
    body.pose.position = mul_add(push.linear, dt, body.pose.position);
    if (push.angular != Vec3{}) body.pose.orientation = integrate(body.pose.orientation, push.angular, dt);
  }
  return largest_rate * dt;
}

}  // namespace

void project_joints(const Settings& settings, std::vector<Body>& bodies, const std::vector<Joint>& joints,
                    const std::vector<JointRow>& solved, JointProjection& scratch) {
  if (settings.baumgarte) return;
  const bool any =
      std::any_of(joints.begin(), joints.end(), [&](const Joint& j) { return holds_awake_body(j, bodies); });
  if (!any) return;
  scratch.tree_island.assign(joints.size(), 0);
  for (const JointRow& row : solved) {
    if (row.tree_island) scratch.tree_island[static_cast<size_t>(row.joint - joints.data())] = 1;
  }
  for (int pass = 0; pass < max_passes; ++pass) {
    if (project_once(settings, bodies, joints, scratch) <= second_pass_turn) return;
  }
}

}  // namespace bitstep
