// GGRS's SyncTestSession: a game's own code run as a rollback session
// would run it in the worst case, alone, before it meets the network.
// Every tick each player's input comes from the game's input code, the
// session's tick runs (GameHooks: apply, the world's step, advance) and
// the world's state and the game's are saved; after each tick from the
// `distance`-th on, both go back `distance` ticks, those ticks run again
// with the same inputs, and every checksum (tick_checksum) must be what it
// was. A game that keeps state outside its save, reads anything but its
// saved state and the inputs (a clock, a random generator of its own, an
// unordered map's order), or changes the world outside its hooks shows up
// at the first tick that differs, named: the world's first differing field,
// or the game's first differing byte.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <vector>

#include "replay/session.h"

namespace bitstep {

struct GameSyncTestResult {
  std::vector<uint64_t> checksums;  // each tick's, the first time it ran
  int64_t resimulated_ticks = 0;
  int64_t mismatch_tick = 0;  // the first tick that ran differently again: 0 when none
  std::string difference;     // "<JSON path>: <first> vs <again>", or "the game's state: byte N: a vs b"
  bool ok() const { return mismatch_tick == 0; }
};

// The game's input code: player's input for a tick (called once per tick
// and player, in player order; the same inputs are used when it runs again).
using GameInputs = std::function<PlayerInput(int player, int64_t tick)>;

// Runs `ticks` ticks of `players` players' game from `sim` as it is,
// rolling back `distance` (1..64) ticks after each; stops at the first
// mismatch. `game` must pass check_hooks, with save and load.
GameSyncTestResult game_sync_test(Simulation& sim, const GameHooks& game, int players, const GameInputs& inputs,
                                  int64_t ticks, int distance);

}  // namespace bitstep
