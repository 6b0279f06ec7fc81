// Input replays: the golden replays in scenes/ reproduce their hash chains
// step by step, and a damaged or malformed replay is refused or reported at
// the step where it differs.
#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <string>
#include <variant>

#include "replay/replay.h"
#include "replay/state_hash.h"

using namespace bitstep;

namespace {

const std::string scenes_dir = std::string(BITSTEP_SOURCE_DIR) + "/scenes";

std::vector<std::string> golden_replays() {
  std::vector<std::string> paths;
  for (const auto& entry : std::filesystem::directory_iterator(scenes_dir)) {
    const std::string name = entry.path().filename().string();
    if (name.size() > 12 && name.ends_with(".replay.json")) paths.push_back(entry.path().string());
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

// Runs a replay; the hash chain it produces.
std::vector<uint64_t> replay_chain(const Replay& replay, uint64_t& scene_hash) {
  World world(replay.scene.settings);
  std::string reason;
  REQUIRE(build_world(replay.scene, world, reason));
  scene_hash = state_hash(world);
  std::vector<uint64_t> hashes;
  run_inputs(world, replay.inputs, replay.steps, hashes);
  return hashes;
}

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
  std::string text, reason;
  REQUIRE(read_text_file(path, text, reason));
  return text;
}

std::string error_of(const std::string& path) {
  auto loaded = load_replay_file(path, true);
  REQUIRE(std::holds_alternative<ReplayError>(loaded));
  return std::get<ReplayError>(loaded).message();
}

}  // namespace

TEST_CASE("every golden replay reproduces its hash chain at every step", "[replay][golden]") {
  const std::vector<std::string> paths = golden_replays();
  REQUIRE(paths.size() >= 13);  // one per shipped scene
  for (const std::string& path : paths) {
    INFO(path);
    auto loaded = load_replay_file(path, true);
    if (const ReplayError* error = std::get_if<ReplayError>(&loaded)) FAIL(error->message());
    const Replay& replay = std::get<Replay>(loaded);
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
  REQUIRE(std::holds_alternative<Replay>(loaded));
  const Replay& replay = std::get<Replay>(loaded);
  // Flip one hex digit of step 77's hash.
  char hash77[17];
  for (int i = 15, shift = 0; i >= 0; --i, shift += 4) hash77[i] = "0123456789abcdef"[(replay.hashes[76] >> shift) & 15];
  hash77[16] = '\0';
  const size_t at = text.find(hash77);
  REQUIRE(at != std::string::npos);
  text[at] = text[at] == '0' ? '1' : '0';
  const TempFile damaged("damaged_test.replay.json", text);
  auto reloaded = load_replay_file(damaged.path, true);
  REQUIRE(std::holds_alternative<Replay>(reloaded));
  uint64_t scene_hash = 0;
  CHECK(first_divergent_step(std::get<Replay>(reloaded).hashes, replay_chain(std::get<Replay>(reloaded), scene_hash)) == 77);
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

TEST_CASE("hashing a world does not change its future", "[replay]") {
  auto loaded = load_scene_file(scenes_dir + "/thrown.json");
  REQUIRE(std::holds_alternative<Scene>(loaded));
  const Scene& scene = std::get<Scene>(loaded);
  World hashed(scene.settings), plain(scene.settings);
  std::string reason;
  REQUIRE(build_world(scene, hashed, reason));
  REQUIRE(build_world(scene, plain, reason));
  uint64_t fold = 0;
  for (int i = 0; i < 90; ++i) {
    hashed.step();
    fold ^= state_hash(hashed);
    plain.step();
  }
  CHECK(fold != 0);
  CHECK(state_hash(hashed) == state_hash(plain));
}
