#include "replay/sync_test.h"

#include <deque>

#include "replay/rollback_state.h"
#include "replay/snapshot.h"
#include "replay/state_dump.h"
#include "replay/state_hash.h"

namespace bitstep {

namespace {

// The state after a tick, and where the inputs stood.
struct Saved {
  std::vector<uint8_t> image;
  InputRun run;
};

// Saves and restores ticks one of the two ways.
class Keeper {
 public:
  explicit Keeper(SyncTestSaves saves) : saves_(saves) {}
  void save(const World& world, std::vector<uint8_t>& image) {
    if (saves_ == SyncTestSaves::snapshots) {
      image = snapshot(world);
      return;
    }
    states_.save(world, image);
  }
  Result<void> restore(const std::vector<uint8_t>& image, World& world) const {
    return saves_ == SyncTestSaves::snapshots ? bitstep::restore(image, world) : states_.restore(image, world);
  }

 private:
  SyncTestSaves saves_;
  RollbackStates states_;
};

void simulate_tick(World& world, const std::vector<Input>& inputs, int64_t tick, InputRun& run,
                   const SyncTestHook& hook, bool again) {
  apply_inputs(world, inputs, tick, run);
  if (hook) hook(world, tick, again);
  world.step();
}

}  // namespace

SyncTestResult sync_test(World& world, const std::vector<Input>& inputs, int64_t ticks, int frames,
                         const SyncTestHook& hook, SyncTestSaves saves) {
  SyncTestResult result;
  Keeper keeper(saves);
  InputRun run(world);
  // saved[i]: the state after tick (tick - saved.size() + 1 + i), the last
  // `frames` + 1 of them (the oldest is where a rollback starts).
  std::deque<Saved> saved;
  saved.push_back({{}, run});
  keeper.save(world, saved.back().image);
  for (int64_t tick = 1; tick <= ticks; ++tick) {
    simulate_tick(world, inputs, tick, run, hook, false);
    result.hashes.push_back(state_hash(world));
    saved.push_back({{}, run});
    keeper.save(world, saved.back().image);
    if (saved.size() > static_cast<size_t>(frames) + 1) saved.pop_front();
    if (tick < frames) continue;
    // Back `frames` ticks, and forward again.
    const Saved& start = saved.front();
    if (const Result<void> restored = keeper.restore(start.image, world); !restored.ok()) {
      result.mismatch_tick = tick - frames;
      result.difference = "restore: " + restored.error().message();
      return result;
    }
    InputRun again = start.run;
    for (int64_t t = tick - frames + 1; t <= tick; ++t) {
      simulate_tick(world, inputs, t, again, hook, true);
      ++result.rollbacks;
      const uint64_t h = state_hash(world);
      const uint64_t first = result.hashes[static_cast<size_t>(t - 1)];
      if (h == first) continue;
      result.mismatch_tick = t;
      result.first_hash = first;
      result.again_hash = h;
      // This state dumped, then the world restored to the first one's.
      const std::string again_dump = dump_state(world);
      const Saved& then = saved[static_cast<size_t>(t - (tick - frames))];
      if (const Result<void> restored = keeper.restore(then.image, world); !restored.ok()) {
        result.difference = "restore: " + restored.error().message();
      } else {
        // Both dumps are dump_state's: readable.
        const DumpDifference d = diff_dumps(dump_state(world), again_dump).value();
        result.difference = d.value_or("the dumps are equal (a field hashed but not dumped)");
      }
      return result;
    }
    run = again;
  }
  return result;
}

}  // namespace bitstep
