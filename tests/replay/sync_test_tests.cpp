// The sync test (replay/sync_test.h): golden replays rolled back after
// every tick give their chains, and a re-simulation that differs is caught
// at its tick with the field that differs.
#include <catch2/catch.hpp>

#include <string>
#include <variant>
#include <vector>

#include "replay/sync_test.h"
#include "tests/replay/test_scenes.h"

using namespace bitstep;

namespace {

Replay golden(const std::string& name) {
  auto loaded = load_replay_file(test::scenes_dir + "/" + name, true);
  if (!loaded.ok()) FAIL(loaded.error().message());
  return std::move(loaded).value();
}

SyncTestResult sync_test_of(const Replay& replay, int frames, const SyncTestHook& hook = {},
                            SyncTestSaves saves = SyncTestSaves::rollback_states) {
  World world(replay.scene.settings);
  REQUIRE(build_world(replay.scene, world).ok());
  return sync_test(world, replay.inputs, replay.steps, frames, hook, saves);
}

}  // namespace

TEST_CASE("golden replays rolled back 8 ticks after every tick give their chains", "[sync_test]") {
  // A stack hit by spawned balls, a body removed, joints and ragdolls, a
  // driven car, sleep, sensors and filters; each kept as a step's state
  // restored in place (a rollback game's way) and as whole snapshots.
  // (The unoptimised checked build, ~15x slower, runs the four shorter
  // replays with rollback states only: 166 s otherwise.)
#if defined(NDEBUG)
  const std::vector<SyncTestSaves> ways = {SyncTestSaves::rollback_states, SyncTestSaves::snapshots};
  const std::vector<const char*> names = {"stack20.replay.json", "stack20.remove_middle.replay.json",
                                          "ragdolls.short.replay.json", "car_wall.replay.json",
                                          "thrown.sleep_motion.replay.json", "sensors.replay.json",
                                          "sliders_motors.replay.json"};
#else
  const std::vector<SyncTestSaves> ways = {SyncTestSaves::rollback_states};
  const std::vector<const char*> names = {"stack20.remove_middle.replay.json", "ragdolls.short.replay.json",
                                          "car_wall.replay.json", "sensors.replay.json"};
#endif
  for (const SyncTestSaves saves : ways) {
    for (const char* name : names) {
      INFO(name << (saves == SyncTestSaves::snapshots ? " (snapshots)" : " (rollback states)"));
      const Replay replay = golden(name);
      const SyncTestResult r = sync_test_of(replay, 8, {}, saves);
      INFO(r.difference);
      CHECK(r.ok());
      CHECK(r.hashes == replay.hashes);
      CHECK(r.rollbacks == 8 * (replay.steps - 7));
    }
  }
}

TEST_CASE("a tick simulated again differently is caught at that tick, naming the field", "[sync_test]") {
  const Replay replay = golden("stack20.replay.json");
  // A nudge only when tick 20 is simulated again: the state a rollback
  // game would reach differs from the one its peers have.
  const SyncTestResult r = sync_test_of(replay, 4, [](World& world, int64_t tick, bool again) {
    if (again && tick == 20) world.apply_impulse({7, world.bodies()[7].generation}, {0.001_fx, Fixed{}, Fixed{}}, world.bodies()[7].pose.position);
  });
  REQUIRE_FALSE(r.ok());
  CHECK(r.mismatch_tick == 20);
  CHECK(r.first_hash == replay.hashes[19]);
  CHECK(r.again_hash != r.first_hash);
  INFO(r.difference);
  // The first difference in the dump's order (here a friction impulse the
  // nudged cube passed down to the bottom contact).
  CHECK(r.difference.rfind("$.", 0) == 0);
  CHECK(r.difference.find(" vs ") != std::string::npos);
}
