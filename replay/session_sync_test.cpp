#include "replay/session_sync_test.h"

#include <deque>

#include "replay/rollback_state.h"
#include "replay/state_dump.h"

namespace bitstep {

namespace {

// The state after a tick: the world's, the game's, and the inputs that led there.
struct Kept {
  std::vector<uint8_t> world, game;
  std::vector<PlayerInput> inputs;  // the tick's own (none for the start)
};

}  // namespace

GameSyncTestResult game_sync_test(Simulation& sim, const GameHooks& game, int players, const GameInputs& inputs,
                                  int64_t ticks, int distance) {
  GameSyncTestResult result;
  RollbackStates states;
  const auto keep = [&](Kept& k) -> uint64_t {
    uint64_t world = 0;
    states.save(sim.world(), k.world, &world);
    k.game.clear();
    game.save(k.game);
    return tick_checksum(world, k.game);
  };
  const auto run = [&](int64_t tick, const std::vector<PlayerInput>& given) {
    for (int p = 0; p < players; ++p) game.apply(sim, p, given[static_cast<size_t>(p)]);
    sim.step();
    if (game.advance) game.advance(sim, tick);
  };
  // kept[i]: after tick (tick - kept.size() + 1 + i), the last distance + 1.
  std::deque<Kept> kept(1);
  keep(kept.back());
  for (int64_t tick = 1; tick <= ticks; ++tick) {
    Kept now;
    for (int p = 0; p < players; ++p) now.inputs.push_back(inputs(p, tick));
    run(tick, now.inputs);
    result.checksums.push_back(keep(now));
    kept.push_back(std::move(now));
    if (kept.size() > static_cast<size_t>(distance) + 1) kept.pop_front();
    if (tick < distance) continue;
    // Back `distance` ticks, the world and the game, and forward again.
    const Kept& start = kept.front();
    const Result<void> restored = states.restore(start.world, sim.world());
    if (!restored.ok() || !game.load(start.game)) {
      result.mismatch_tick = tick - distance;
      result.difference = restored.ok() ? "the game's load refused its own state" : restored.error().message();
      return result;
    }
    for (int64_t t = tick - distance + 1; t <= tick; ++t) {
      const Kept& first = kept[static_cast<size_t>(t - (tick - distance))];
      run(t, first.inputs);
      ++result.resimulated_ticks;
      Kept again;
      if (keep(again) == result.checksums[static_cast<size_t>(t - 1)]) continue;
      result.mismatch_tick = t;
      // The world's first differing field (the state again dumped, then
      // the first run's restored and dumped), else the game's byte.
      const std::string again_dump = dump_state(sim.world());
      if (const Result<void> back = states.restore(first.world, sim.world()); !back.ok()) {
        result.difference = back.error().message();
      } else {
        result.difference = diff_dumps(dump_state(sim.world()), again_dump)
                                .value()
                                .value_or(game_state_difference(first.game, again.game));
      }
      return result;
    }
  }
  return result;
}

}  // namespace bitstep
