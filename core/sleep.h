// Sleeping and activation (after Kenwright's simple impulse engine and
// JigLib). Islands (core/islands.h) sleep and wake as one. A sleeping body
// is not integrated, has zero velocity, and is immovable to the bodies
// touching it; contacts between bodies that cannot move are neither
// re-collided nor solved (core/contact_update.cpp).
//
// Methods (Settings::sleep_method):
// - motion (Kenwright's simple impulse engine): rwa = bias rwa + (1 - bias) (v.v + w.w) each step,
//   capped at 10 epsilon; a body is sleepy after rwa < epsilon for
//   sleep_min_time. A body touching a sleeping one wakes its island when its
//   own v.v + w.w exceeds 2 epsilon; a slower one rests on it as on the ground
//   and may fall asleep there.
// - still (JigLib's): a body whose pose stays within the tolerances of a
//   reference pose for sleep_time is sleepy; over the second half of that
//   time its velocities ramp down to zero. Any awake body touching a sleeping
//   one wakes its island.
// An island falls asleep when every awake body in it is sleepy and it rests
// on something: a static or kinematic body, or a body already asleep. A
// sleeping island wakes when an input reaches one of its bodies, when a body
// it touches is removed, and when it rests on nothing any more (it never
// floats): in the same step.
#pragma once

#include <cstdint>
#include <vector>

#include "core/body.h"
#include "core/contact.h"
#include "core/joint.h"
#include "core/islands.h"

namespace bitstep {

// Per-step working memory (rebuilt every step: not state).
struct SleepScratch {
  Islands islands;
  std::vector<uint8_t> island_flags;  // per island: sleep_flag_* bits
};

// The state a body starts from when it wakes (or is created awake).
void reset_sleep(const Settings& settings, Body& body);

// After the narrowphase: builds the islands and wakes each sleeping island
// that a fast body touches or that rests on nothing. Woken bodies get this
// step's forces when the others already have (`forces_done`: they skipped
// integrate_velocities). Returns the number woken.
int wake_islands(const Settings& settings, std::vector<Body>& bodies, const std::vector<Contact>& contacts,
                 const std::vector<Joint>& joints,
                 SleepScratch& scratch, bool forces_done = true);

// After the positions: updates each awake body's measure and puts to sleep
// the islands found by wake_islands whose awake bodies are all sleepy.
void sleep_islands(const Settings& settings, std::vector<Body>& bodies, SleepScratch& scratch);

// Wakes the sleeping bodies of the island holding each slot in `slots`
// (an input reached them, or their support was removed).
void wake_islands_of(const Settings& settings, std::vector<Body>& bodies, const std::vector<Contact>& contacts,
                     const std::vector<Joint>& joints,
                     const std::vector<uint32_t>& slots);

}  // namespace bitstep
