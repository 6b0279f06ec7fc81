#include "core/joint_projection.h"

#include <algorithm>

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

// One projection: the joints' position rows at the current poses, solved
// exactly for pseudo-velocities that close them in one step, applied to
// the poses. Returns the largest turn (rad) of a body, or -1 when no row
// had anything to push.
Fixed project_once(const Settings& settings, std::vector<Body>& bodies, const std::vector<Joint>& joints,
                   JointProjection& scratch) {
  // The bodies a joint holds, with their inverse inertia at the current
  // orientation; every other body stands still.
  std::vector<SolverBody>& solver_bodies = scratch.bodies;
  solver_bodies.assign(bodies.size(), SolverBody{});
  for (const Joint& joint : joints) {
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
  scratch.joints = joints;
  prepare_joint_rows(closing, bodies, scratch.joints, solver_bodies, scratch.rows, scratch.tree);
  if (!joints_to_push(scratch.rows)) return -Fixed::one();
  push_joints(solver_bodies, scratch.rows, scratch.tree);
  const Fixed dt = settings.dt;
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
                    JointProjection& scratch) {
  if (settings.baumgarte) return;
  const bool any = std::any_of(joints.begin(), joints.end(), [&](const Joint& j) {
    return j.alive && (is_awake_dynamic(bodies[j.body_a]) || is_awake_dynamic(bodies[j.body_b]));
  });
  if (!any) return;
  for (int pass = 0; pass < max_passes; ++pass) {
    if (project_once(settings, bodies, joints, scratch) <= second_pass_turn) return;
  }
}

}  // namespace bitstep
