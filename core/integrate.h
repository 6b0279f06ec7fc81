// Integration: forces into velocities, velocities (plus split-impulse
// pseudo-velocities) into poses. Semi-implicit Euler, as both seeds.
#pragma once

#include <vector>

#include "core/contact.h"
#include "core/solver.h"

namespace bitstep {

// v += dt (g + F / m), w += dt I^-1 tau, damping, then the envelope's speed
// clamps; forces are cleared. Refreshes the world inverse inertia R I^-1 R^T.
// Sleeping bodies are skipped; integrate_velocity is one awake dynamic body.
void integrate_velocities(const Settings& settings, std::vector<Body>& bodies);
void integrate_velocity(const Settings& settings, Body& body);
// R I^-1 R^T of the body's current pose (from the body-frame inverse).
void refresh_inverse_inertia(Body& body);

// x += dt (v + v_push) for bodies with contact points, x += dt (v_start + v) / 2
// for bodies in free flight (exact under constant force; v_start is the
// velocity before this step's forces); q += dt/2 (w + w_push) q, renormalised.
// `touching` is scratch (per slot: has a contact point this step).
void integrate_positions(const Settings& settings, std::vector<Body>& bodies, const PushVelocities& push,
                         const std::vector<BodyRates>& start_velocities, const std::vector<Contact>& contacts,
                         std::vector<uint8_t>& touching);

}  // namespace bitstep
