// Snapshots: restoring continues bit-identically, and a damaged image is
// refused without touching the world.
#include <catch2/catch.hpp>

#include <string>
#include <variant>

#include "replay/replay.h"
#include "replay/snapshot.h"
#include "replay/state_dump.h"
#include "replay/state_hash.h"
#include "tests/replay/test_scenes.h"

using namespace bitstep;

namespace {

using bitstep::test::world_of;

World restored_from(const std::vector<uint8_t>& image) {
  World world;
  if (const Result<void> restored = restore(image, world); !restored.ok()) FAIL(restored.error().message());
  return world;
}

}  // namespace

TEST_CASE("snapshot equals real: restored at any step of a contact-dense window, the chain is the same",
          "[snapshot]") {
  World straight = world_of("thrown.json");
  const int first = 30, last = 75, end = 90;  // cubes hitting the pile
  std::vector<uint64_t> chain(end + 1);
  std::vector<std::vector<uint8_t>> images(end + 1);
  for (int step = 1; step <= end; ++step) {
    straight.step();
    chain[static_cast<size_t>(step)] = state_hash(straight);
    if (step >= first && step <= last) images[static_cast<size_t>(step)] = snapshot(straight);
  }
  for (int k = first; k <= last; ++k) {
    INFO("restored at step " << k);
    World world = restored_from(images[static_cast<size_t>(k)]);
    REQUIRE(state_hash(world) == chain[static_cast<size_t>(k)]);
    REQUIRE(snapshot(world) == images[static_cast<size_t>(k)]);  // the image round-trips byte for byte
    for (int step = k + 1; step <= end; ++step) {
      world.step();
      REQUIRE(state_hash(world) == chain[static_cast<size_t>(step)]);
    }
  }
}

TEST_CASE("rollback: 1,000 rounds of mispredicted inputs, restored and corrected, end bit-equal",
          "[snapshot]") {
  World straight = world_of("tables.json");
  World rolled = world_of("tables.json");
  const Vec3 point{Fixed{}, 9.0_fx, Fixed{}};
  for (int round = 0; round < 1000; ++round) {
    // The right input: a small push every 7th step on a table.
    const BodyId table{static_cast<uint32_t>(1 + round % 5), 0};
    const Vec3 right{Fixed::from_int(round % 7 == 0 ? 20 : 0), Fixed{}, Fixed{}};
    straight.apply_impulse(table, right, point);
    straight.step();
    // Predict with a wrong input for three steps, then roll back.
    const std::vector<uint8_t> image = snapshot(rolled);
    for (int k = 0; k < 3; ++k) {
      rolled.apply_impulse(table, Vec3{Fixed{}, Fixed{}, 30.0_fx}, point);
      rolled.step();
    }
    REQUIRE(restore(image, rolled).ok());
    rolled.apply_impulse(table, right, point);
    rolled.step();
  }
  CHECK(straight.step_count() == 1000);
  CHECK(state_hash(rolled) == state_hash(straight));
  CHECK(snapshot(rolled) == snapshot(straight));
}

TEST_CASE("a corrupt, truncated or wrong-version snapshot is refused and the world is untouched", "[snapshot]") {
  World source = world_of("stack20.json");
  for (int i = 0; i < 30; ++i) source.step();
  const std::vector<uint8_t> good = snapshot(source);
  World target = world_of("bounce.json");
  const uint64_t before = state_hash(target);

  auto refused = [&](std::vector<uint8_t> image, const std::string& expected) {
    INFO(expected);
    const Result<void> restored = restore(image, target);
    REQUIRE_FALSE(restored.ok());
    INFO(restored.error().message());
    CHECK(restored.error().message().find(expected) != std::string::npos);
    CHECK(state_hash(target) == before);
  };
  std::vector<uint8_t> flipped = good;
  flipped[flipped.size() / 2] ^= 0x10;
  refused(flipped, "checksum mismatch");
  refused(std::vector<uint8_t>(good.begin(), good.begin() + static_cast<std::ptrdiff_t>(good.size() - 9)), "truncated");
  refused(std::vector<uint8_t>(good.begin(), good.begin() + 10), "truncated");
  std::vector<uint8_t> version = good;
  version.at(8) = snapshot_version + 1;  // the next format's image
  refused(version, "version " + std::to_string(snapshot_version + 1));
  std::vector<uint8_t> magic = good;
  magic[0] = 'X';
  refused(magic, "bad magic");
  refused({}, "truncated");
  // Well formed, checksum and all, but asking for a step outside the world
  // envelope (a hand-made image: the scene reader refuses such settings).
  Settings outside;
  outside.dt = 1.0_fx;
  refused(snapshot(World(outside)), "dt outside the world envelope");
  outside.dt = "1/60"_fx;
  outside.max_linear_speed = 1000.0_fx;
  refused(snapshot(World(outside)), "max_linear_speed outside the world envelope");

  // The good image restores, and the world then equals the source.
  REQUIRE(restore(good, target).ok());
  CHECK(state_hash(target) == state_hash(source));
}

TEST_CASE("snapshotting a world does not change its future", "[snapshot]") {
  World a = world_of("jenga.json");
  World b = world_of("jenga.json");
  size_t bytes = 0;
  for (int i = 0; i < 60; ++i) {
    bytes += snapshot(a).size();
    a.step();
    b.step();
  }
  CHECK(bytes > 0);
  CHECK(state_hash(a) == state_hash(b));
}

TEST_CASE("a guendelman world with sleep restores its pipeline and sleep settings and continues identically",
          "[snapshot]") {
  auto loaded = load_scene_file(std::string(BITSTEP_SOURCE_DIR) + "/scenes/stack20.json");
  REQUIRE(loaded.ok());
  Scene scene = loaded.value();
  scene.settings.pipeline = Pipeline::guendelman;
  scene.settings.sleep_method = SleepMethod::still;
  World world(scene.settings);
  REQUIRE(build_world(scene, world).ok());
  for (int s = 0; s < 20; ++s) world.step();
  World copy;
  REQUIRE(restore(snapshot(world), copy).ok());
  CHECK(copy.settings().pipeline == Pipeline::guendelman);
  CHECK(copy.settings().sleep_method == SleepMethod::still);
  for (int s = 0; s < 60; ++s) {
    world.step();
    copy.step();
    REQUIRE(state_hash(copy) == state_hash(world));
  }
}

// More than one substep is a flag and a count byte in the settings; a world
// of one substep has the bytes it had before substeps existed (the golden
// replays' hashes hold them).
TEST_CASE("a world of 4 substeps restores its substeps and continues identically", "[snapshot][substeps]") {
  auto loaded = load_scene_file(std::string(BITSTEP_SOURCE_DIR) + "/scenes/chains.json");
  REQUIRE(loaded.ok());
  Scene scene = loaded.value();
  World one(scene.settings);
  REQUIRE(build_world(scene, one).ok());
  scene.settings.substeps = 4;
  World world(scene.settings);
  REQUIRE(build_world(scene, world).ok());
  CHECK(snapshot(world).size() == snapshot(one).size() + 1);
  CHECK(dump_state(one).find("substeps") == std::string::npos);
  for (int s = 0; s < 20; ++s) world.step();
  CHECK(dump_state(world).find("\"substeps\": 4") != std::string::npos);
  World copy;
  REQUIRE(restore(snapshot(world), copy).ok());
  CHECK(copy.settings().substeps == 4);
  for (int s = 0; s < 40; ++s) {
    world.step();
    copy.step();
    REQUIRE(state_hash(copy) == state_hash(world));
  }
  CHECK(copy.step_count() == 60);
}

// The soft step is a flag and its three settings; a world without it has
// the bytes it had before it existed.
TEST_CASE("a world of the soft step restores it and continues identically", "[snapshot][soft]") {
  auto loaded = load_scene_file(std::string(BITSTEP_SOURCE_DIR) + "/scenes/thrown.json");
  REQUIRE(loaded.ok());
  Scene scene = loaded.value();
  World rigid(scene.settings);
  REQUIRE(build_world(scene, rigid).ok());
  scene.settings.soft_substeps = 4;
  scene.settings.contact_hertz = 45.0_fx;
  World world(scene.settings);
  REQUIRE(build_world(scene, world).ok());
  CHECK(snapshot(world).size() == snapshot(rigid).size() + 1 + 8 + 8);
  CHECK(dump_state(rigid).find("soft_substeps") == std::string::npos);
  for (int s = 0; s < 40; ++s) world.step();  // the cubes are hitting the ground
  World copy;
  REQUIRE(restore(snapshot(world), copy).ok());
  CHECK((copy.settings().soft_substeps == 4 && copy.settings().contact_hertz == 45.0_fx));
  for (int s = 0; s < 40; ++s) {
    world.step();
    copy.step();
    REQUIRE(state_hash(copy) == state_hash(world));
  }
}

TEST_CASE("a world with joints restores and continues identically", "[snapshot][joint]") {
  World straight = world_of("stack20.json");
  // The top five boxes hung from one another and from box 10 by hinges,
  // the top one roped to the ground: the stack falls apart on its joints.
  for (uint32_t i = 16; i <= 20; ++i) {
    JointDef def;
    def.type = JointType::hinge;
    def.body_a = {i - 1, 0};
    def.body_b = {i, 0};
    def.anchor_a = straight.body(def.body_a).pose.position + Vec3{0.5_fx, 0.5_fx, Fixed{}};
    def.axis = {Fixed{}, Fixed{}, Fixed::one()};
    REQUIRE(straight.create_joint(def).ok());
  }
  straight.apply_impulse({18, 0}, {300.0_fx, Fixed{}, 100.0_fx}, straight.body({18, 0}).pose.position);
  std::vector<uint64_t> chain;
  std::vector<uint8_t> image;
  for (int step = 1; step <= 90; ++step) {
    straight.step();
    chain.push_back(state_hash(straight));
    if (step == 30) image = snapshot(straight);
  }
  World world;
  REQUIRE(restore(image, world).ok());
  REQUIRE(snapshot(world) == image);
  for (int step = 31; step <= 90; ++step) {
    world.step();
    REQUIRE(state_hash(world) == chain[static_cast<size_t>(step - 1)]);
  }
}

// Collision filters are state (they decide the future): hashed, saved and
// dumped in a block of their own, which a world without filters does not
// have (its hash is the one it had before filters existed).
TEST_CASE("a world with collision filters restores and continues identically", "[snapshot][filter]") {
  World straight = world_of("stack20.json");
  const uint64_t unfiltered = state_hash(straight);
  BodyDef ghost;
  ghost.pose.position = {Fixed{}, 3.0_fx, 0.3_fx};
  ghost.shapes.push_back({ShapeType::box, {0.5_fx, 0.5_fx, 0.5_fx}, {}, {}, {}});
  ghost.filter = {2, 1};  // on layer 1, colliding with layer 0 (the ground): through the stack
  const BodyId id = straight.create_body(ghost).value();
  std::vector<uint64_t> chain;
  std::vector<uint8_t> image;
  for (int step = 1; step <= 60; ++step) {
    straight.step();
    chain.push_back(state_hash(straight));
    if (step == 20) image = snapshot(straight);
  }
  World world;
  REQUIRE(restore(image, world).ok());
  REQUIRE(snapshot(world) == image);
  CHECK(world.body(id).filter == CollisionFilter{2, 1});
  for (int step = 21; step <= 60; ++step) {
    world.step();
    REQUIRE(state_hash(world) == chain[static_cast<size_t>(step - 1)]);
  }
  // Another filter, another hash; removing the filtered body leaves no block.
  World other = world_of("stack20.json");
  ghost.filter = {2, 3};
  other.create_body(ghost);
  World same = world_of("stack20.json");
  ghost.filter = {2, 1};
  same.create_body(ghost);
  CHECK(state_hash(other) != state_hash(same));
  const World unchanged = world_of("stack20.json");
  CHECK(state_hash(unchanged) == unfiltered);
}

// Sensor overlaps are state: restored while a cube is inside the zone, the
// world reports it leaving at the same step, with the same hash chain.
TEST_CASE("a world with sensors restores mid-overlap and reports the same events", "[snapshot][sensor]") {
  World straight = world_of("sensors.json");
  straight.set_events(true);
  std::vector<uint64_t> chain;
  std::vector<std::vector<WorldEvent>> events;
  std::vector<uint8_t> image;
  for (int step = 1; step <= 120; ++step) {
    straight.step();
    chain.push_back(state_hash(straight));
    events.push_back(straight.events());
    if (step == 40) {
      REQUIRE_FALSE(straight.sensor_overlaps().empty());  // cube.1 is inside the zone
      image = snapshot(straight);
    }
  }
  World world;
  REQUIRE(restore(image, world).ok());
  REQUIRE(world.sensor_overlaps().size() == 1u);
  world.set_events(true);
  int sensor_ends = 0;
  for (int step = 41; step <= 120; ++step) {
    world.step();
    REQUIRE(state_hash(world) == chain[static_cast<size_t>(step - 1)]);
    REQUIRE(world.events() == events[static_cast<size_t>(step - 1)]);
    for (const WorldEvent& e : world.events()) sensor_ends += e.kind == EventKind::sensor_end ? 1 : 0;
  }
  CHECK(sensor_ends == 4);  // cube.1, cube.2, cube.3 and the ball leave the zone after step 40
}

// Cars are state (their definitions and controls): a car driving and
// steering restores and continues with the same hash chain, and a world
// without cars keeps its old hash.
TEST_CASE("a world with a driven car restores and continues identically", "[snapshot][car]") {
  World straight = world_of("slide_stop.json");
  const uint64_t before_car = state_hash(straight);
  BodyDef body;
  body.pose.position = {Fixed{}, 3.0_fx, -5.0_fx};
  body.mass = Fixed::from_int(1000);
  body.shapes.push_back({ShapeType::box, {0.9_fx, 0.3_fx, 2.0_fx}, {}, {}, {}});
  const BodyId chassis = straight.create_body(body).value();
  CarDef def;
  def.chassis = chassis;
  def.rays_per_wheel = 3;
  for (int w = 0; w < 4; ++w) {
    def.wheels.push_back({{w % 2 == 0 ? 0.8_fx : -0.8_fx, -0.3_fx, w < 2 ? 1.4_fx : -1.4_fx}, w >= 2, w < 2});
  }
  const Result<CarId> made = straight.create_car(def);
  REQUIRE(made.ok());
  const CarId car = made.value();
  CHECK(state_hash(straight) != before_car);
  std::vector<uint64_t> chain;
  std::vector<uint8_t> image;
  for (int step = 1; step <= 180; ++step) {
    if (step == 60) straight.set_car_controls(car, {Fixed::one(), Fixed{}, 0.4_fx});
    straight.step();
    chain.push_back(state_hash(straight));
    if (step == 90) image = snapshot(straight);
  }
  World world;
  REQUIRE(restore(image, world).ok());
  REQUIRE(snapshot(world) == image);
  REQUIRE(world.cars().size() == 1u);
  CHECK(world.cars()[0].controls.steer == 0.4_fx);
  for (int step = 91; step <= 180; ++step) {
    world.step();
    REQUIRE(state_hash(world) == chain[static_cast<size_t>(step - 1)]);
  }
}
