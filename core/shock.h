// Shock propagation (Guendelman, Bridson and Fedkiw), the last pass of the
// velocity solve: rank by rank upward from the ground and sideways from
// walls (shock_levels.h), every body ranked below is immovable (infinite
// mass), so each body is stopped against its supports exactly instead of
// sharing the correction with them, and a stack's column of contacts
// converges in one pass however tall it is. Bodies without support are
// left as the iterations left them. Internal to core/.
#pragma once

#include <vector>

#include "core/contact.h"
#include "core/solver_rows.h"

namespace bitstep {

// Reads scratch.rows and scratch.manifolds, updates scratch.bodies'
// velocities, uses the scratch's shock vectors.
void propagate_shock(const Settings& settings, const std::vector<Body>& bodies, const std::vector<Contact>& contacts,
                     SolverScratch& scratch);

}  // namespace bitstep
