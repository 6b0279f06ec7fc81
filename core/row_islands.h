// The solve's islands: a union-find over the body slots through every row
// between two movable bodies (contact manifolds, joints and, where asked,
// tyres), each set's root its lowest slot (islands.h), so the same islands
// whatever order the rows come in. The held islands' plan (held_islands.h)
// and the joints' extra passes (island_passes.h) read them. Internal to
// core/.
#pragma once

#include <cstdint>
#include <vector>

#include "core/joint_solver.h"
#include "core/solver_rows.h"
#include "core/tyre_rows.h"

namespace bitstep {

// Resets `parent` to one set per slot and joins the rows' bodies; tyres
// may be null (they join nothing).
void unite_rows(const std::vector<SolverBody>& bodies, const std::vector<ManifoldRow>& manifold_rows,
                const std::vector<JointRow>& joint_rows, const std::vector<TyreRow>* tyre_rows,
                std::vector<uint32_t>& parent);

// The island of a row between a and b: its movable body's root (every row
// touches a movable body).
uint32_t row_island(const std::vector<SolverBody>& bodies, std::vector<uint32_t>& parent, uint32_t a, uint32_t b);

}  // namespace bitstep
