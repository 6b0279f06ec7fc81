// Sleeping and activation on the shipped scenes, under both methods: when
// islands fall asleep (golden steps), what wakes them, and that a sleeping
// world continues bit-identically through a snapshot.
#include <catch2/catch.hpp>

#include <string>
#include <vector>

#include "core/world.h"
#include "replay/scene.h"
#include "replay/snapshot.h"
#include "replay/state_hash.h"
#include "tests/replay/test_scenes.h"
#include "tests/test_support.h"

using namespace bitstep;

namespace {

const char* name_of(SleepMethod method) { return method == SleepMethod::motion ? "motion" : "still"; }

Scene scene_with_sleep(const std::string& file, SleepMethod method) {
  auto loaded = load_scene_file(test::scenes_dir + "/" + file);
  if (!loaded.ok()) FAIL(loaded.error().message());
  Scene scene = loaded.value();
  scene.settings.sleep_method = method;
  return scene;
}

World build(const Scene& scene) {
  World world(scene.settings);
  if (const Result<void> built = build_world(scene, world); !built.ok()) FAIL(built.error().message());
  return world;
}

World world_with_sleep(const std::string& file, SleepMethod method) { return build(scene_with_sleep(file, method)); }

int dynamic_count(const World& world) {
  int n = 0;
  for (const Body& b : world.bodies()) n += b.alive && b.type == BodyType::dynamic;
  return n;
}

bool all_asleep(const World& world) { return world.stats().sleeping_bodies == dynamic_count(world); }

// Steps until every dynamic body sleeps (limit + 1 if they never do).
int steps_until_asleep(World& world, int limit) {
  for (int step = 1; step <= limit; ++step) {
    world.step();
    if (all_asleep(world)) return step;
  }
  return limit + 1;
}

// The slots of the stack's boxes, bottom first (the stack generator's order).
std::vector<uint32_t> dynamic_slots(const World& world) {
  std::vector<uint32_t> slots;
  for (uint32_t i = 0; i < world.bodies().size(); ++i) {
    if (world.bodies()[i].alive && world.bodies()[i].type == BodyType::dynamic) slots.push_back(i);
  }
  return slots;
}

BodyId id_of(const World& world, uint32_t slot) { return {slot, world.bodies()[slot].generation}; }

}  // namespace

// Golden sleep steps: a change that moves one says so in its commit.
TEST_CASE("stack20 falls asleep within 3 s: step 46 (motion), step 60 (still)", "[sleep][scene]") {
  for (auto [method, golden] : {std::pair{SleepMethod::motion, 46}, std::pair{SleepMethod::still, 60}}) {
    INFO(name_of(method));
    World world = world_with_sleep("stack20.json", method);
    const int step = steps_until_asleep(world, 180);
    CHECK(step == golden);
    CHECK(step <= 180);
    // Asleep, nothing moves and nothing changes but the step count.
    std::vector<Pose> poses;
    for (const Body& b : world.bodies()) poses.push_back(b.pose);
    const std::vector<Contact> contacts = world.contacts();
    world.step();
    for (size_t i = 0; i < poses.size(); ++i) {
      CHECK(world.bodies()[i].pose.position == poses[i].position);
      CHECK(world.bodies()[i].pose.orientation == poses[i].orientation);
    }
    CHECK(world.contacts().size() == contacts.size());
  }
}

TEST_CASE("pyramid20 and thrown fall asleep at their golden steps, thrown within 10 s", "[sleep][scene][slow]") {
  struct Case {
    const char* scene;
    SleepMethod method;
    int golden;
  };
  for (const Case& c : {Case{"pyramid20.json", SleepMethod::motion, 46}, Case{"pyramid20.json", SleepMethod::still, 60},
                        Case{"thrown.json", SleepMethod::motion, 245}, Case{"thrown.json", SleepMethod::still, 217}}) {
    INFO(c.scene << " " << name_of(c.method));
    World world = world_with_sleep(c.scene, c.method);
    const int step = steps_until_asleep(world, 600);
    CHECK(step == c.golden);
    CHECK(step <= 600);
  }
}

TEST_CASE("removing the bottom box of a sleeping stack20 wakes every box in that step, and they fall",
          "[sleep][scene]") {
  for (SleepMethod method : {SleepMethod::motion, SleepMethod::still}) {
    INFO(name_of(method));
    World world = world_with_sleep("stack20.json", method);
    REQUIRE(steps_until_asleep(world, 180) <= 180);
    const std::vector<uint32_t> boxes = dynamic_slots(world);
    REQUIRE(boxes.size() == 20);
    std::vector<Fixed> heights;
    for (uint32_t slot : boxes) heights.push_back(world.bodies()[slot].pose.position.y);
    REQUIRE(world.remove_body(id_of(world, boxes[0])));
    for (size_t i = 1; i < boxes.size(); ++i) CHECK_FALSE(world.bodies()[boxes[i]].asleep);
    world.step();
    for (size_t i = 1; i < boxes.size(); ++i) CHECK(world.bodies()[boxes[i]].pose.position.y < heights[i]);
    // The whole stack falls at once (JigLib's test of recursive
    // waking): 20 steps on, before the bottom box lands (1 m takes 27),
    // every box has dropped at least 0.45 m (a free body drops 0.545 m; one
    // woken three steps late, 0.41 m). The lower boxes drop faster than
    // free fall, up to 0.69 m, in the sleeping and the awake world alike:
    // the contacts' warm-start impulses push them down while the iterations
    // release the stack's weight.
    for (int s = 1; s < 20; ++s) world.step();
    for (size_t i = 1; i < boxes.size(); ++i) {
      INFO("box " << i);
      const Fixed drop = heights[i] - world.bodies()[boxes[i]].pose.position.y;
      CHECK(test::to_double(drop) > 0.45);
      CHECK(test::to_double(drop) < 0.75);
    }
  }
}

TEST_CASE("an impulse on one domino of a sleeping row wakes only its island, and its fall wakes the next ones",
          "[sleep][scene]") {
  for (SleepMethod method : {SleepMethod::motion, SleepMethod::still}) {
    INFO(name_of(method));
    // The dominoes scene, its first domino not tipped, every domino asleep.
    Scene scene = scene_with_sleep("dominoes.json", method);
    for (SceneBody& b : scene.bodies) {
      if (b.def.type != BodyType::dynamic) continue;
      b.def.linear_velocity = b.def.angular_velocity = Vec3{};
      b.def.asleep = true;
    }
    World world = build(scene);
    const std::vector<uint32_t> dominoes = dynamic_slots(world);
    REQUIRE(dominoes.size() == 40);
    world.step();
    REQUIRE(all_asleep(world));  // each stands on the ground: none wakes

    // Push the top of domino 20 along +x.
    const uint32_t pushed = dominoes[20];
    const Vec3 top = world.bodies()[pushed].pose.position + Vec3{Fixed{}, 0.9_fx, Fixed{}};
    world.apply_impulse(id_of(world, pushed), {100.0_fx, Fixed{}, Fixed{}}, top);
    for (size_t i = 0; i < dominoes.size(); ++i) CHECK(world.bodies()[dominoes[i]].asleep == (i != 20));

    // It falls onto domino 21 and wakes it, and so on down the row; the
    // dominoes behind it never wake.
    int steps = 0;
    while (steps < 600 && world.bodies()[dominoes[39]].asleep) {
      world.step();
      ++steps;
      for (size_t i = 0; i < 20; ++i) REQUIRE(world.bodies()[dominoes[i]].asleep);
    }
    CHECK(steps < 600);
  }
}

TEST_CASE("a body created asleep in the air wakes in the first step and falls", "[sleep]") {
  for (SleepMethod method : {SleepMethod::motion, SleepMethod::still}) {
    INFO(name_of(method));
    Scene scene = scene_with_sleep("stack20.json", method);
    SceneBody floating = scene.bodies.back();
    floating.def.pose.position = {10.0_fx, 5.0_fx, Fixed{}};
    floating.def.asleep = true;
    scene.bodies.push_back(floating);
    World world = build(scene);
    const uint32_t slot = static_cast<uint32_t>(world.bodies().size() - 1);
    REQUIRE(world.bodies()[slot].asleep);
    world.step();
    CHECK_FALSE(world.bodies()[slot].asleep);
    CHECK(world.bodies()[slot].pose.position.y < 5.0_fx);
  }
}

TEST_CASE("a box spawned onto a sleeping stack wakes it, and the stack sleeps again with the box on top",
          "[sleep][scene]") {
  for (SleepMethod method : {SleepMethod::motion, SleepMethod::still}) {
    INFO(name_of(method));
    Scene scene = scene_with_sleep("stack20.json", method);
    World world = build(scene);
    REQUIRE(steps_until_asleep(world, 180) <= 180);
    // At rest, exactly on the top face (y = 20): only the spawn rule wakes
    // the stack (the motion method's touch rule needs v.v + w.w > 2 epsilon).
    BodyDef box = scene.bodies.back().def;
    box.pose.position = {Fixed{}, 20.5_fx, Fixed{}};
    REQUIRE(world.create_body(box).ok());
    CHECK(world.stats().sleeping_bodies == 0);
    CHECK(steps_until_asleep(world, 300) <= 300);
    CHECK(abs(world.bodies().back().pose.position.y - 20.5_fx) < 0.01_fx);
  }
}

TEST_CASE("a fast body wakes the sleeping stack it hits (motion method)", "[sleep][scene]") {
  World world = world_with_sleep("stack20.json", SleepMethod::motion);
  REQUIRE(steps_until_asleep(world, 180) <= 180);
  BodyDef ball;
  ball.pose.position = {-3.0_fx, 19.5_fx, Fixed{}};
  ball.linear_velocity = {10.0_fx, Fixed{}, Fixed{}};
  ball.shapes.push_back({ShapeType::sphere, {}, 0.3_fx, {}, {}});
  REQUIRE(world.create_body(ball).ok());
  int steps = 0;
  while (steps < 60 && world.stats().sleeping_bodies == 20) {
    world.step();
    ++steps;
  }
  CHECK(world.stats().sleeping_bodies == 0);  // the island wakes as one
  CHECK(steps < 30);
}

TEST_CASE("snapshot in the middle of a sleep countdown: the restored world continues bit-identically",
          "[sleep][snapshot]") {
  for (SleepMethod method : {SleepMethod::motion, SleepMethod::still}) {
    INFO(name_of(method));
    World world = world_with_sleep("stack20.json", method);
    // Mid-countdown: sleepy for some steps, the still method's ramp under way.
    for (int s = 0; s < 40; ++s) world.step();
    const Body& top = world.bodies()[dynamic_slots(world).back()];
    REQUIRE_FALSE(top.asleep);
    REQUIRE(top.sleepy_steps > 0);
    const std::vector<uint8_t> image = snapshot(world);
    World copy;
    REQUIRE(restore(image, copy).ok());
    for (int s = 0; s < 40; ++s) {
      world.step();
      copy.step();
      REQUIRE(state_hash(copy) == state_hash(world));
    }
    CHECK(all_asleep(world));
  }
}



TEST_CASE("sleep keys in a scene: read, and refused with the path and the reason", "[sleep][scene]") {
  auto parse = [](const std::string& settings, const std::string& body_extra) {
    return parse_scene(R"({"format": "bitstep-scene", "version": 1, "settings": {)" + settings +
                           R"(}, "bodies": [{"position": [0, 0.5, 0], )" + body_extra +
                           R"("shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}]}]})",
                       "f.json");
  };
  auto error_of = [&](const std::string& settings, const std::string& body_extra) {
    const auto result = parse(settings, body_extra);
    if (!result.ok()) return result.error().message();
    return std::string("no error");
  };
  const auto good = parse(R"("sleep": "still", "sleep_time": 2, "sleep_linear_tolerance": 0.01)", R"("asleep": true, )");
  REQUIRE(good.ok());
  const Scene& scene = good.value();
  CHECK(scene.settings.sleep_method == SleepMethod::still);
  CHECK(scene.settings.sleep_time == 2.0_fx);
  CHECK(scene.settings.sleep_linear_tolerance == 0.01_fx);
  CHECK(scene.bodies[0].def.asleep);

  CHECK(error_of(R"("sleep": "doze")", "") == R"(f.json: $.settings.sleep: expected "off", "motion" or "still", got "doze")");
  CHECK(error_of(R"("sleep_time": 5000)", "").starts_with("f.json: $.settings.sleep_time: outside"));
  CHECK(error_of("", R"("asleep": true, "velocity": [1, 0, 0], )") ==
        "f.json: $.bodies[0].asleep: a sleeping body has no velocity");
}
