// The world's bound (core/README.md "World bounds") and loads that change
// nothing: a body past envelope::world_bound at the end of a step is
// removed with a left_world event, so the world always saves and loads;
// and a rollback state or snapshot refused at any byte (truncated, a byte
// flipped, or flipped with the checksum made good again so that the reader
// itself must refuse it) leaves the world's hash as it was.
#include <xxhash.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <span>
#include <vector>

#include "replay/bitstep.h"
#include "replay/rollback_state.h"
#include "replay/snapshot.h"
#include "replay/state_hash.h"
#include "tests/replay/image_seal.h"

using namespace bitstep;

namespace {

BodyDef ball_at(Vec3 position) {
  BodyDef ball;
  ball.pose.position = position;
  ball.shapes.push_back({ShapeType::sphere, {}, 0.5_fx, {}, {}});
  return ball;
}

// A ground, a box resting on it and a ball 10 m to the side with nothing
// below it.
World ground_box_and_ball() {
  World world;
  BodyDef ground;
  ground.type = BodyType::static_body;
  ground.pose.position = {Fixed{}, -1.0_fx, Fixed{}};
  ground.shapes.push_back({ShapeType::box, {5.0_fx, 1.0_fx, 5.0_fx}, {}, {}, {}});
  REQUIRE(world.create_body(ground).ok());
  BodyDef box;
  box.pose.position = {Fixed{}, 0.5_fx, Fixed{}};
  box.shapes.push_back({ShapeType::box, {0.5_fx, 0.5_fx, 0.5_fx}, {}, {}, {}});
  REQUIRE(world.create_body(box).ok());
  REQUIRE(world.create_body(ball_at({10.0_fx, Fixed{}, Fixed{}})).ok());
  return world;
}

// The same world with body `slot` moved to `position` at `velocity` (a
// world cannot create a body past the 16 km envelope: it is built from
// the state, as a snapshot restore builds one).
World moved(const World& world, uint32_t slot, Vec3 position, Vec3 velocity) {
  std::vector<Body> bodies = world.bodies();
  bodies[slot].pose.position = position;
  bodies[slot].linear_velocity = velocity;
  return World::from_state(world.settings(), world.step_count(), bodies, world.free_slots(), world.contacts(),
                           world.joints(), world.free_joint_slots(), world.sensor_overlaps(), world.cars());
}

// A 20 m rope from the box (slot 1) to the ball (slot 2).
void rope_box_to_ball(World& world) {
  JointDef rope;
  rope.type = JointType::max_distance;
  rope.body_a = {1, world.bodies()[1].generation};
  rope.body_b = {2, world.bodies()[2].generation};
  rope.anchor_a = world.bodies()[1].pose.position;
  rope.anchor_b = world.bodies()[2].pose.position;
  rope.length = 20.0_fx;
  const Result<JointId> joined = world.create_joint(rope);
  if (!joined.ok()) FAIL(joined.error().message());
}

bool inside_bound(const World& world) {
  for (const Body& body : world.bodies()) {
    if (!body.alive) continue;
    for (const Fixed f : {body.pose.position.x, body.pose.position.y, body.pose.position.z}) {
      if (f > envelope::world_bound || f < -envelope::world_bound) return false;
    }
  }
  return true;
}

// The world saves and loads both ways, and keeps stepping as a copy
// loaded from its snapshot does.
void saves_loads_and_steps(World& world) {
  const uint64_t hash = state_hash(world);
  RollbackStates states;
  std::vector<uint8_t> state;
  states.save(world, state);
  for (int i = 0; i < 3; ++i) world.step();
  REQUIRE(states.restore(state, world).ok());
  CHECK(state_hash(world) == hash);
  World copy;
  REQUIRE(restore(snapshot(world), copy).ok());
  CHECK(state_hash(copy) == hash);
  for (int i = 0; i < 30; ++i) {
    world.step();
    copy.step();
  }
  CHECK(state_hash(world) == state_hash(copy));
}

}  // namespace

// 200,000 real steps: 0.3 s in Release, 26 s in the checked ASan build,
// which has the next test's balls started 1 m inside the bound instead.
TEST_CASE("a ball falling for 200,000 steps leaves the world at its bound, which saves, loads and steps",
          "[bounds][slow]") {
  World world = ground_box_and_ball();
  world.set_events(false);  // left_world is listed all the same
  uint64_t left_at = 0;
  bool always_inside = true;
  for (int step = 1; step <= 200000; ++step) {
    world.step();
    for (const WorldEvent& e : world.events()) {
      CHECK(e.kind == EventKind::left_world);
      CHECK(e.key.body_a == 2u);
      left_at = world.step_count();
    }
    if ((step & 1023) == 0) always_inside = always_inside && inside_bound(world);
  }
  CHECK(always_inside);
  // 500 m/s after 51 s (12.7 km); 2^19 m at step 64,444 (60 Hz).
  CHECK(left_at == 64444);
  CHECK_FALSE(world.bodies()[2].alive);
  CHECK(world.bodies()[1].alive);
  saves_loads_and_steps(world);
}

TEST_CASE("a ball thrown past the bound at full speed is removed that step, with its joint", "[bounds]") {
  const Fixed bound = envelope::world_bound;
  const Fixed speed = envelope::max_linear_speed;
  const World start = ground_box_and_ball();
  // Each axis, each side; the ball 1 m inside the bound, thrown outward.
  for (int axis = 0; axis < 3; ++axis) {
    for (const int side : {1, -1}) {
      Vec3 position{10.0_fx, Fixed{}, Fixed{}}, velocity;
      const Fixed sign = Fixed::from_int(side);
      (axis == 0 ? position.x : axis == 1 ? position.y : position.z) = sign * (bound - 1.0_fx);
      (axis == 0 ? velocity.x : axis == 1 ? velocity.y : velocity.z) = sign * speed;
      World world = moved(start, 2, position, velocity);
      world.set_events(true);  // the box's contact begins too; left_world comes last
      world.step();
      REQUIRE_FALSE(world.events().empty());
      CHECK(world.events().back().kind == EventKind::left_world);
      CHECK(world.events().back().key.body_a == 2u);
      CHECK_FALSE(world.bodies()[2].alive);
      CHECK(inside_bound(world));
      saves_loads_and_steps(world);
    }
  }
  // Jointed to the box: the joint goes with it, the box stays.
  World joined = ground_box_and_ball();
  rope_box_to_ball(joined);
  World world = moved(joined, 2, {bound, Fixed{}, Fixed{}}, {speed, Fixed{}, Fixed{}});
  world.step();
  CHECK_FALSE(world.bodies()[2].alive);
  CHECK_FALSE(world.joints()[0].alive);
  CHECK(world.bodies()[1].alive);
  saves_loads_and_steps(world);
  // At the bound exactly, a body stays (the bound is inclusive).
  World resting = moved(start, 2, {bound, Fixed{}, Fixed{}}, {});
  Settings no_gravity = resting.settings();
  no_gravity.gravity = {};
  World still = World::from_state(no_gravity, 0, resting.bodies(), resting.free_slots(), resting.contacts());
  still.step();
  CHECK(still.bodies()[2].alive);
}

TEST_CASE("a snapshot of a body between the bound and the readers' 2^20 m loads, and its next step removes it",
          "[bounds]") {
  const Fixed beyond = envelope::world_bound + envelope::world_bound / 2.0_fx;
  const World old = moved(ground_box_and_ball(), 2, {Fixed{}, -beyond, Fixed{}}, {});
  World world;
  REQUIRE(restore(snapshot(old), world).ok());
  world.step();
  REQUIRE(world.events().size() == 1u);
  CHECK(world.events()[0].kind == EventKind::left_world);
  CHECK_FALSE(world.bodies()[2].alive);
  saves_loads_and_steps(world);
}

TEST_CASE("a rollback state refused at any byte changes nothing", "[bounds][rollback_state]") {
  World world = ground_box_and_ball();
  rope_box_to_ball(world);
  for (int i = 0; i < 5; ++i) world.step();
  RollbackStates states;
  std::vector<uint8_t> image, now;
  states.save(world, image);
  for (int i = 0; i < 5; ++i) world.step();
  states.save(world, now);
  const uint64_t hash = state_hash(world);
  size_t refused = 0, resealed_refused = 0, resealed_read = 0;
  for (size_t size = 0; size < image.size(); ++size) {
    refused += !states.restore(std::span<const uint8_t>(image.data(), size), world).ok();
  }
  CHECK(refused == image.size());
  CHECK(state_hash(world) == hash);
  for (size_t at = 0; at < image.size(); ++at) {
    std::vector<uint8_t> flipped = image;
    flipped[at] ^= 0xFF;
    refused += !states.restore(flipped, world).ok();
    REQUIRE(state_hash(world) == hash);
    if (at >= image.size() - 8) continue;
    test::reseal_rollback_state(flipped);  // the reader itself must refuse it, or read it whole
    if (!states.restore(flipped, world).ok()) {
      ++resealed_refused;
      REQUIRE(state_hash(world) == hash);
    } else {
      ++resealed_read;
      REQUIRE(states.restore(now, world).ok());
      REQUIRE(state_hash(world) == hash);
    }
  }
  CHECK(refused == 2 * image.size());
  // Flips of a value's high byte make a value no world holds.
  CHECK(resealed_refused > 100);
  WARN(image.size() << " bytes: " << refused << " truncations and flips refused; resealed flips: "
                    << resealed_refused << " refused, " << resealed_read << " read whole");
  // Through the C API: the same, as a game sees it.
  const char* scene = R"({"format": "bitstep-scene", "version": 1, "bodies": [
    {"name": "ground", "type": "static", "shapes": [{"type": "box", "half_extents": [5, 1, 5]}]},
    {"name": "box", "position": [0, 1.5, 0], "shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}]}]})";
  bitstep_simulation* sim = nullptr;
  REQUIRE(bitstep_create_from_text(scene, std::char_traits<char>::length(scene), "scene", &sim, nullptr, 0) ==
          BITSTEP_OK);
  for (int i = 0; i < 3; ++i) REQUIRE(bitstep_step(sim) == BITSTEP_OK);
  const auto saved = [&](bool whole) {
    std::vector<uint8_t> bytes(4096);
    size_t size = 0;
    REQUIRE((whole ? bitstep_save(sim, bytes.data(), bytes.size(), &size)
                   : bitstep_save_state(sim, bytes.data(), bytes.size(), &size)) == BITSTEP_OK);
    bytes.resize(size);
    return bytes;
  };
  const std::vector<uint8_t> c_state = saved(false), c_snapshot = saved(true);
  for (int i = 0; i < 3; ++i) REQUIRE(bitstep_step(sim) == BITSTEP_OK);
  const std::vector<uint8_t> c_state_now = saved(false);
  const uint64_t c_hash = bitstep_hash(sim);
  // Every flip (resealed) and truncation of `saved_image` through `load`:
  // refused with the hash as it was, or read whole (then `current` brings
  // it back).
  const auto refuse_each = [&](auto load, auto reseal, const std::vector<uint8_t>& saved_image,
                               const std::vector<uint8_t>& current) {
    for (size_t at = 0; at < saved_image.size(); ++at) {
      std::vector<uint8_t> flipped = saved_image;
      flipped[at] ^= 0xFF;
      reseal(flipped);
      if (load(sim, flipped.data(), flipped.size()) == BITSTEP_OK) {
        REQUIRE(load(sim, current.data(), current.size()) == BITSTEP_OK);
      }
      REQUIRE(bitstep_hash(sim) == c_hash);
      REQUIRE(load(sim, saved_image.data(), at) == BITSTEP_INVALID);
      REQUIRE(bitstep_hash(sim) == c_hash);
    }
  };
  refuse_each(bitstep_load_state, test::reseal_rollback_state, c_state, c_state_now);
  refuse_each(bitstep_load, test::reseal_snapshot, c_snapshot, saved(true));  // last: a snapshot load makes a new world
  bitstep_destroy(sim);
}

TEST_CASE("a snapshot refused at any byte changes nothing", "[bounds][snapshot]") {
  World world = ground_box_and_ball();
  for (int i = 0; i < 5; ++i) world.step();
  const std::vector<uint8_t> image = snapshot(world);
  for (int i = 0; i < 5; ++i) world.step();
  const std::vector<uint8_t> now = snapshot(world);
  const uint64_t hash = state_hash(world);
  size_t refused = 0, resealed_refused = 0;
  for (size_t size = 0; size < image.size(); ++size) {
    refused += !restore(std::span<const uint8_t>(image.data(), size), world).ok();
  }
  CHECK(refused == image.size());
  CHECK(state_hash(world) == hash);
  for (size_t at = 0; at < image.size(); ++at) {
    std::vector<uint8_t> flipped = image;
    flipped[at] ^= 0xFF;
    refused += !restore(flipped, world).ok();
    REQUIRE(state_hash(world) == hash);
    if (at >= image.size() - 8) continue;
    test::reseal_snapshot(flipped);
    if (!restore(flipped, world).ok()) {
      ++resealed_refused;
      REQUIRE(state_hash(world) == hash);
    } else {
      REQUIRE(restore(now, world).ok());
      REQUIRE(state_hash(world) == hash);
    }
  }
  CHECK(refused == 2 * image.size());
  CHECK(resealed_refused > 100);
  WARN(image.size() << " bytes: " << refused << " truncations and flips refused; resealed flips refused: "
                    << resealed_refused);
}
