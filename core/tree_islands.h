// Joint islands that one tree solve holds.
//
// The tree solve (joint_tree.h) gives lambda = K^-1 (target - J v) for
// every equality row of a tree at once, exact up to rounding. Where that
// is all an island has (every joint of it in an exact tree, none with a
// row solved row by row: a motor, friction, an active rope, an engaged
// limit or swing left out of the tree; no contact or tyre on its bodies),
// a later pass only solves again for what rounding left: a few ulp in a
// healthy tree, more where a pivot keeps a tiny part of its diagonal (a
// 10 g link holding a 100 t ball), where each pass refines the last. Such
// an island's joints (JointRow::tree_island) are solved while their tree's
// residual |target - J v| exceeds tree_residual_tolerance
// (joint_solver.cpp), and take part in no pass after that: a hanging chain
// or a pendulum is solved once or twice a step instead of once per pass.
// A row that leaves the tree in a pass ends this for its tree. Here an
// island is the awake bodies joined by this solve's contact rows, joints
// and tyres; static and sleeping bodies join nothing. Internal to core/.
#pragma once

#include <cstdint>
#include <vector>

#include "core/joint_solver.h"
#include "core/solver_rows.h"
#include "core/tyre_rows.h"

namespace bitstep {

struct TreeIslands {
  // Workspace: the union-find's parents, and per root whether anything
  // but the tree acts on its island.
  std::vector<uint32_t> parent;
  std::vector<uint8_t> more_than_tree;
};

// Sets every joint row's tree_island.
void mark_tree_islands(const std::vector<SolverBody>& bodies, const std::vector<ManifoldRow>& manifold_rows,
                       const std::vector<TyreRow>& tyre_rows, const JointTree& tree, std::vector<JointRow>& joint_rows,
                       TreeIslands& scratch);

}  // namespace bitstep
