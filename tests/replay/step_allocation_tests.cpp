// A settled world's step allocates nothing (core/README.md): every per-step
// vector lives in workspace the world keeps (broadphase, narrowphase,
// solver, shock levels, islands), and no algorithm takes a heap buffer of
// its own. A game stepping 60 to 500 times a second (rollback re-simulates
// up to 8 frames per frame) should not touch the allocator once its scene
// has come to rest. Measured before the workspace: 32 allocations per
// settled step in stack20, 53 in pyramid20, 88 in thrown.
//
// This executable replaces the global operator new to count calls
// (tests/allocation_counter.h), so it holds allocation tests alone.
#include <catch2/catch.hpp>

#include <vector>

#include "replay/rollback_state.h"
#include "replay/state_hash.h"
#include "replay/thread_pool.h"
#include "tests/allocation_counter.h"
#include "tests/core/test_world.h"

using namespace bitstep;
using bitstep::test::allocations;
using bitstep::test::TestWorld;

namespace {

// Every shape kind at rest, each in the contacts a scene has: a stack of six
// boxes (face contacts, shock levels six high), a box across two boxes (a
// body on two supports), spheres on the ground and on a box, two capsules
// lying side by side, and a table of five boxes in one body (a compound).
void add_resting_scene(TestWorld& t) {
  t.add_ground();
  const Vec3 cube{0.25_fx, 0.25_fx, 0.25_fx};
  for (int k = 0; k < 6; ++k) t.add_box({Fixed{}, 0.25_fx + Fixed::from_int(k) * 0.5_fx, Fixed{}}, cube);
  t.add_box({2.0_fx, 0.25_fx, Fixed{}}, cube);
  t.add_box({3.0_fx, 0.25_fx, Fixed{}}, cube);
  t.add_box({2.5_fx, 0.6_fx, Fixed{}}, {0.8_fx, 0.1_fx, 0.25_fx});
  t.add_sphere({Fixed{}, 0.3_fx, 2.0_fx}, 0.3_fx);
  t.add_sphere({1.0_fx, 0.3_fx, 2.0_fx}, 0.3_fx);
  t.add_sphere({2.5_fx, 0.9_fx, Fixed{}}, 0.2_fx);
  for (int k = 0; k < 2; ++k) {
    const Quat lying = bitstep::test::about_degrees({Fixed{}, Fixed{}, Fixed::one()}, 90.0_fx);
    t.add_capsule({{-2.0_fx, 0.1_fx, Fixed::from_int(k) * 0.2_fx}, lying}, 0.1_fx, 0.5_fx);
  }
  BodyDef table;
  table.pose.position = {Fixed{}, 0.5_fx, -2.0_fx};
  table.shapes.push_back({ShapeType::box, {0.5_fx, 0.05_fx, 0.5_fx}, {}, {}, {}});
  for (int leg = 0; leg < 4; ++leg) {
    const Fixed x = leg % 2 == 0 ? 0.45_fx : -0.45_fx, z = leg < 2 ? 0.45_fx : -0.45_fx;
    table.shapes.push_back({ShapeType::box, {0.05_fx, 0.225_fx, 0.05_fx}, {}, {}, {{x, -0.275_fx, z}, {}}});
  }
  t.world.create_body(table);
}

long allocations_over(TestWorld& t, int steps) {
  const long before = allocations.load();
  t.simulate_steps(steps);
  return allocations.load() - before;
}

}  // namespace

TEST_CASE("the allocation counter sees a vector's allocation (negative control)", "[allocation]") {
  const long before = allocations.load();
  std::vector<int> v(1000, 1);
  CHECK(allocations.load() - before >= 1);
  CHECK(v[999] == 1);
}

TEST_CASE("a settled world's step allocates nothing, in both pipelines and every sleep method", "[allocation]") {
  for (Pipeline pipeline : {Pipeline::standard, Pipeline::guendelman}) {
    for (SleepMethod method : {SleepMethod::off, SleepMethod::motion, SleepMethod::still}) {
      Settings settings;
      settings.pipeline = pipeline;
      settings.sleep_method = method;
      TestWorld t(settings);
      add_resting_scene(t);
      t.simulate_steps(180);  // 3 s: settled (asleep under either method)
      INFO((pipeline == Pipeline::standard ? "standard" : "guendelman")
           << ", sleep " << (method == SleepMethod::off ? "off" : method == SleepMethod::motion ? "motion" : "still"));
      CHECK(t.world.stats().contact_points > 20);  // the scene is in contact, not flying apart
      CHECK(allocations_over(t, 60) == 0);
    }
  }
}

// The solver's sweeps shared among workers (core/ordered_sweeps.h) plan in
// workspace too: a settled pyramid of 120 boxes (~330 manifolds, enough to
// share) on two workers.
TEST_CASE("a settled pyramid's step on two workers allocates nothing", "[allocation][threads]") {
  ThreadPool pool(2);
  TestWorld t;
  t.add_ground();
  const Vec3 cube{0.25_fx, 0.25_fx, 0.25_fx};
  for (int row = 0; row < 15; ++row) {
    for (int k = 0; k < 15 - row; ++k) {
      const Fixed x = Fixed::from_int(2 * k + row - 14) * 0.26_fx;
      t.add_box({x, 0.25_fx + Fixed::from_int(row) * 0.5_fx, Fixed{}}, cube);
    }
  }
  t.world.set_executor(&pool);
  t.simulate_steps(60);
  const uint64_t shared_before = t.world.shared_sweep_runs();
  CHECK(allocations_over(t, 60) == 0);
  CHECK(t.world.shared_sweep_runs() > shared_before);  // the workers did run
}

TEST_CASE("a rollback state of a settled world is saved and restored in place without allocating", "[allocation]") {
  TestWorld t;
  add_resting_scene(t);
  t.simulate_steps(240);  // settled
  RollbackStates states;
  std::vector<uint8_t> buffer;
  states.save(t.world, buffer);  // grows the buffer, remembers every body once
  REQUIRE_FALSE(buffer.empty());
  REQUIRE(states.restore(buffer, t.world).ok());            // warms the reader's scratch up
  const uint64_t saved = state_hash(t.world);
  t.simulate_steps(8);
  const long before = allocations.load();
  states.save(t.world, buffer);
  REQUIRE(states.restore(buffer, t.world).ok());
  CHECK(allocations.load() - before == 0);
  CHECK(state_hash(t.world) != saved);  // the later state, restored
}
