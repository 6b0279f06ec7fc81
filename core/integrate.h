// Integration: forces into velocities, velocities (plus split-impulse
// pseudo-velocities) into poses. Semi-implicit Euler, as in Kenwright's
// simple impulse engine and JigLib.
#pragma once

#include <vector>

#include "core/contact.h"
#include "core/joint.h"
#include "core/solver.h"

namespace bitstep {

// Each body slot's world inverse inertia as last computed, with the
// orientation and body-frame inverse it came from: R I^-1 R^T is a function
// of those two alone, so a body that has not turned by a bit (a standing
// structure's) takes it from here, not from two matrix products. Not state:
// the inputs are compared in full.
struct InertiaCache {
  struct Entry {
    Quat orientation;
    Mat33 local, world;
    bool valid = false;
  };
  std::vector<Entry> entries;
};

// v += dt (g + F / m), w += dt I^-1 tau, damping, then the envelope's speed
// clamps; forces are cleared. Refreshes the world inverse inertia R I^-1 R^T
// (through `cache` when given). Sleeping bodies are skipped;
// integrate_velocity is one awake dynamic body.
void integrate_velocities(const Settings& settings, std::vector<Body>& bodies, InertiaCache* cache = nullptr);
void integrate_velocity(const Settings& settings, Body& body, InertiaCache::Entry* cached = nullptr);
// R I^-1 R^T of the body's current pose (from the body-frame inverse).
void refresh_inverse_inertia(Body& body);

// The largest |entry| of a vector or matrix.
Fixed largest_component(Vec3 v);
Fixed largest_entry(const Mat33& m);

// Halves `inertia` (and doubles `inverse`, when given) until no entry
// exceeds 2^15 kg m^2, and returns how many times: what is homogeneous in I
// (Euler's equations, w . I w up to the factor 2^k) is then computed with
// w (<= 100 rad/s) inside the number range. 0 for every body below the
// bound: the plain bits.
int scale_inertia_down(Mat33& inertia, Mat33* inverse = nullptr);

// x += dt (v + v_push) for bodies with contact points, x += dt (v_start + v) / 2
// for bodies in free flight (exact under constant force; v_start is the
// velocity before this step's forces); q += dt/2 (w + w_push) q, renormalised.
// `touching` is scratch (per slot: has a contact point, a joint or a
// grounded wheel's rows this step: constrained, not in free flight; a
// chassis on its suspension moves by the velocity its implicit springs
// solved for, as they assume).
void integrate_positions(const Settings& settings, std::vector<Body>& bodies, const PushVelocities& push,
                         const std::vector<BodyRates>& start_velocities, const std::vector<Contact>& contacts,
                         const std::vector<Joint>& joints, const std::vector<TyreContact>& tyres,
                         std::vector<uint8_t>& touching);

}  // namespace bitstep
