// After the step's integration, every joint's error is projected out of
// the poses (post-stabilisation, Cline and Pai, "Post-stabilization for
// rigid body simulation with contact and constraints", 2003): the joints'
// position rows are built again at the integrated poses (the anchors'
// gap, a hinge's axis, a limit passed, a rope past its length) and
// solved exactly over each tree (joint_tree.h) for pseudo-velocities
// that close them in one step, which move the poses and nothing else (no
// momentum is added; velocities are the solve's). The rows are linear at
// the poses they start from: a pass that turned a body by more than 0.02
// rad is followed by a second, from the poses it left.
//
// Why: the solve's rows are linear in the step's start. A limb turning at
// 30 rad/s in a ragdoll's fall turns ~30 degrees a step at 60 Hz, and the
// linearised limit lets the integrated angle pass it by as much; the
// split impulse alone would take it back at max_push_out_speed (3 rad/s,
// 3 degrees a step), leaving a heap of ragdolls with limbs degrees past
// their limits. Projected, a limb ends the step within a fraction of a
// degree of its limit (tests/core/joint_tests.cpp: a hinge tumbling fast
// ends every step within half a degree of it). Off when the scene asks
// for Baumgarte (its bias is the joints' correction then).
// Internal to core/.
#pragma once

#include <vector>

#include "core/body.h"
#include "core/joint.h"
#include "core/joint_solver.h"
#include "core/settings.h"

namespace bitstep {

struct JointProjection {
  // Working memory, kept between steps (a settled step allocates nothing):
  // a copy of the joints (the row setup resets impulses a step's solve
  // still needs), the bodies as the solve sees them, the rows and trees.
  std::vector<Joint> joints;
  std::vector<SolverBody> bodies;
  std::vector<JointRow> rows;
  JointTree tree;
  // Per joint: whether the step's solve found it in a tree island
  // (tree_islands.h). Per body slot: the union-find over the joints
  // (through awake dynamic bodies), and per root whether its tree is
  // settled (joint_projection.cpp).
  std::vector<uint8_t> tree_island;
  std::vector<uint32_t> parent;
  std::vector<uint8_t> settled;
};

// Moves the awake bodies that joints hold so that every joint holds at
// their poses (to first order). Nothing to do without a live joint.
// `solved`: the step's solve's joint rows. A tree whose joints all were in
// tree islands there (tree_islands.h: no contact, no row solved row by
// row) and whose errors are all within a few micrometres is left as it
// is (joint_projection.cpp).
void project_joints(const Settings& settings, std::vector<Body>& bodies, const std::vector<Joint>& joints,
                    const std::vector<JointRow>& solved, JointProjection& scratch);

}  // namespace bitstep
