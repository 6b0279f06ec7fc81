// Rollback states (replay/rollback_state.h): a step's state alone, restored
// in place, gives the state hash it was saved with, across a removed body
// and a slot reused by another; it is refused by another world and when
// damaged, changing nothing; and it is smaller than a snapshot.
#include <catch2/catch.hpp>
#include <set>
#include <string>
#include <vector>

#include "replay/rollback_state.h"
#include "replay/simulation.h"
#include "replay/snapshot.h"
#include "replay/state_hash.h"
#include "tests/replay/test_scenes.h"

using namespace bitstep;

namespace {

std::vector<uint8_t> save(RollbackStates& states, const World& world) {
  std::vector<uint8_t> image;
  states.save(world, image);
  return image;
}

}  // namespace

TEST_CASE("a rollback state restores across a removed body and a reused slot, and the future follows", "[rollback_state]") {
  World world = test::world_of("stack20.json");
  RollbackStates states;
  for (int i = 0; i < 30; ++i) world.step();
  const std::vector<uint8_t> image = save(states, world);
  const uint64_t saved = state_hash(world);
  // The future from here, for comparison (a world restored from a snapshot).
  World reference;
  REQUIRE(restore(snapshot(world), reference).ok());
  std::vector<uint64_t> chain;
  for (int i = 0; i < 20; ++i) {
    reference.step();
    chain.push_back(state_hash(reference));
  }
  // Another timeline: cube 10 removed, a ball in its slot, some steps.
  const BodyId cube{10, world.bodies()[10].generation};
  REQUIRE(world.remove_body(cube));
  BodyDef ball;
  ball.pose.position = {Fixed::from_int(3), Fixed::from_int(2), Fixed{}};
  ball.shapes.push_back({ShapeType::sphere, {}, 0.4_fx, {}, {}});
  const Result<BodyId> spawned = world.create_body(ball);
  REQUIRE(spawned.ok());
  REQUIRE(spawned.value().index == 10);  // the slot reused
  for (int i = 0; i < 12; ++i) world.step();
  (void)save(states, world);  // the ball remembered too
  // Back: the cube's shapes and mass come back from the states' memory.
  REQUIRE(states.restore(image, world).ok());
  CHECK(state_hash(world) == saved);
  CHECK(world.bodies()[10].shapes.size() == 1u);
  CHECK(world.bodies()[10].shapes[0].type == ShapeType::box);
  for (int i = 0; i < 20; ++i) {
    world.step();
    CHECK(state_hash(world) == chain[static_cast<size_t>(i)]);
  }
}

TEST_CASE("a rollback state is refused by another world and when damaged, and nothing changes", "[rollback_state]") {
  World world = test::world_of("pyramid20.json");
  RollbackStates states;
  for (int i = 0; i < 5; ++i) world.step();
  const std::vector<uint8_t> image = save(states, world);
  world.step();
  const uint64_t now = state_hash(world);
  World other = test::world_of("pyramid20.json");
  const Result<void> foreign = states.restore(image, other);
  REQUIRE_FALSE(foreign.ok());
  CHECK(foreign.error().message() == "a rollback state of another world");
  World copy;  // the same state in another world object: its future bodies are its own
  REQUIRE(restore(snapshot(world), copy).ok());
  CHECK_FALSE(states.restore(image, copy).ok());
  std::vector<uint8_t> damaged = image;
  damaged[damaged.size() / 2] ^= 0x10;
  CHECK(states.restore(damaged, world).error().message() == "checksum mismatch: the image is corrupt");
  CHECK(states.restore(std::span<const uint8_t>(image.data(), image.size() - 1), world).error().message() ==
        "truncated or padded");
  CHECK(states.restore(std::span<const uint8_t>(image.data(), 10), world).error().message() == "not a rollback state");
  CHECK(state_hash(world) == now);
  // A buffer too small holds nothing usable and says how large it must be.
  std::vector<uint8_t> small(image.size() - 1);
  CHECK(states.save(world, std::span<uint8_t>(small)) == image.size());
  CHECK(states.save(world, std::span<uint8_t>()) == image.size());
}

TEST_CASE("a rollback state is smaller than a snapshot: its bodies carry no shapes or masses", "[rollback_state]") {
  for (const char* scene : {"stack20.json", "pyramid20.json", "wall128.json"}) {
    INFO(scene);
    World world = test::world_of(scene);
    world.step();
    RollbackStates states;
    const size_t rollback = save(states, world).size(), whole = snapshot(world).size();
    // Per body at least the 225 bytes of type, mass properties, material,
    // damping and one shape fewer.
    CHECK(whole - rollback >= 225 * world.bodies().size());
  }
}

TEST_CASE("rollback states follow their world: after a snapshot load they start again", "[rollback_state]") {
  World world = test::world_of("stack20.json");
  RollbackStates states;
  world.step();
  const std::vector<uint8_t> old_state = save(states, world);
  const std::vector<uint8_t> image = snapshot(world);
  // A snapshot restored makes a new world object, its serials numbered anew.
  REQUIRE(restore(image, world).ok());
  CHECK(states.restore(old_state, world).error().message() == "a rollback state of another world");
  for (int i = 0; i < 3; ++i) world.step();
  const std::vector<uint8_t> state = save(states, world);  // forgets the old world's bodies
  const uint64_t saved = state_hash(world);
  world.step();
  REQUIRE(states.restore(state, world).ok());
  CHECK(state_hash(world) == saved);
}

TEST_CASE("rollback states forget bodies gone from their last saves, and refuse the states that named them", "[rollback_state]") {
  World world = test::world_of("stack20.json");
  RollbackStates states;
  world.step();
  const std::vector<uint8_t> with_cube = save(states, world);
  const size_t kept = states.remembered_bodies();
  REQUIRE(world.remove_body({12, world.bodies()[12].generation}));
  std::vector<uint8_t> later;
  for (int i = 0; i < 3; ++i) {
    world.step();
    later = save(states, world);
  }
  states.forget_all_but_last(4);  // the cube was in the 4th last save: kept
  CHECK(states.remembered_bodies() == kept);
  states.forget_all_but_last(3);  // in none of the last 3: forgotten
  CHECK(states.remembered_bodies() == kept - 1);
  const uint64_t now = state_hash(world);
  const Result<void> refused = states.restore(with_cube, world);
  REQUIRE_FALSE(refused.ok());
  CHECK(refused.error().message() == "older than the states kept: a body it names was forgotten");
  CHECK(state_hash(world) == now);  // refused whole: nothing read
  // The last state still restores.
  world.step();
  REQUIRE(states.restore(later, world).ok());
  CHECK(state_hash(world) == now);
}

// Found by fuzz_capi (tools/fuzz/README.md): a state saved before a sensor
// filled a freed slot restored with the sensor's flag left in the dead slot
// (another hash, though accepted); and one saved before a world had joints,
// sensor overlaps or cars was refused once it had them (the copy it is read
// into kept them: "a joints, filters or cars block that this state does
// not have").
TEST_CASE("a rollback state restores after a sensor fills a freed slot, or a world gains joints or overlaps",
          "[rollback_state]") {
  const char* car_scene = R"({"format": "bitstep-scene", "version": 1, "bodies": [
    {"name": "ground", "type": "static", "position": [0, -1, 0], "shapes": [{"type": "box", "half_extents": [20, 1, 20]}]},
    {"name": "box", "position": [0, 0.5, 0], "shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}]},
    {"name": "chassis", "position": [5, 1, 0], "mass": 1200, "shapes": [{"type": "box", "half_extents": [0.9, 0.3, 2.1]}]}],
    "cars": [{"name": "car", "chassis": "chassis", "rays_per_wheel": 1, "wheels": [
      {"attachment": [0.8, -0.3, 1.45], "steered": true}, {"attachment": [-0.8, -0.3, 1.45], "steered": true},
      {"attachment": [0.8, -0.3, -1.45], "driven": true}, {"attachment": [-0.8, -0.3, -1.45], "driven": true}]}]})";
  const char* plain_scene = R"({"format": "bitstep-scene", "version": 1, "bodies": [
    {"name": "ground", "type": "static", "position": [0, -1, 0], "shapes": [{"type": "box", "half_extents": [20, 1, 20]}]},
    {"name": "box", "position": [0, 0.5, 0], "shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}]},
    {"name": "ball", "position": [0, 2, 0], "shapes": [{"type": "sphere", "radius": 0.5}]}]})";
  const char* sensor = R"({"name": "sensor", "sensor": true, "type": "static", "shapes": [{"type": "sphere", "radius": 7}]})";
  const char* pin = R"({"type": "point", "body_a": "box", "body_b": "ball", "anchor": [0, 1.25, 0]})";
  for (int variant = 0; variant < 3; ++variant) {
    INFO("variant " << variant);
    auto sim = Simulation::from_text(variant == 0 ? car_scene : plain_scene, "rollback.json");
    REQUIRE(sim.ok());
    for (int i = 0; i < 5; ++i) sim->step();
    if (variant == 0) REQUIRE(sim->remove_body(*sim->find_body("box")));  // the sensor takes its slot
    std::vector<uint8_t> image(sim->save_state({}));
    REQUIRE(sim->save_state(image) == image.size());
    const uint64_t saved = sim->hash();
    if (variant == 2) {
      REQUIRE(sim->add_joint(pin).ok());
    } else {
      REQUIRE(sim->add_body(sensor).ok());
    }
    sim->step();  // the sensor's overlaps, the joint's impulses
    const Result<void> loaded = sim->load_state(image);
    INFO((loaded.ok() ? "" : loaded.error().message()));
    CHECK(loaded.ok());
    CHECK(sim->hash() == saved);
  }
}

TEST_CASE("a rollback state's checksum is the same for worlds in the same state, whoever built them",
          "[rollback_state]") {
  for (const char* name : {"stack20.json", "playground.json", "ragdolls.json", "sensors.json"}) {
    INFO(name);
    World world = test::world_of(name);
    for (int i = 0; i < 30; ++i) world.step();
    // A body removed and another spawned: serials differ from a copy's.
    REQUIRE(world.remove_body(BodyId{1, world.bodies()[1].generation}));
    world.step();
    World copy;
    REQUIRE(restore(snapshot(world), copy).ok());  // another world object: its bodies have other serials
    RollbackStates mine, theirs;
    std::vector<uint8_t> a, b;
    std::set<uint64_t> seen;
    for (int i = 0; i < 20; ++i) {
      uint64_t sum_a = 0, sum_b = 0;
      mine.save(world, a, &sum_a);
      theirs.save(copy, b, &sum_b);
      REQUIRE(sum_a == sum_b);
      CHECK(RollbackStates::checksum(a) == sum_a);
      CHECK(a != b);  // the images differ (world, serials), the state does not
      seen.insert(sum_a);
      world.step();
      copy.step();
    }
    CHECK(seen.size() == 20);  // every step's state has its own
    // One bit of one velocity: another checksum.
    Simulation sim = std::move(Simulation::from_file(test::scenes_dir + "/" + name)).value();
    for (int i = 0; i < 5; ++i) sim.step();
    std::vector<uint8_t> before, after;
    uint64_t sum_before = 0, sum_after = 0;
    RollbackStates states;
    states.save(sim.world(), before, &sum_before);
    const BodyId moved{static_cast<uint32_t>(sim.world().bodies().size() - 1), sim.world().bodies().back().generation};
    const Body& body = sim.world().body(moved);
    Vec3 v = body.linear_velocity;
    v.y = Fixed::from_raw(v.y.raw() ^ 1);
    REQUIRE(sim.set_velocity(moved, v, body.angular_velocity));
    states.save(sim.world(), after, &sum_after);
    CHECK(sum_before != sum_after);
    // A changed payload byte, not resealed, is refused.
    after[after.size() - 20] ^= 1;
    CHECK(states.restore(after, sim.world()).error().message() == "checksum mismatch: the image is corrupt");
  }
  CHECK_FALSE(RollbackStates::checksum(std::vector<uint8_t>(10)).has_value());
}
