// The contact solver: sequential impulses with accumulated, warm-started
// impulses (Catto), friction clamped by the normal impulse with static and
// dynamic coefficients, restitution, and penetration recovery either by split
// impulse (pseudo-velocities that never enter momentum, JigLib's way)
// or by a Baumgarte bias on the real velocity (the way of Kenwright's simple
// impulse engine).
#pragma once

#include <vector>

#include "core/body.h"
#include "core/contact.h"
#include "core/executor.h"
#include "core/contact_rows.h"
#include "core/joint_solver.h"
#include "core/solver_scratch.h"
#include "core/solver_rows.h"
#include "core/tyre_rows.h"

namespace bitstep {

// Pseudo-velocities from the split-impulse passes, per body slot: positions
// integrate v + push, then push is dropped, so no energy enters.
struct PushVelocities {
  std::vector<Vec3> linear;
  std::vector<Vec3> angular;
};

// The joints to solve with the contacts, and their rows' workspace.
struct JointSet {
  std::vector<Joint>& joints;
  std::vector<JointRow>& rows;
  JointTree& tree;
};

// The cars' grounded tyres to solve with the contacts (core/tyre_rows.h),
// and their rows' workspace.
struct TyreSet {
  std::vector<TyreContact>& contacts;
  std::vector<TyreRow>& rows;
};

// What one solve works on: the world's state it changes (bodies,
// contacts), its joints, the workspace it keeps from step to step, and who
// runs its sweeps. `executor` (null: the caller's thread alone) spreads the
// iterations and position passes over its workers; the result is the same
// bits.
struct SolveContext {
  const Settings& settings;
  std::vector<Body>& bodies;
  std::vector<Contact>& contacts;
  JointSet joints;
  TyreSet tyres;
  PushVelocities& push;
  SolverScratch& scratch;
  Executor* executor = nullptr;
};

// One solve of the contacts, joints and tyres. Joints and tyres take part
// in the standard and contact passes (not in the guendelman collision
// pass, whose restitution acts on contacts alone); with either the sweeps
// stay on the caller's thread.
void solve_contacts(const SolveContext& context, SolvePass pass = SolvePass::standard);

}  // namespace bitstep
