// The world envelope (core/README.md "Bodies and mass"): what a
// body definition and an input may hold. Inside it nothing in the simulation
// leaves Q32.32 (a checked build aborts on any saturation: inside the
// envelope that is a bug); outside it a body is refused with the field and
// the reason, and inputs are bounded before they can overflow.
#pragma once

#include <string>

#include "core/body.h"
#include "core/error.h"
#include "core/settings.h"

namespace bitstep {

// Positions within +-16 km, sizes 0.01..50 m, parts within 50 m of the body
// origin, speeds within the body's limits (speed_limits); a dynamic body's
// mass 0.01..1e5 kg and density (given, or mass / volume) at most
// envelope::max_density. Refused: the field relative to the body ("mass",
// "shapes[2].radius") and why ("outside 0.01..50 m").
Result<void> check_envelope(const BodyDef& def);
// One shape of a body: its size keys within 0.01..50 m (a capsule's
// half_height 0..50 m) and its local position within 50 m of the body
// origin; `index` goes into the error's place ("shapes[index].radius").
Result<void> check_shape(const Shape& shape, int index);

// Refuses the first setting outside the world envelope (the place is its
// scene key, the reason "outside the world envelope"): readers refuse a
// scene or snapshot that asks for one. dt 0.0001..0.1 s, substeps 1..16
// with dt / substeps at least 0.0001 s, gravity within +-1000 m/s^2 per
// axis, velocity clamps positive and no higher than the envelope's speeds
// (above them the solver's products are not bounded), push-out speed and
// restitution threshold within those speeds, slop and speculative
// distance within the largest size.
Result<void> check_settings(const Settings& settings);

// Inputs. An input's velocity change can be far beyond the speed clamps (an
// impulse of 1e6 N s on 0.01 kg is 1e8 m/s; at the corner of a 0.01 m box it
// spins it at ~1e12 rad/s): it is computed at a power-of-two scale where it
// cannot leave the range, and the result is clamped at once to the speeds
// the step clamps to, keeping its direction. Within the clamps the result is
// bit for bit the plain formula's.
// A body's speed limits: the world's, lowered for a dynamic body whose
// momentum about its reach would pass envelope::max_reach_momentum:
// linear m v R <= L and angular m w R^2 <= L, R its reach. `shapes` about
// the centre of mass, inverse_mass 0 for a static or kinematic body
// (which keeps the world's). The step clamps to these (Body::limits).
// The farthest any point of the shapes lies from the frame's origin (m):
// a body's reach about its centre of mass.
Fixed reach(const std::vector<Shape>& shapes);
SpeedLimits speed_limits(Fixed inverse_mass, const std::vector<Shape>& shapes, SpeedLimits world);

// v += J / m, w += I^-1 (r x J) with r = point - centre of mass, each
// clamped to the limits. A dynamic body.
void add_impulse(Body& body, Vec3 impulse, Vec3 world_point, SpeedLimits limits);
// force += F, torque += r x F, each total bounded (direction kept) so that
// the step's dt F / m and dt I^-1 tau stay below 2^28 (m/s, rad/s: far
// beyond the clamps, which then apply) and inside the range.
void add_force(Body& body, Vec3 force, Vec3 world_point, Fixed dt);
// A velocity clamped to its length limit (the step's clamp).
Vec3 clamp_speed(Vec3 velocity, Fixed limit);

}  // namespace bitstep
