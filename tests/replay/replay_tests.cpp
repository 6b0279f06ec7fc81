// Input replays: the golden replays in scenes/ reproduce their hash chains
// step by step, and a damaged or malformed replay is refused or reported at
// the step where it differs.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <variant>

#include "replay/generators.h"
#include "replay/replay.h"
#include "replay/state_dump.h"
#include "replay/state_hash.h"
#include "tests/replay/golden_replays.h"
#include "tests/replay/test_scenes.h"
#include "tests/test_support.h"

using namespace bitstep;

namespace {

using bitstep::test::golden_replays;
using bitstep::test::left_to_optimised_builds;
using bitstep::test::replay_chain;
using bitstep::test::replays_of_this_build;
using bitstep::test::scenes_dir;
using bitstep::test::world_of;

// A temporary file with the given text, next to a copy of bounce.json (so
// that "scene": "bounce.json" resolves), removed at the end of the test.
struct TempFile {
  std::filesystem::path folder;
  std::string path;
  TempFile(const std::string& name, const std::string& text)
      : folder(std::filesystem::temp_directory_path() / ("bitstep_replay_tests_" + name)),
        path((folder / name).string()) {
    std::filesystem::create_directories(folder);
    std::filesystem::copy_file(scenes_dir + "/bounce.json", folder / "bounce.json",
                               std::filesystem::copy_options::overwrite_existing);
    std::ofstream(path, std::ios::binary) << text;
  }
  ~TempFile() {
    std::error_code ignored;
    std::filesystem::remove_all(folder, ignored);
  }
};

std::string read_all(const std::string& path) {
  Result<std::string> text = read_text_file(path);
  REQUIRE(text.ok());
  return std::move(text).value();
}

std::string error_of(const std::string& path) {
  auto loaded = load_replay_file(path, true);
  REQUIRE(!loaded.ok());
  return loaded.error().message();
}

}  // namespace


// The broadphase reuses last step's pairs when no body's bounds or margin
// changed by a bit (core/broadphase.h), the narrowphase last step's result
// for a shape pair whose poses and margin did not (core/contact_update.h),
// the solver a manifold's rows whose inputs did not (core/row_cache.h); the
// recorded chains were made with all three on. Off, every replay must give
// the same hash at every step.
TEST_CASE("every golden replay gives the same chain with the pairs', narrowphase's and rows' reuse off",
          "[replay][golden]") {
  const std::vector<std::string> paths = replays_of_this_build();
  for (const std::string& path : paths) {
    INFO(path);
    auto loaded = load_replay_file(path, true);
    if (!loaded.ok()) FAIL(loaded.error().message());
    const Replay& replay = loaded.value();
    uint64_t scene_hash = 0;
    CHECK(first_divergent_step(replay.hashes, replay_chain(replay, scene_hash, false)) == 0);
  }
}

TEST_CASE("every golden replay reproduces its hash chain at every step", "[replay][golden]") {
  const std::vector<std::string> paths = golden_replays();
  REQUIRE(paths.size() >= 13);  // one per shipped scene
  for (const std::string& path : paths) {
    if (left_to_optimised_builds(path)) continue;
    INFO(path);
    auto loaded = load_replay_file(path, true);
    if (!loaded.ok()) FAIL(loaded.error().message());
    const Replay& replay = loaded.value();
    CHECK_FALSE(replay.inputs.empty());
    uint64_t scene_hash = 0;
    const std::vector<uint64_t> hashes = replay_chain(replay, scene_hash);
    CHECK(scene_hash == replay.scene_hash);
    CHECK(first_divergent_step(replay.hashes, hashes) == 0);
  }
}

TEST_CASE("a changed hash is reported at its step", "[replay]") {
  std::string text = read_all(scenes_dir + "/bounce.replay.json");
  auto loaded = load_replay_file(scenes_dir + "/bounce.replay.json", true);
  REQUIRE(loaded.ok());
  const Replay& replay = loaded.value();
  // Flip one hex digit of step 77's hash.
  char hash77[17];
  for (int i = 15, shift = 0; i >= 0; --i, shift += 4) hash77[i] = "0123456789abcdef"[(replay.hashes[76] >> shift) & 15];
  hash77[16] = '\0';
  const size_t at = text.find(hash77);
  REQUIRE(at != std::string::npos);
  text[at] = text[at] == '0' ? '1' : '0';
  const TempFile damaged("damaged_test.replay.json", text);
  auto reloaded = load_replay_file(damaged.path, true);
  REQUIRE(reloaded.ok());
  uint64_t scene_hash = 0;
  CHECK(first_divergent_step(reloaded.value().hashes, replay_chain(reloaded.value(), scene_hash)) == 77);
}

TEST_CASE("malformed replays are refused with the file, the JSON path and the reason", "[replay]") {
  const std::string head = "{\"format\": \"bitstep-replay\", \"version\": 1, \"scene\": \"bounce.json\", ";
  const std::string hash = "\"0000000000000000\"";
  struct Case {
    std::string text, expected;
  };
  const Case cases[] = {
      {head + "\"scene_hash\": " + hash + ", \"steps\": 1, \"hashes\": [" + hash + "], \"extra\": 1}",
       "$.extra: unknown key"},
      {head + "\"scene_hash\": " + hash + ", \"steps\": 2, \"hashes\": [" + hash + "]}", "$.hashes: 1 hashes for 2 steps"},
      {head + "\"scene_hash\": " + hash + ", \"steps\": 1}", "missing key \"hashes\""},
      {head + "\"scene_hash\": \"12\", \"steps\": 0, \"hashes\": []}", "$.scene_hash: expected 16 hex digits"},
      {head + "\"scene_hash\": " + hash + ", \"steps\": 1, \"hashes\": [" + hash +
           "], \"inputs\": [{\"step\": 2, \"type\": \"wake\", \"body\": 1}]}",
       "$.inputs[0].step: after the last step (1)"},
      {head + "\"scene_hash\": " + hash + ", \"steps\": 1, \"hashes\": [" + hash +
           "], \"inputs\": [{\"step\": 1, \"type\": \"remove\", \"body\": \"nobody\"}]}",
       "$.inputs[0].body: no body named \"nobody\""},
      {head + "\"scene_hash\": " + hash + ", \"steps\": 1, \"hashes\": [" + hash +
           "], \"inputs\": [{\"step\": 1, \"type\": \"impulse\", \"body\": 1, \"impulse\": [1e9, 0, 0], \"point\": [0, 0, 0]}]}",
       "$.inputs[0].impulse"},
      {head + "\"scene_hash\": " + hash + ", \"steps\": 1, \"hashes\": [" + hash +
           "], \"inputs\": [{\"step\": 1, \"type\": \"drive\", \"car\": \"car.0\", \"throttle\": 1}]}",
       "$.inputs[0].car: no car named \"car.0\" in the scene"},
      {"{\"format\": \"bitstep-scene\", \"version\": 1}", "$.format: expected \"bitstep-replay\""},
      {"{\"format\": \"bitstep-replay\", \"version\": 2}", "$.version: unsupported version 2"},
      {"{\"format\": \"bitstep-replay\", \"version\": 1, \"scene\": \"missing.json\"}", "missing.json: cannot read"},
      {"{\"format\": ", "byte"},
  };
  for (const Case& c : cases) {
    INFO(c.text);
    const TempFile file("malformed_test.replay.json", c.text);
    const std::string message = error_of(file.path);
    INFO(message);
    CHECK(message.find(c.expected) != std::string::npos);
    CHECK(message.find('\n') == std::string::npos);
  }
}

TEST_CASE("10,000 inputs naming bodies of a 10,000-body scene are read, each to its slot", "[replay][json]") {
  // A scan of the bodies per input made this n^2.
  StackParams stack;
  stack.count = 10000;
  Scene scene;
  scene.bodies = generate_stack(stack);
  std::string text = "{\"inputs\": [";
  for (int i = stack.count - 1; i >= 0; --i) {
    text.append(i == stack.count - 1 ? "" : ", ").append(R"({"step": 1, "type": "wake", "body": "stack.)");
    text.append(std::to_string(i)).append("\"}");
  }
  const TempFile file("names_test.json", text + "]}");
  auto loaded = load_inputs_file(file.path, scene);
  if (!loaded.ok()) FAIL(loaded.error().message());
  const std::vector<Input>& inputs = loaded.value().inputs;
  REQUIRE(inputs.size() == 10000);
  CHECK(inputs.front().body == 9999);
  CHECK(inputs.back().body == 0);
}

TEST_CASE("hashing a world does not change its future", "[replay]") {
  World hashed = world_of("thrown.json");
  World plain = world_of("thrown.json");
  uint64_t fold = 0;
  for (int i = 0; i < 90; ++i) {
    hashed.step();
    fold ^= state_hash(hashed);
    plain.step();
  }
  CHECK(fold != 0);
  CHECK(state_hash(hashed) == state_hash(plain));
}

TEST_CASE("diff names the first body and field where two states differ", "[replay][diff]") {
  World a = world_of("stack20.json");
  World b = world_of("stack20.json");
  for (int i = 0; i < 10; ++i) {
    a.step();
    b.step();
  }
  CHECK_FALSE(diff_dumps(dump_state(a), dump_state(b)).value().has_value());
  b.apply_impulse(BodyId{7, 0}, Vec3{Fixed{}, 50.0_fx, Fixed{}}, b.body(BodyId{7, 0}).pose.position);
  const Result<DumpDifference> d = diff_dumps(dump_state(a), dump_state(b));
  REQUIRE(d.ok());
  REQUIRE(d->has_value());
  INFO(**d);
  CHECK((*d)->rfind("$.bodies[7].linear_velocity[1]: ", 0) == 0);
  CHECK(diff_dumps("{}", dump_state(a)).error().message() == "first dump: not a bitstep-state dump");
}

TEST_CASE("independence: key order and number spelling do not change the chain, a far-away body changes no other",
          "[replay][independence]") {
  const std::string one =
      R"({"format": "bitstep-scene", "version": 1, "settings": {"dt": "1/60", "velocity_iterations": 10},
          "materials": {"m": {"static_friction": 0.5, "dynamic_friction": 0.5, "restitution": 0}},
          "bodies": [{"type": "static", "position": [0, -1, 0], "shapes": [{"type": "box", "half_extents": [50, 1, 50]}]},
                     {"position": [0, 0.5, 0], "material": "m", "shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}]},
                     {"position": [0.25, 1.5, 0], "velocity": [0, 0, 0.5], "material": "m",
                      "shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}]}]})";
  const std::string other =
      R"({"version": 1, "format": "bitstep-scene",
          "bodies": [{"shapes": [{"half_extents": [5e1, 1, 50.0], "type": "box"}], "position": [0, -1.0, 0], "type": "static"},
                     {"material": "m", "position": ["0", "1/2", 0], "shapes": [{"type": "box", "half_extents": [0.5, 5e-1, "1/2"]}]},
                     {"shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}], "material": "m",
                      "velocity": [0, 0.0, "raw:80000000"], "position": ["1/4", 1.5, 0]}],
          "materials": {"m": {"restitution": 0, "dynamic_friction": "1/2", "static_friction": 0.50}},
          "settings": {"velocity_iterations": 10, "dt": "0.0166666666/1.0000000000"}})";
  auto chain = [](const std::string& text, bool far_body, std::vector<std::string>& dumps) {
    auto parsed = parse_scene(text, "inline.json");
    if (!parsed.ok()) FAIL(parsed.error().message());
    Scene scene = parsed.value();
    if (far_body) {
      SceneBody far = scene.bodies[1];
      far.def.pose.position = {1000.0_fx, 500.0_fx, 1000.0_fx};
      scene.bodies.push_back(far);
    }
    World world(scene.settings);
    REQUIRE(build_world(scene, world).ok());
    std::vector<uint64_t> hashes;
    for (int i = 0; i < 120; ++i) {
      world.step();
      hashes.push_back(state_hash(world));
      std::string state = dump_state(world);
      // The first three bodies and every contact: cut the far body's entry.
      const size_t far_entry = state.find("{\"slot\": 3,");
      if (far_entry != std::string::npos) state.erase(far_entry, state.find('\n', far_entry) - far_entry);
      dumps.push_back(state);
    }
    return hashes;
  };
  std::vector<std::string> dumps_one, dumps_other, dumps_far;
  const std::vector<uint64_t> a = chain(one, false, dumps_one);
  const std::vector<uint64_t> b = chain(other, false, dumps_other);
  CHECK(first_divergent_step(a, b) == 0);
  chain(one, true, dumps_far);
  for (size_t i = 0; i < dumps_one.size(); ++i) {
    INFO("step " << i + 1);
    // Equal but for the far body's entry (and the separator before it).
    std::string without = dumps_far[i];
    const size_t comma = without.find(",\n    \n  ]");
    if (comma != std::string::npos) without.erase(comma, 6);
    REQUIRE(without == dumps_one[i]);
  }
}

TEST_CASE("a replay may carry its scene inline", "[replay]") {
  auto golden = load_replay_file(scenes_dir + "/bounce.replay.json", true);
  REQUIRE(golden.ok());
  Replay replay = golden.value();
  // The first 30 steps come before the golden replay's first input.
  replay.steps = 30;
  replay.hashes.resize(30);
  replay.inputs.clear();
  replay.inline_scene = read_all(scenes_dir + "/bounce.json");
  const TempFile file("inline_test.replay.json", replay_json(replay, "test"));
  auto loaded = load_replay_file(file.path, true);
  if (!loaded.ok()) FAIL(loaded.error().message());
  CHECK(verify_replay(loaded.value()).ok());

  std::string broken = read_all(file.path);
  const std::string radius = "\"half_extents\": [0.5, 0.5, 0.5]";
  const size_t at = broken.find(radius);
  REQUIRE(at != std::string::npos);
  broken.replace(at, radius.size(), "\"half_extents\": [0.5, 0.5, 500]");
  const TempFile bad("inline_bad_test.replay.json", broken);
  const std::string message = error_of(bad.path);
  INFO(message);
  CHECK(message.find("$.scene.bodies[1].shapes[0].half_extents") != std::string::npos);
}

namespace {

// A replay of the first 30 steps of bounce.json with `settings` (a JSON
// member, or empty) recorded: read without hashes, then run.
Replay record_bounce(const std::string& name, const std::string& settings) {
  const TempFile file(name, "{\"format\": \"bitstep-replay\", \"version\": 1, \"scene\": \"bounce.json\", " + settings +
                                "\"scene_hash\": \"0000000000000000\", \"steps\": 30}");
  auto loaded = load_replay_file(file.path, false);
  if (!loaded.ok()) FAIL(loaded.error().message());
  Replay replay = loaded.value();
  replay.hashes = replay_chain(replay, replay.scene_hash);
  return replay;
}

}  // namespace

TEST_CASE("a replay's settings override the scene's and verify", "[replay][settings]") {
  const Replay plain = record_bounce("plain_settings_test.replay.json", "");
  const Replay fewer = record_bounce("fewer_settings_test.replay.json", "\"settings\": {\"velocity_iterations\": 3}, ");
  CHECK(plain.settings_override.empty());
  CHECK(fewer.settings_override == "{\"velocity_iterations\": 3}");
  auto scene = load_scene_file(scenes_dir + "/bounce.json");
  REQUIRE(scene.ok());
  const Settings& scene_settings = scene.value().settings;
  REQUIRE(scene_settings.velocity_iterations != 3);
  CHECK(plain.scene.settings.velocity_iterations == scene_settings.velocity_iterations);
  // Over the scene's settings: the keys the override does not name stay the scene's.
  CHECK(fewer.scene.settings.restitution_threshold == scene_settings.restitution_threshold);
  CHECK(fewer.scene_hash != plain.scene_hash);  // the hash covers the settings
  CHECK(replay_json(plain, "test").find("\"settings\"") == std::string::npos);

  const TempFile file("fewer_verify_test.replay.json", replay_json(fewer, "test"));
  auto loaded = load_replay_file(file.path, true);
  if (!loaded.ok()) FAIL(loaded.error().message());
  const Replay& replay = loaded.value();
  CHECK(verify_replay(replay).ok());
  World world(replay.scene.settings);
  REQUIRE(build_world(replay.scene, world).ok());
  CHECK(world.settings().velocity_iterations == 3);
}

TEST_CASE("a replay with a bad settings override is refused with its JSON path", "[replay][settings]") {
  const std::string head = "{\"format\": \"bitstep-replay\", \"version\": 1, \"scene\": \"bounce.json\", ";
  const std::string tail = ", \"scene_hash\": \"0000000000000000\", \"steps\": 0, \"hashes\": []}";
  struct Case {
    std::string settings, expected;
  };
  const Case cases[] = {
      {"{\"no_such_key\": 1}", "$.settings.no_such_key: unknown key"},
      {"{\"sleep\": \"sometimes\"}", "$.settings.sleep"},
      {"{\"velocity_iterations\": 0}", "$.settings.velocity_iterations"},
      {"3", "$.settings: expected an object"},
  };
  for (const Case& c : cases) {
    INFO(c.settings);
    const TempFile file("bad_settings_test.replay.json", head + "\"settings\": " + c.settings + tail);
    const std::string message = error_of(file.path);
    INFO(message);
    CHECK(message.find(file.path + ": " + c.expected) == 0);
    CHECK(message.find('\n') == std::string::npos);
  }
  // The command line's --settings: the same reader, the same kind of message.
  Settings settings;
  auto applied = apply_settings_text("{\"velocity_iterations\": 4, \"sleep\": 1}", "--settings", settings);
  REQUIRE(!applied.ok());
  CHECK(applied.error().message().rfind("--settings: $.sleep: ", 0) == 0);
  CHECK(settings.velocity_iterations == Settings{}.velocity_iterations);  // untouched on error
  applied = apply_settings_text("{\"velocity_iterations\":4}", "--settings", settings);
  REQUIRE(applied.ok());
  CHECK(applied.value() == "{\"velocity_iterations\": 4}");
  CHECK(settings.velocity_iterations == 4);
}

TEST_CASE("a settings override survives writing and reading the replay", "[replay][settings]") {
  const Replay replay = record_bounce("round_trip_settings_test.replay.json",
                                      "\"settings\": {\"sleep\": \"still\", \"gravity\": [0, \"-981/100\", 0]}, ");
  const std::string text = replay_json(replay, "test");
  const TempFile file("round_trip_written_test.replay.json", text);
  auto loaded = load_replay_file(file.path, true);
  if (!loaded.ok()) FAIL(loaded.error().message());
  const Replay& reread = loaded.value();
  CHECK(reread.settings_override == replay.settings_override);
  CHECK(reread.settings_override == "{\"sleep\": \"still\", \"gravity\": [0, \"-981/100\", 0]}");
  CHECK(reread.scene.settings.sleep_method == SleepMethod::still);
  CHECK(replay_json(reread, "test") == text);
}

TEST_CASE("inputs outside the envelope are refused when the replay is read, naming the field", "[replay][envelope]") {
  const std::string head = "{\"format\": \"bitstep-replay\", \"version\": 1, \"scene\": \"bounce.json\", "
                           "\"scene_hash\": \"0000000000000000\", \"steps\": 1, \"hashes\": [\"0000000000000000\"], "
                           "\"inputs\": [{\"step\": 1, ";
  struct Case {
    std::string input, expected;
  };
  const Case cases[] = {
      // Each component within 500 m/s, the length 866 m/s.
      {"\"type\": \"set_velocity\", \"body\": 1, \"linear\": [500, 500, 500]}",
       "$.inputs[0].linear: faster than 500 m/s"},
      {"\"type\": \"set_velocity\", \"body\": 1, \"angular\": [100, 1, 0]}", "$.inputs[0].angular: faster than 100 rad/s"},
      // 1e5 kg in a 0.02 m box: 1.25e10 kg/m^3 (it spawned as ~17,180 kg).
      {"\"type\": \"spawn\", \"body\": {\"mass\": 100000, \"shapes\": [{\"type\": \"box\", \"half_extents\": [0.01, 0.01, "
       "0.01]}]}}",
       "$.inputs[0].body.mass: 100000 kg in 0.000008 m^3 is denser than 100000000 kg/m^3"},
      {"\"type\": \"spawn\", \"body\": {\"density\": 1000, \"shapes\": [{\"type\": \"box\", \"half_extents\": [0.01, "
       "0.01, 0.01]}]}}",
       "$.inputs[0].body.density: 1000 kg/m^3 gives a mass outside 0.01..100000 kg"},
      {"\"type\": \"force\", \"body\": 1, \"force\": [0, 1000001, 0], \"point\": [0, 0, 0]}", "$.inputs[0].force"},
  };
  for (const Case& c : cases) {
    const TempFile file("envelope_test.replay.json", head + c.input + "]}");
    const std::string message = error_of(file.path);
    INFO(message);
    CHECK(message.find(c.expected) != std::string::npos);
    CHECK(message.find('\n') == std::string::npos);
  }
}

TEST_CASE("inputs at their bounds replay in every build", "[replay][envelope]") {
  // The documented bounds, at the far corner of the scene's ball and from
  // across the world: computed at a scale where they cannot overflow, then
  // clamped (a checked build aborted in cross / dot).
  const std::string text =
      "{\"format\": \"bitstep-replay\", \"version\": 1, \"scene\": \"bounce.json\", "
      "\"scene_hash\": \"0000000000000000\", \"steps\": 30, \"inputs\": ["
      "{\"step\": 1, \"type\": \"impulse\", \"body\": 1, \"impulse\": [1000000, -1000000, 1000000], "
      "\"point\": [16000, 16000, 16000]},"
      "{\"step\": 2, \"type\": \"force\", \"body\": 1, \"force\": [1000000, 1000000, -1000000], "
      "\"point\": [-16000, -16000, 16000]},"
      "{\"step\": 3, \"type\": \"set_velocity\", \"body\": 1, \"linear\": [0, -500, 0], \"angular\": [0, 100, 0]},"
      "{\"step\": 4, \"type\": \"spawn\", \"body\": {\"mass\": 800, \"position\": [3, 1, 0], "
      "\"shapes\": [{\"type\": \"box\", \"half_extents\": [0.01, 0.01, 0.01]}]}}]}";
  const TempFile file("bounds_test.replay.json", text);
  auto loaded = load_replay_file(file.path, false);
  if (!loaded.ok()) FAIL(loaded.error().message());
  const Replay& replay = loaded.value();
  World world(replay.scene.settings);
  REQUIRE(build_world(replay.scene, world).ok());
  std::vector<uint64_t> hashes;
  run_inputs(world, replay.inputs, replay.steps, hashes);
  CHECK(hashes.size() == 30);
  CHECK(world.bodies().size() == 3);  // the spawn was admitted
  for (const Body& body : world.bodies()) CHECK(length(body.linear_velocity) <= envelope::max_linear_speed);
}

// The car's golden replay: its drive inputs set the controls from their
// step on; the course is crossed, the crates pushed, the car stopped.
TEST_CASE("car.replay.json drives the course: drive inputs steer the run", "[replay][car]") {
  auto loaded = load_replay_file(scenes_dir + "/car.replay.json", true);
  if (!loaded.ok()) FAIL(loaded.error().message());
  const Replay& replay = loaded.value();
  REQUIRE(replay.inputs.size() == 4u);
  CHECK(replay.inputs[0].kind == Input::Kind::drive);
  CHECK(replay.inputs[0].controls.throttle == 0.7_fx);
  CHECK(replay.inputs[3].controls.brake == Fixed::one());
  World world(replay.scene.settings);
  REQUIRE(build_world(replay.scene, world).ok());
  InputRun run(world);
  for (int64_t step = 1; step <= replay.steps; ++step) {
    apply_inputs(world, replay.inputs, step, run);
    world.step();
    if (step == 600) CHECK(world.cars()[0].controls.throttle == 0.5_fx);
  }
  const Body& chassis = world.bodies()[replay.scene.cars[0].chassis];
  CHECK(bitstep::test::to_double(chassis.pose.position.z) > 60.0);   // past the crates' first place (48 m)
  CHECK(bitstep::test::to_double(length(chassis.linear_velocity)) < 0.01);  // braked to rest
  for (const WheelState& wheel : world.cars()[0].wheels) CHECK(wheel.on_ground);
}

// JigLib's "drive into a wall and squash a box" case with the real
// car, both pipelines: the throttle held down, the chassis pins the 1 kg
// cube against the wall and never pushes it more than slop (0) + 5 mm in.
TEST_CASE("car_wall: the car pins the cube against the wall without pushing it in", "[replay][car]") {
  for (const char* name : {"car_wall.replay.json", "car_wall.guendelman.replay.json"}) {
    INFO(name);
    auto loaded = load_replay_file(scenes_dir + "/" + name, true);
    if (!loaded.ok()) FAIL(loaded.error().message());
    const Replay& replay = loaded.value();
    World world(replay.scene.settings);
    REQUIRE(build_world(replay.scene, world).ok());
    InputRun run(world);
    double deepest = 0, pinned_steps = 0;
    for (int64_t step = 1; step <= 300; ++step) {  // the replay's 120 steps, then 3 s more at full throttle
      apply_inputs(world, replay.inputs, step, run);
      world.step();
      const double cube_left = bitstep::test::to_double(world.bodies()[2].pose.position.x) - 0.5;  // the wall's face at x = 0
      deepest = std::max(deepest, -cube_left);
      bool touching_car = false;
      for (const Contact& c : world.contacts()) touching_car = touching_car || (c.key.body_a == 2 && c.key.body_b == 3 && touches(c.manifold));
      pinned_steps += touching_car ? 1 : 0;
    }
    INFO("deepest " << deepest * 1000 << " mm into the wall; pinned " << pinned_steps << " steps");
    CHECK(deepest < 0.005);
    CHECK(pinned_steps > 200);  // the car holds it there
    CHECK(world.cars()[0].controls.throttle == Fixed::one());
  }
}
