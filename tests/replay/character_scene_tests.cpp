// Characters in scenes, replays and states: the "characters" key and its
// refusals, "move", "add_character" and "remove_character" inputs, the
// course's golden run, and a character saved mid-jump and restored
// continuing bit for bit.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>

#include "replay/bitstep.h"
#include "replay/replay.h"
#include "replay/scene.h"
#include "replay/snapshot.h"
#include "replay/state_hash.h"
#include "tests/replay/test_scenes.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::to_double;

namespace {

std::string scene_with(const std::string& characters) {
  return R"({"format": "bitstep-scene", "version": 1, "bodies": [{"name": "ground", "type": "static",
    "position": [0, -1, 0], "shapes": [{"type": "box", "half_extents": [10, 1, 10]}]}], "characters": )" +
         characters + "}";
}

std::string error_of(const std::string& text) {
  const auto result = parse_scene(text, "f.json");
  return result.ok() ? "no error" : result.error().message();
}

std::string replay_error_of(const std::string& inputs) {
  const std::string text = R"({"format": "bitstep-replay", "version": 1, "engine": "test", "scene": )" +
                           scene_with(R"([{"name": "hero", "position": [0, 0.91, 0]}])") +
                           R"(, "scene_hash": "0000000000000000", "steps": 10, "inputs": )" + inputs + "}";
  const auto result = parse_replay(text, "r.json", false);
  return result.ok() ? "no error" : result.error().message();
}

Replay course() {
  auto loaded = load_replay_file(test::scenes_dir + "/course.replay.json", true);
  REQUIRE(loaded.ok());
  return std::move(loaded.value());
}

}  // namespace

TEST_CASE("character scenes: a character in, its definition out, and refusals that name their place",
          "[scene][character]") {
  const auto scene = parse_scene(
      scene_with(R"([{"name": "hero", "position": [1, 0.91, 2], "radius": 0.4, "max_slope": 60, "step_height": 0.5,
                      "facing": [1, 0, 1], "collides_with": [0, 3]}])"),
      "f.json");
  REQUIRE(scene.ok());
  REQUIRE(scene.value().characters.size() == 1);
  const CharacterDef& def = scene.value().characters[0].def;
  CHECK(def.radius == 0.4_fx);
  CHECK(std::abs(to_double(def.max_slope_cos) - 0.5) < 1e-9);
  CHECK(def.step_height == 0.5_fx);
  CHECK(std::abs(to_double(def.facing.x) - std::sqrt(0.5)) < 1e-9);
  CHECK(def.collides_with == 9u);
  CHECK(error_of(scene_with(R"([{"name": "a", "position": [0, 1, 0], "radius": 9}])")) ==
        "f.json: $.characters[0].radius: outside 0.05..5 m");
  CHECK(error_of(scene_with(R"([{"name": "a", "position": [0, 1, 0], "step_height": 1}])")) ==
        "f.json: $.characters[0].step_height: outside 0 m..its half height");
  CHECK(error_of(scene_with(R"([{"name": "a", "position": [0, 1, 0], "max_slope": 90}])")) ==
        "f.json: $.characters[0].max_slope: outside 0..89 degrees");
  CHECK(error_of(scene_with(R"([{"name": "a", "position": [0, 1, 0], "facing": [0, 1, 0]}])")) ==
        "f.json: $.characters[0].facing: not a level direction");
  CHECK(error_of(scene_with(R"([{"name": "a", "position": [0, 1, 0]}, {"name": "a", "position": [2, 1, 0]}])")) ==
        "f.json: $.characters[1].name: duplicate character name \"a\"");
  CHECK(error_of(scene_with(R"([{"name": "a", "position": [0, 1, 0], "speed": 3}])"))
            .rfind("f.json: $.characters[0].speed: unknown key", 0) == 0);
  CHECK(error_of(scene_with(R"([{"position": [0, 1, 0]}])")) == "f.json: $.characters[0]: missing key \"name\"");
}

TEST_CASE("move inputs: a character by name, a level velocity and a jump", "[replay][character]") {
  CHECK(replay_error_of(R"([{"step": 2, "type": "move", "character": "hero", "velocity": [1, -2], "jump": true}])") ==
        "no error");
  CHECK(replay_error_of(R"([{"step": 2, "type": "move", "character": "villain", "velocity": [1, 0]}])") ==
        "r.json: $.inputs[0].character: no character named \"villain\" in the scene or added by an add_character "
        "before it");
  CHECK(replay_error_of(R"([{"step": 2, "type": "move", "character": "hero", "velocity": [1, 0, 0]}])") ==
        "r.json: $.inputs[0].velocity: expected [x, z] in m/s");
  CHECK(replay_error_of(R"([{"step": 2, "type": "move", "character": "hero", "velocity": [101, 0]}])")
            .rfind("r.json: $.inputs[0].velocity[0]: ", 0) == 0);
  CHECK(replay_error_of(R"([{"step": 2, "type": "move", "character": "hero"}])") ==
        "r.json: $.inputs[0]: missing key \"velocity\"");
}

TEST_CASE("add_character and remove_character inputs: a character joins, walks and leaves", "[replay][character]") {
  const std::string added = R"({"step": 5, "type": "add_character", "character": {"name": "late",
                                "position": [3, 0.86, 0], "radius": 0.25}})";
  CHECK(replay_error_of("[" + added + R"(, {"step": 6, "type": "move", "character": "late", "velocity": [1, 0]},
                                          {"step": 9, "type": "remove_character", "character": "late"}])") ==
        "no error");
  CHECK(replay_error_of(R"([{"step": 4, "type": "move", "character": "late", "velocity": [1, 0]}, )" + added + "]") ==
        "r.json: $.inputs[0].character: no character named \"late\" in the scene or added by an add_character "
        "before it");
  CHECK(replay_error_of(
            R"([{"step": 5, "type": "add_character", "character": {"name": "hero", "position": [3, 1, 0]}}])") ==
        "r.json: $.inputs[0].character.name: duplicate character name \"hero\"");
  CHECK(replay_error_of(R"([{"step": 5, "type": "add_character", "character": {"name": "b", "position": [3, 1, 0],
                              "radius": 9}}])") == "r.json: $.inputs[0].character.radius: outside 0.05..5 m");
  CHECK(replay_error_of(R"([{"step": 5, "type": "remove_character", "character": "nobody"}])") ==
        "r.json: $.inputs[0].character: no character named \"nobody\" in the scene or added by an add_character "
        "before it");

  // Joins at step 5, walks 1 m/s from step 6, leaves at step 60.
  const std::string text = R"({"format": "bitstep-replay", "version": 1, "engine": "test", "scene": )" +
                           scene_with(R"([{"name": "hero", "position": [0, 0.91, 0]}])") +
                           R"(, "scene_hash": "0000000000000000", "steps": 90, "inputs": [)" + added +
                           R"(, {"step": 6, "type": "move", "character": "late", "velocity": [1, 0]},
                              {"step": 60, "type": "remove_character", "character": "late"}]})";
  const auto replay = parse_replay(text, "r.json", false);
  REQUIRE(replay.ok());
  World world(replay->scene.settings);
  REQUIRE(build_world(replay->scene, world).ok());
  InputRun run(world);
  std::vector<uint64_t> first;
  std::vector<uint8_t> at_30;
  for (int64_t step = 1; step <= 90; ++step) {
    apply_inputs(world, replay->inputs, step, run);
    world.step();
    first.push_back(state_hash(world));
    if (step == 30) at_30 = snapshot(world);
    if (step == 5) {
      REQUIRE(world.characters().size() == 2);
      CHECK(world.characters()[1].ground == GroundState::on_ground);  // it stands where it is created
    }
    if (step == 59) {
      // 54 steps at 1 m/s: 0.9 m.
      INFO("late at x " << to_double(world.characters()[1].position.x));
      CHECK(std::abs(to_double(world.characters()[1].position.x) - 3.9) < 0.001);
      CHECK(world.characters()[1].alive);
    }
  }
  CHECK_FALSE(world.characters()[1].alive);
  CHECK(world.characters()[0].alive);
  // Restored at step 30 (the added character in the state), the run
  // continues on the same chain.
  World again(replay->scene.settings);
  REQUIRE(build_world(replay->scene, again).ok());
  REQUIRE(restore(at_30, again).ok());
  InputRun later(again);
  later.next = static_cast<size_t>(
      std::find_if(replay->inputs.begin(), replay->inputs.end(), [](const Input& in) { return in.step > 30; }) -
      replay->inputs.begin());
  for (int64_t step = 31; step <= 90; ++step) {
    apply_inputs(again, replay->inputs, step, later);
    again.step();
    REQUIRE(state_hash(again) == first[static_cast<size_t>(step - 1)]);
  }
}

TEST_CASE("C API: a character added and removed by name", "[capi][character]") {
  bitstep_simulation* sim = nullptr;
  char error[256] = "";
  const std::string path = test::scenes_dir + "/course.json";
  REQUIRE(bitstep_create_from_file(path.c_str(), &sim, error, sizeof error) == BITSTEP_OK);
  REQUIRE(bitstep_add_character(sim, R"({"name": "guest", "position": [-4, 0.91, -4]})") == BITSTEP_OK);
  bitstep_character_state state{};
  REQUIRE(bitstep_get_character(sim, "guest", &state) == BITSTEP_OK);
  CHECK(state.ground == BITSTEP_ON_GROUND);
  REQUIRE(bitstep_move_character(sim, "guest", {Fixed::one().raw(), 0, 0}, 0) == BITSTEP_OK);
  for (int i = 0; i < 30; ++i) REQUIRE(bitstep_step(sim) == BITSTEP_OK);
  REQUIRE(bitstep_get_character(sim, "guest", &state) == BITSTEP_OK);
  CHECK(std::abs(to_double(Fixed::from_raw(state.position.x)) + 3.5) < 0.001);  // 30 steps at 1 m/s
  CHECK(bitstep_add_character(sim, R"({"name": "guest", "position": [4, 0.91, 4]})") != BITSTEP_OK);
  CHECK(std::string(bitstep_last_error(sim)) == "add_character: name: a live character is named \"guest\"");
  CHECK(bitstep_add_character(sim, R"({"name": "x", "position": [4, 0.91, 4], "radius": 9})") != BITSTEP_OK);
  CHECK(std::string(bitstep_last_error(sim)) == "add_character: $.radius: outside 0.05..5 m");
  REQUIRE(bitstep_remove_character(sim, "guest") == BITSTEP_OK);
  CHECK(bitstep_get_character(sim, "guest", &state) == BITSTEP_NOT_FOUND);
  CHECK(bitstep_remove_character(sim, "guest") == BITSTEP_NOT_FOUND);
  CHECK(bitstep_add_character(sim, nullptr) == BITSTEP_NULL_ARGUMENT);
  // The name is free again once its character has left.
  CHECK(bitstep_add_character(sim, R"({"name": "guest", "position": [4, 0.91, 4]})") == BITSTEP_OK);
  bitstep_destroy(sim);
}

TEST_CASE("course.replay.json: the walker climbs the stairs, the pusher rides the turntable", "[replay][character]") {
  const Replay replay = course();
  World world(replay.scene.settings);
  REQUIRE(build_world(replay.scene, world).ok());
  InputRun run(world);
  const auto feet = [&](size_t k) {
    const Character& c = world.characters()[k];
    return to_double(c.position.y - c.def.radius - c.def.half_height);
  };
  Vec3 on_table_at_600;
  const BodyId table{10, 0};
  REQUIRE(replay.scene.bodies[10].name == "turntable");
  for (int64_t step = 1; step <= replay.steps; ++step) {
    apply_inputs(world, replay.inputs, step, run);
    world.step();
    if (step == 200) {
      // On the landing (its top 1.2 m up) after six 0.2 m stairs.
      CHECK(std::abs(feet(0) - 1.2) < 0.02);
      CHECK(world.characters()[0].ground == GroundState::on_ground);
    }
    const Pose& p = world.body(table).pose;
    if (step == 600) on_table_at_600 = rotate_inverse(p.orientation, world.characters()[1].position - p.position);
    if (step == replay.steps) {
      // The pusher stood still on the turning table for 2 s: where it stands on the table has not moved.
      const Vec3 now = rotate_inverse(p.orientation, world.characters()[1].position - p.position);
      CHECK(to_double(length(now - on_table_at_600)) < 0.005);
      CHECK(world.characters()[1].ground_body == table);
    }
  }
}

TEST_CASE("character worlds: saved mid-jump and restored, the chain is the same", "[snapshot][character]") {
  const Replay replay = course();
  World straight(replay.scene.settings);
  REQUIRE(build_world(replay.scene, straight).ok());
  InputRun run(straight);
  std::vector<uint8_t> image;
  for (int64_t step = 1; step <= 310; ++step) {
    apply_inputs(straight, replay.inputs, step, run);
    straight.step();
  }
  REQUIRE(straight.characters()[0].ground == GroundState::in_air);  // jumped at 300
  image = snapshot(straight);
  World restored;
  REQUIRE(restore(image, restored).ok());
  CHECK(snapshot(restored) == image);
  InputRun restored_run(restored);
  for (int64_t step = 311; step <= 420; ++step) {
    apply_inputs(straight, replay.inputs, step, run);
    apply_inputs(restored, replay.inputs, step, restored_run);
    straight.step();
    restored.step();
    REQUIRE(state_hash(restored) == state_hash(straight));
  }
}

TEST_CASE("C API: characters moved by bitstep_move_character give the golden chain", "[capi][character]") {
  const Replay replay = course();
  bitstep_simulation* sim = nullptr;
  char error[256] = "";
  const std::string path = test::scenes_dir + "/course.json";
  REQUIRE(bitstep_create_from_file(path.c_str(), &sim, error, sizeof error) == BITSTEP_OK);
  // The replay's move inputs, made as calls: velocity [x, z] and jump.
  const auto raw = [](Fixed f) { return f.raw(); };
  for (int64_t step = 1; step <= replay.steps; ++step) {
    for (const Input& input : replay.inputs) {
      if (input.step != step) continue;
      REQUIRE(input.kind == Input::Kind::move);
      const std::string& name = replay.scene.characters[input.character].name;
      const bitstep_vec3 v{raw(input.moving.velocity.x), 0, raw(input.moving.velocity.z)};
      REQUIRE(bitstep_move_character(sim, name.c_str(), v, input.moving.jump ? 1 : 0) == BITSTEP_OK);
    }
    REQUIRE(bitstep_step(sim) == BITSTEP_OK);
    REQUIRE(bitstep_hash(sim) == replay.hashes[static_cast<size_t>(step - 1)]);
  }
  bitstep_character_state state{};
  REQUIRE(bitstep_get_character(sim, "pusher", &state) == BITSTEP_OK);
  CHECK(state.ground == BITSTEP_ON_GROUND);
  CHECK(state.ground_body.index == 10u);  // the turntable
  CHECK(bitstep_get_character(sim, "nobody", &state) == BITSTEP_NOT_FOUND);
  CHECK(std::string(bitstep_last_error(sim)) == "no character named \"nobody\"");
  CHECK(bitstep_move_character(sim, "walker", {Fixed::from_int(101).raw(), 0, 0}, 0) == BITSTEP_INVALID);
  CHECK(std::string(bitstep_last_error(sim)).rfind("move: velocity.x: outside", 0) == 0);
  CHECK(bitstep_move_character(sim, nullptr, {}, 0) == BITSTEP_NULL_ARGUMENT);
  CHECK(bitstep_get_character(sim, "walker", nullptr) == BITSTEP_NULL_ARGUMENT);
  bitstep_destroy(sim);
}
