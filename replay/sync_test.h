// GGPO's sync test, offline: a run that a rollback game would make in the
// worst case. After every tick the world goes back `frames` ticks (restored
// from the snapshot saved then), simulates them again with the same inputs
// and must reach the same hash at every one; a tick whose state depends on
// anything but the state saved and the inputs (a cache, an uninitialised
// field, the order of a hash map) shows up as a mismatch, with the first
// differing field of the two states.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "core/world.h"
#include "replay/replay.h"

namespace bitstep {

struct SyncTestResult {
  std::vector<uint64_t> hashes;  // the chain, one hash per tick (as a replay's)
  int64_t rollbacks = 0;         // ticks simulated again
  // The first tick whose state, simulated again, differed: 0 when none.
  int64_t mismatch_tick = 0;
  uint64_t first_hash = 0, again_hash = 0;  // its hash the first time and again
  std::string difference;                   // "<JSON path>: <first> vs <again>" (state_dump's diff)
  bool ok() const { return mismatch_tick == 0; }
};

// Before each tick's step, first time (again = false) and simulated again
// (again = true), after the tick's inputs: for tests that break it on purpose.
using SyncTestHook = std::function<void(World& world, int64_t tick, bool again)>;

// How a tick's state is kept: as a rollback game keeps it (a step's state
// alone, restored in place: rollback_state.h), or as a whole snapshot
// restored into a new world (snapshot.h).
enum class SyncTestSaves : uint8_t { rollback_states, snapshots };

// Runs `ticks` ticks of `inputs` (replay inputs: tick = step) from `world`
// at step 0, rolling back `frames` (>= 1) ticks after each tick from the
// `frames`-th on. Stops at the first mismatch.
SyncTestResult sync_test(World& world, const std::vector<Input>& inputs, int64_t ticks, int frames,
                         const SyncTestHook& hook = {}, SyncTestSaves saves = SyncTestSaves::rollback_states);

}  // namespace bitstep
