// The position passes: split impulse (JigLib's way). Each contact row
// whose point overlaps beyond the slop, or whose impact left an exact
// rebound displacement, asks for a push velocity; the passes solve the
// rows on pseudo-velocities (SolverBody::push) that positions integrate
// and then drop, so no energy enters. Joints push last in every pass, and
// the last pass pushes the contacts of jointed bodies one way (below).
// Internal to core/.
#pragma once

#include <cstdint>
#include <vector>

#include "core/island_passes.h"
#include "core/joint_solver.h"
#include "core/solver_rows.h"

namespace bitstep {

// The position passes' working memory: the last pass's one-way rows, by
// row (one_way_pushes), which bodies a joint holds, and their trees (a
// union-find's parents).
struct PositionScratch {
  std::vector<OneWayPush> one_way;
  std::vector<uint8_t> jointed;
  std::vector<uint32_t> joint_trees;
};

// settings.position_iterations passes over the contact rows and the
// joints, after the passes some islands' joints ask for beyond them
// (island_passes.h), on the caller's thread.
void push_apart(const Settings& settings, std::vector<SolverBody>& bodies, const std::vector<PointRow>& rows,
                std::vector<JointRow>& joint_rows, JointTree& tree, const IslandPasses& island_passes,
                PositionScratch& scratch);

}  // namespace bitstep
