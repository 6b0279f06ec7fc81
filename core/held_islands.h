// Fewer velocity passes for the islands the contacts hold at rest.
//
// The shock step (shock.h) gives a standing structure its velocities from
// the ground up after the iterations: in a pile at rest it recomputes what
// the later passes would refine. Standing scenes keep 0 drift and 0
// penetration with 4 velocity passes instead of 10, at a good deal fewer
// of the step's instructions (a pyramid, a wall, jenga); a pile in motion
// needs all of them (a thrown pile sinks deeper at 4). So an
// island whose bodies all start the step at rest (every movable body's
// velocity before this step's forces exactly zero, as the shock step
// leaves a standing structure), whose every
// contact is a resting face (3 or more touching points asking for no
// relative speed: its centroid and rocking rows settle the face's three
// normal degrees of freedom at once, contact_rows.cpp) and which has no
// impact, joint or tyre runs Settings::held_velocity_iterations passes;
// every other island the world's velocity_iterations. Heaps resting on
// edges and corners need their passes: held at 4, more of them creep than
// at 10. And a pile that trembles (a thrown pile with sleep off keeps
// trembling) is not at rest: held at 4 whenever it slowed below some speed,
// it would lose bit-exact rest, and with it the reuse of its rows and shape
// pairs (core/row_cache.h), costing more time a step than the skipped
// passes save.
//
// The first held passes sweep every row; the passes after them sweep only
// the rows of the islands in motion, in the same order. Rows of different
// islands share no movable body, so an island in motion computes exactly
// what it computed with every island at the world's passes. Only with the
// shock step (without it nothing recomputes the held islands' velocities).
// Here an island is the awake bodies joined by this solve's contact rows,
// joints and tyres; static and sleeping bodies join nothing. Internal to
// core/.
#pragma once

#include <cstdint>
#include <vector>

#include "core/joint_solver.h"
#include "core/solver_rows.h"
#include "core/tyre_rows.h"

namespace bitstep {

struct Settings;

struct HeldIslands {
  int all_passes = 0;  // velocity passes over every row (the world's when no island is held)
  int more_passes = 0;  // passes after them over the rows of the islands in motion
  // The rows of the islands in motion, in row order.
  std::vector<uint32_t> manifolds, free_rows;
  uint64_t held_rows = 0;  // manifold rows solved at the held passes, over the world's life
  // Workspace: the union-find's parents, and per root whether its island moves.
  std::vector<uint32_t> parent;
  std::vector<uint8_t> moving;
};

// Sorts the islands into held and in motion and lists the rows of those in
// motion. `start` per slot: the velocities before this step's forces.
void plan_held_islands(const Settings& settings, const std::vector<SolverBody>& bodies,
                       const std::vector<BodyRates>& start, const std::vector<PointRow>& rows,
                       const std::vector<ManifoldRow>& manifold_rows, const std::vector<JointRow>& joint_rows,
                       const std::vector<TyreRow>& tyre_rows, HeldIslands& out);

// The passes after the held ones over the islands in motion: per pass, as
// a world's pass, the manifolds' friction, centroid and rocking rows, the
// free point rows in alternating direction, the joints, the tyres.
void run_moving_passes(std::vector<SolverBody>& bodies, std::vector<PointRow>& rows,
                       const std::vector<ManifoldRow>& manifold_rows, std::vector<JointRow>& joint_rows,
                       JointTree& tree, std::vector<TyreRow>& tyre_rows, const HeldIslands& plan);

}  // namespace bitstep
