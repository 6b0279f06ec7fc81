// The threaded solve under ThreadSanitizer's eyes (tools/test.sh builds only
// this program with it): every golden replay on 3 workers and seven on 2
// and 8 (seven on each under ThreadSanitizer, tests/replay/golden_replays.h), and a
// restore that keeps the world's workers.
#include <catch2/catch.hpp>

#include <cstdint>
#include <string>
#include <variant>
#include <vector>

#include "replay/snapshot.h"
#include "replay/state_hash.h"
#include "replay/thread_pool.h"
#include "tests/replay/golden_replays.h"

using namespace bitstep;
using bitstep::test::replay_chain;
using bitstep::test::replays_of_this_build;

// The solver's sweeps on several workers keep every body's updates in the
// one-thread order (core/ordered_sweeps.h): the same chain for any count,
// more workers than cores included (8 on CI's 2). Every replay of the build
// runs on 3 workers, where the sweeps run on copies of the rows' parts in
// every scene; the seven covering replays on 2 and 8 (a worker count moves
// the shares' boundaries, not the kinds of work).
TEST_CASE("every golden replay reproduces its hash chain on 3 workers, the covering ones on 2 and 8",
          "[replay][golden][threads]") {
  for (const int workers : {2, 3, 8}) {
    const std::vector<std::string> paths = workers == 3 ? replays_of_this_build() : bitstep::test::covering_replays();
    ThreadPool pool(workers);
    uint64_t shared_runs = 0;
    for (const std::string& path : paths) {
      INFO(path << " on " << workers << " workers");
      auto loaded = load_replay_file(path, true);
      if (!loaded.ok()) FAIL(loaded.error().message());
      const Replay& replay = loaded.value();
      uint64_t scene_hash = 0;
      // On 3 workers the sweeps run on copies of the rows' parts (made and
      // written back by the workers) in every scene.
      CHECK(first_divergent_step(replay.hashes,
                                 replay_chain(replay, scene_hash, true, &pool, &shared_runs, workers == 3)) == 0);
    }
    // Shared, not left on one thread: the standing pyramid and the walls are
    // (977 runs on 2 and 3 workers, 616 on 8, in Release).
    CHECK(shared_runs > 10);
  }
}

// The executor is how a world steps, not state: a restore keeps the one the
// world had (a rollback session restores every frame), and a pyramid
// restored mid-collapse continues on two workers with the bits it would
// have had on one.
TEST_CASE("a restore keeps the world's executor, and the workers continue with the same bits", "[snapshot][threads]") {
  auto loaded = load_scene_file(std::string(BITSTEP_SOURCE_DIR) + "/scenes/pyramid20.json");
  REQUIRE(loaded.ok());
  const Scene& scene = loaded.value();
  World world(scene.settings);
  REQUIRE(build_world(scene, world).ok());
  for (int s = 0; s < 30; ++s) world.step();
  ThreadPool pool(2);
  World shared;
  shared.set_executor(&pool);
  REQUIRE(restore(snapshot(world), shared).ok());
  CHECK(shared.executor() == &pool);
  for (int s = 0; s < 30; ++s) {
    world.step();
    shared.step();
    REQUIRE(state_hash(shared) == state_hash(world));
  }
  CHECK(shared.shared_sweep_runs() > 0);
}
