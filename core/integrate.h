// Integration: forces into velocities, velocities (plus split-impulse
// pseudo-velocities) into poses. Semi-implicit Euler, as both seeds.
#pragma once

#include <vector>

#include "core/solver.h"

namespace bitstep {

// v += dt (g + F / m), w += dt I^-1 tau, damping, then the envelope's speed
// clamps; forces are cleared. Refreshes the world inverse inertia R I^-1 R^T.
void integrate_velocities(const Settings& settings, std::vector<Body>& bodies);

// x += dt (v + v_push), q += dt/2 (w + w_push) q, renormalised.
void integrate_positions(const Settings& settings, std::vector<Body>& bodies, const PushVelocities& push);

}  // namespace bitstep
