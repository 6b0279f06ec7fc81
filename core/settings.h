// Every tunable of the simulation, with its unit and default. Scenes
// override any of them (replay/ maps the JSON keys of "settings" here).
#pragma once

#include <cstdint>

#include "fixed/decimal.h"
#include "fixed/vec3.h"

namespace bitstep {

using namespace bitstep::literals;

// The world envelope (core/README.md "Bodies and mass"): checked when a body is created.
namespace envelope {
inline constexpr Fixed max_position = 16000.0_fx;  // m, |coordinate|
inline constexpr Fixed min_size = 0.01_fx;         // m, box half-extent, radius, capsule half-height may be 0
inline constexpr Fixed max_size = 50.0_fx;         // m
inline constexpr Fixed min_mass = 0.01_fx;         // kg
inline constexpr Fixed max_mass = 100000.0_fx;     // kg
// kg/m^3, a dynamic body's density (given, or mass / volume): 4,400 times
// osmium, so 800 kg fits in the smallest box (0.02 m wide). The mass formulas
// (core/mass.cpp) form density x 4/3 pi, which leaves Q32.32 above 5.1e8.
inline constexpr Fixed max_density = 100000000.0_fx;
inline constexpr Fixed max_linear_speed = 500.0_fx;  // m/s
inline constexpr Fixed max_angular_speed = 100.0_fx; // rad/s
// A dynamic body's momentum about its reach R (the farthest point of its
// shapes from its centre of mass), kg m^2/s: its speeds are clamped below
// the world's where m v R or m w R^2 would pass this (speed_limits,
// core/envelope.h), so that the angular impulses the solver forms from them
// (a twist row's mu j_n r, a face's moment about its centroid, a joint's
// I dw, two such bodies meeting) stay inside Q32.32. At the world's speeds
// a 1e5 kg box 100 m wide would form ~1e10 (range 2.1e9): the checked build
// would abort in its first contact. Every corner of the envelope runs at
// limits from 2^30 (the range's largest power of two); 2^28 leaves 4x for two
// bodies meeting. A 1e5 kg body 87 m in reach moves at most 31 m/s and
// 0.36 rad/s; below m R = 537,000 kg m and m R^2 = 2.7e6 kg m^2 (a 1e5 kg
// body within 5 m, a 1,000 kg one within 50 m) the world's clamps stand.
inline constexpr Fixed max_reach_momentum = Fixed::from_raw(int64_t{1} << (28 + 32));  // 2.7e8
// The step's own settings. dt from 100 us (10 kHz) to 0.1 s (a 10 Hz
// lockstep tick): at 1000 s the first contact's dot products left Q32.32,
// and 1 / dt must fit (dt of 1 raw unit divided 1 by 2^-32). Gravity per
// axis up to 100 g.
inline constexpr Fixed min_dt = 0.0001_fx;           // s
inline constexpr Fixed max_dt = 0.1_fx;              // s
inline constexpr Fixed max_gravity = 1000.0_fx;      // m/s^2, per axis
// Substeps per step: dt / substeps must stay at least min_dt, the shortest
// step the products above were bounded for.
inline constexpr int max_substeps = 16;
// The soft step's contact spring (soft_step.h): its frequency and damping
// ratio. 2 pi 1000 Hz times the longest substep (0.1 s) times 2 (1000 +
// 630) stays far inside Q32.32.
inline constexpr Fixed max_contact_hertz = 1000.0_fx;  // Hz
inline constexpr Fixed max_damping_ratio = 1000.0_fx;  // 1
// The world's bound, m, |coordinate| of a centre of mass: a body past it at
// the end of a step is removed (World::step), so no world holds a position
// its saved state could not hold (the readers accept 2^20 m). 2^19 m is 32
// times the creation envelope and, a step moving a body at most 50 m
// (500 m/s x 0.1 s), leaves the readers' bound 500,000 m of room.
inline constexpr Fixed world_bound = Fixed::from_raw(int64_t{1} << 51);  // 524,288 m
}  // namespace envelope

// How bodies fall asleep (core/sleep.h). Off: no sleep bookkeeping at all.
enum class SleepMethod : uint8_t {
  off,
  motion,  // Kenwright's engine: a recently-weighted average of v.v + w.w stays below sleep_epsilon
  still,   // JigLib: the pose stays within tolerances of a reference pose for sleep_time
};

// The order of a step (core/world.cpp).
enum class Pipeline : uint8_t {
  standard,    // forces, contacts, one solve (restitution placed at the moment of impact), positions
  guendelman,  // JigLib (after Guendelman, Bridson and Fedkiw 2003): contacts where forces would take
               // the bodies, a collision pass with restitution on the current velocities, forces, an
               // inelastic contact pass, positions
};

struct Settings {
  Fixed dt = "1/60"_fx;                              // s, the fixed time step
  Vec3 gravity{Fixed{}, -9.81_fx, Fixed{}};          // m/s^2
  int velocity_iterations = 10;                      // sequential-impulse passes per step
  int position_iterations = 4;                       // split-impulse (pseudo-velocity) passes per step
  // Velocity passes, at most velocity_iterations, for an island the
  // contacts hold at rest (core/held_islands.h): every body of it still
  // when the step begins, every contact a resting face, no impact, joint
  // or tyre. Only with the shock step, which gives such an island its
  // velocities from the ground up.
  int held_velocity_iterations = 4;
  // count, 1..max_substeps: the step runs its whole physics n times at
  // dt / n (forces, cars, collision, solve, positions, joint projection), as
  // Jolt's collision steps do; inputs, hashes, snapshots, events, sleep,
  // joint breaking and the step counter stay at dt. Each pass's rows are
  // linear at its start: a chain under tension T has a transverse stiffness
  // T / l per link, and the step is stable only while T dt^2 / (m l) stays
  // small, so light links holding a heavy load need a shorter dt. 1: the
  // step as it always was, bit for bit.
  int substeps = 1;
  // 0: the solve above (velocity_iterations passes, the shock step, the
  // position passes). n > 0: the soft step (core/soft_step.h), Box2D v3's
  // solver: n substeps of one soft pass and one relax pass each, no shock
  // step, no position passes; velocity_iterations is not read.
  int soft_substeps = 0;
  Fixed contact_hertz = 30.0_fx;          // Hz, soft step: the contact spring's frequency
  Fixed contact_damping_ratio = 10.0_fx;  // 1, soft step: its damping ratio (overdamped)
  Fixed penetration_slop = Fixed{};                  // m, overlap left alone (no push-out below it); 0: resting
                                                     // shapes sit at their true geometry (a slop of mm leaves
                                                     // uneven overlaps that tilt a capsule pile into rolling)
  Fixed split_impulse_factor = 0.2_fx;               // 1, fraction of the overlap beyond the slop removed per step
  Fixed max_push_out_speed = 3.0_fx;                 // m/s, cap of the penetration-recovery speed
  bool baumgarte = false;                            // Kenwright's way: bias the real velocity instead of split impulse
  Fixed baumgarte_factor = 0.2_fx;                   // 1, used when baumgarte is on
  Fixed restitution_threshold = 1.0_fx;              // m/s, approach speeds below it do not bounce
  Fixed speculative_distance = 0.02_fx;              // m, contacts are kept this far before touching
  Fixed max_linear_speed = envelope::max_linear_speed;    // m/s, world envelope: velocities are clamped to it
  Fixed max_angular_speed = envelope::max_angular_speed;  // rad/s, world envelope
  bool warm_starting = true;                         // start each step from last step's impulses
  bool shock_propagation = true;                     // JigLib's: last pass up from the ground, lower bodies immovable
  int shock_iterations = 32;                         // most passes over each shock level (until nothing changes)
  Pipeline pipeline = Pipeline::standard;            // the order of the step
  SleepMethod sleep_method = SleepMethod::off;       // islands at rest stop costing anything
  Fixed sleep_epsilon = 0.05_fx;                     // m^2/s^2 (v.v + w.w), motion: sleepy below it, wakes a
                                                     // sleeping body it touches above 2x, capped at 10x
  Fixed sleep_bias = 0.96_fx;                        // 1, motion: rwa = bias rwa + (1 - bias) (v.v + w.w) per step
  Fixed sleep_min_time = 0.5_fx;                     // s, motion: sleepy this long before the island may sleep
  Fixed sleep_time = 1.0_fx;                         // s, still: within tolerance this long; velocities ramp
                                                     // to zero over its second half
  Fixed sleep_linear_tolerance = 0.05_fx;            // m, still: distance from the reference position
  Fixed sleep_angular_tolerance = 0.1_fx;            // rad, still: rotation from the reference orientation
};


}  // namespace bitstep
