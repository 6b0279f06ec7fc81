// `bitstep bench`'s costs section: what a game pays beyond a step.
// - Rollback: a rollback game restores the state of a past frame and
//   re-simulates up to 8 frames inside one 60 Hz frame (16.7 ms).
// - Memory: the peak resident memory of a large scene, bitstep and the
//   peer each in a process of its own (the peer program's `memory`).
#pragma once

#include <cstddef>
#include <optional>
#include <string>

#include "core/world.h"

namespace bitstep::bench {

inline constexpr int rollback_frames = 8;
inline constexpr double frame_ms = 1000.0 / 60.0;

struct RollbackRow {
  std::string scene;          // file name in the scenes folder
  int from_step = 0;          // the snapshot is taken after this many steps
  size_t bodies = 0;          // body slots
  size_t snapshot_bytes = 0;  // the whole world's image
  int rounds = 0;             // rollbacks timed
  double restore_ms = 0;      // mean, restore alone
  double rollback_ms = 0;     // mean, restore + rollback_frames steps
  // The same with a rollback state (replay/rollback_state.h): the step's
  // state alone, saved into a kept buffer and restored in place.
  size_t state_bytes = 0;
  double state_save_ms = 0, snapshot_save_ms = 0;  // mean, saving one
  double state_restore_ms = 0, state_rollback_ms = 0;
  // The rollback state's rollback when the input that caused it pushes a
  // body (the last dynamic one, 2 m/s sideways) at its first step.
  double pushed_rollback_ms = 0;
  bool same_bits = true;  // every round of each kind ended at its first round's state hash
};

// Loads the scene, steps it `from_step` times, snapshots it, then times
// `rounds` rollbacks (restore + rollback_frames steps), checking each ends
// on the same state hash. Throws std::runtime_error on a scene that does
// not load.
RollbackRow measure_rollback(const std::string& scenes_dir, const std::string& scene, int from_step, int rounds);

// The body a rollback case pushes: the last dynamic one in slot order (a
// pyramid's top cube, a pile's last), or nullopt.
std::optional<BodyId> last_dynamic_body(const World& world);
// An impulse that gives `body` `speed` (m/s) sideways along +x.
Vec3 sideways_impulse(const Body& body, Fixed speed);

// The peak resident set of a process, KiB (getrusage's ru_maxrss).
long peak_resident_kib();

}  // namespace bitstep::bench
