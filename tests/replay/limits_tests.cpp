// replay/limits.h: every hostile input built here is refused with its one
// line (the file, the place, the limit), and the largest legal values are
// still read where that is cheap.
#include <catch2/catch.hpp>
#include <xxhash.h>

#include <filesystem>
#include <fstream>
#include <string>
#include <variant>
#include <vector>

#include "core/world.h"
#include "replay/json_tree.h"
#include "replay/limits.h"
#include "replay/replay.h"
#include "replay/scene.h"
#include "replay/snapshot.h"

using namespace bitstep;

namespace {

// A folder of its own under the system's temporary folder, removed after.
struct TempDir {
  std::filesystem::path path;
  explicit TempDir(const std::string& name)
      : path(std::filesystem::temp_directory_path() / ("bitstep_limits_tests_" + name)) {
    std::filesystem::remove_all(path);
    std::filesystem::create_directories(path);
  }
  ~TempDir() {
    std::error_code ignored;
    std::filesystem::remove_all(path, ignored);
  }
  std::string file(const std::string& name, const std::string& text) const {
    const std::string p = (path / name).string();
    std::ofstream(p, std::ios::binary) << text;
    return p;
  }
};

std::string scene_error(const std::string& text) {
  const auto result = parse_scene(text, "f.json");
  if (!result.ok()) return result.error().message();
  return "no error";
}

std::string scene_with(const std::string& members) {
  return R"({"format": "bitstep-scene", "version": 1, )" + members + "}";
}

// `count` copies of `item`, comma-separated.
std::string repeated(const std::string& item, size_t count) {
  std::string out;
  out.reserve((item.size() + 2) * count);
  for (size_t i = 0; i < count; ++i) {
    if (i > 0) out += ',';
    out += item;
  }
  return out;
}

std::string stacks(int stacks, int count) {
  std::string generators;
  for (int i = 0; i < stacks; ++i) {
    if (i > 0) generators += ',';
    generators += R"({"type": "stack", "name": "s)";
    generators += std::to_string(i);
    generators += R"(", "count": )";
    generators += std::to_string(count);
    generators += R"(, "position": [)";
    generators += std::to_string(2 * i);
    generators += ", 0, 0]}";
  }
  return scene_with(R"("generators": [)" + generators + "]");
}

const std::string box = R"({"type": "box", "half_extents": [0.5, 0.5, 0.5]})";

}  // namespace

TEST_CASE("a JSON file over the size limit is refused without reading it", "[replay][limits]") {
  const TempDir dir("big_file");
  // A sparse 1 GiB file: its size is all there is to it.
  const std::string path = dir.file("big.json", "");
  std::filesystem::resize_file(path, std::uintmax_t{1} << 30);
  const std::string limit = "1073741824 bytes: more than the limit of 67108864 bytes (64 MiB)";
  const auto scene = load_scene_file(path);
  REQUIRE(!scene.ok());
  CHECK(scene.error().message() == path + ": " + limit);
  const auto replay = load_replay_file(path, true);
  REQUIRE(!replay.ok());
  CHECK(replay.error().message() == path + ": " + limit);
  const auto inputs = load_inputs_file(path, Scene{});
  REQUIRE(!inputs.ok());
  CHECK(inputs.error().message() == path + ": " + limit);

  // One byte over the limit is refused; at the limit the file is read (and
  // is then only malformed: zero bytes are not JSON).
  std::filesystem::resize_file(path, limits::max_json_file_bytes + 1);
  const Result<std::string> over = read_text_file(path);
  REQUIRE_FALSE(over.ok());
  CHECK(over.error().message() == path + ": 67108865 bytes: more than the limit of 67108864 bytes (64 MiB)");
  std::filesystem::resize_file(path, limits::max_json_file_bytes);
  const Result<std::string> at_limit = read_text_file(path);
  REQUIRE(at_limit.ok());
  CHECK(at_limit->size() == limits::max_json_file_bytes);

  // Snapshot images have their own limit (bitstep run --restore).
  CHECK(check_file_size(limits::max_snapshot_file_bytes, limits::max_snapshot_file_bytes).ok());
  CHECK(check_file_size(limits::max_snapshot_file_bytes + 1, limits::max_snapshot_file_bytes).error().message() ==
        "1073741825 bytes: more than the limit of 1073741824 bytes (1024 MiB)");
}

TEST_CASE("JSON nesting and tree size are bounded", "[replay][limits]") {
  const std::string deep = std::string(limits::max_json_depth + 1, '[') + std::string(limits::max_json_depth + 1, ']');
  CHECK(scene_error(deep) == "f.json: $" + [] {
          std::string path;
          for (int i = 0; i < limits::max_json_depth; ++i) path += "[0]";
          return path;
        }() + ": nesting deeper than 64 levels");
  const std::string legal = std::string(limits::max_json_depth, '[') + std::string(limits::max_json_depth, ']');
  CHECK(json::parse(legal).ok());

  // The tree's bytes: a small budget shows the value that crosses it.
  std::string text = "[";
  text += repeated("0", 100);
  text += ']';
  const auto small = json::parse(text, 40 * sizeof(json::Node));
  REQUIRE(!small.ok());
  const Error& error = small.error();
  CHECK(error.place.rfind("$[", 0) == 0);
  CHECK(error.reason == "the JSON tree would take more than the limit of " + std::to_string(40 * sizeof(json::Node)) +
                            " bytes in memory");
  CHECK(json::parse(text, 200 * (sizeof(json::Node) + 8)).ok());
}

TEST_CASE("a scene's counts are bounded before its items are read", "[replay][limits]") {
  // Arrays of empty objects: refused by their length alone (an empty
  // object would be an error of its own).
  CHECK(scene_error(scene_with(R"("bodies": [)" + repeated("{}", 100001) + "]")) ==
        "f.json: $.bodies: 100001 bodies: more than the limit of 100000");
  CHECK(scene_error(scene_with(R"("generators": [)" + repeated("{}", 10001) + "]")) ==
        "f.json: $.generators: 10001 generators: more than the limit of 10000");
  CHECK(scene_error(scene_with(R"("joints": [)" + repeated("{}", 100001) + "]")) ==
        "f.json: $.joints: 100001 joints: more than the limit of 100000");
  CHECK(scene_error(scene_with(R"("cars": [)" + repeated("{}", 1001) + "]")) ==
        "f.json: $.cars: 1001 cars: more than the limit of 1000");
  std::string materials;
  for (int i = 0; i <= limits::max_materials; ++i) {
    materials += i == 0 ? "\"m" : ", \"m";
    materials += std::to_string(i);
    materials += "\": {}";
  }
  CHECK(scene_error(scene_with(R"("materials": {)" + materials + "}")) ==
        "f.json: $.materials: 100001 materials: more than the limit of 100000");
}

TEST_CASE("shapes per body: 256 are read, 257 refused", "[replay][limits]") {
  const auto body = [](int shapes) {
    const std::string small_box = R"({"type": "box", "half_extents": [0.1, 0.1, 0.1]})";  // 8 kg
    return scene_with(R"("bodies": [{"shapes": [)" + repeated(small_box, static_cast<size_t>(shapes)) + "]}]");
  };
  CHECK(scene_error(body(limits::max_shapes_per_body)) == "no error");
  CHECK(scene_error(body(limits::max_shapes_per_body + 1)) ==
        "f.json: $.bodies[0].shapes: 257 shapes in a body: more than the limit of 256");
}

TEST_CASE("bodies per scene: generators are counted before they make their bodies", "[replay][limits]") {
  CHECK(scene_error(scene_with(R"("generators": [{"type": "pyramid", "base": 1000}])")) ==
        "f.json: $.generators[0]: would make 500500 bodies: more than the limit of 100000 in a scene");
  const std::string wide_wall = R"({"type": "wall", "base": 1000, "rows": 101, "shape": "rectangle"})";
  CHECK(scene_error(scene_with(R"("generators": [)" + wide_wall + "]")) ==
        "f.json: $.generators[0]: would make 101000 bodies: more than the limit of 100000 in a scene");
  CHECK(scene_error(scene_with(R"("generators": [{"type": "wall", "base": 1000, "rows": 1000}])")) ==
        "f.json: $.generators[0]: would make 500500 bodies: more than the limit of 100000 in a scene");
  // The largest pyramid under the limit: base 446, 99,681 bodies.
  CHECK(scene_error(scene_with(R"("generators": [{"type": "pyramid", "base": 447}])")) ==
        "f.json: $.generators[0]: would make 100128 bodies: more than the limit of 100000 in a scene");
  // The sum of every generator's: ten stacks of 10,000 are the limit exactly.
  const auto exact = parse_scene(stacks(10, 10000), "f.json");
  REQUIRE(exact.ok());
  CHECK(exact.value().bodies.size() == static_cast<size_t>(limits::max_scene_bodies));
  CHECK(scene_error(stacks(11, 10000)) == "f.json: $.generators[10]: more than 100000 bodies in the scene");
}

TEST_CASE("replay steps, hashes and inputs are bounded before anything runs", "[replay][limits]") {
  const TempDir dir("replay");
  dir.file("one.json", scene_with(R"("bodies": [{"shapes": [)" + box + "]}]"));
  const std::string hash = "\"0000000000000000\"";
  const auto replay = [&](const std::string& steps, const std::string& rest) {
    const std::string head = R"({"format": "bitstep-replay", "version": 1, "scene": "one.json", "scene_hash": )";
    return dir.file("r.replay.json", head + hash + R"(, "steps": )" + steps + rest + "}");
  };
  const auto error_of = [](const std::string& path) {
    const auto loaded = load_replay_file(path, true);
    if (!loaded.ok()) return loaded.error().message();
    return std::string("no error");
  };
  std::string path = replay("100000000", R"(, "hashes": [])");
  CHECK(error_of(path) == path + ": $.steps: outside 0..1000000");
  // 10^6 steps claimed, one hash given (or none): refused as it is read.
  path = replay("1000000", R"(, "hashes": [)" + hash + "]");
  CHECK(error_of(path) == path + ": $.hashes: 1 hashes for 1000000 steps");
  path = replay("1000000", "");
  CHECK(error_of(path) == path + ": $: missing key \"hashes\" (the hash chain to verify against)");
  // The largest step count, with its whole chain (19 MB), is read.
  path = replay("1000000", R"(, "hashes": [)" + repeated(hash, 1000000) + "]");
  const auto longest = load_replay_file(path, true);
  REQUIRE(longest.ok());
  CHECK(longest.value().hashes.size() == 1000000);
  // Inputs: refused by the array's length.
  path = replay("1", R"(, "hashes": [)" + hash + R"(], "inputs": [)" + repeated("{}", 1000001) + "]");
  CHECK(error_of(path) == path + ": $.inputs: 1000001 inputs: more than the limit of 1000000");
}

namespace {

// A snapshot with its payload replaced, header and checksum made to match.
std::vector<uint8_t> with_payload(std::vector<uint8_t> payload) {
  std::vector<uint8_t> image = {'B', 'I', 'T', 'S', 'T', 'E', 'P', 'S'};
  for (int i = 0; i < 4; ++i) image.push_back(static_cast<uint8_t>(snapshot_version >> (8 * i)));
  for (int i = 0; i < 8; ++i) image.push_back(static_cast<uint8_t>(uint64_t{payload.size()} >> (8 * i)));
  image.insert(image.end(), payload.begin(), payload.end());
  const uint64_t checksum = XXH3_64bits(image.data(), image.size());
  for (int i = 0; i < 8; ++i) image.push_back(static_cast<uint8_t>(checksum >> (8 * i)));
  return image;
}

void put_u32(std::vector<uint8_t>& bytes, size_t at, uint32_t value) {
  for (size_t i = 0; i < 4; ++i) bytes[at + i] = static_cast<uint8_t>(value >> (8 * i));
}

std::string restore_error(const std::vector<uint8_t>& image) {
  World world;
  const Result<void> restored = restore(image, world);
  return restored.ok() ? "no error" : restored.error().message();
}

}  // namespace

TEST_CASE("a snapshot's counts are refused before the world is allocated", "[replay][limits]") {
  // An empty world's payload: step, settings, then the counts of bodies,
  // free slots and contacts (4 bytes each).
  const std::vector<uint8_t> image = snapshot(World{});
  const std::vector<uint8_t> payload(image.begin() + 20, image.end() - 8);
  const size_t bodies_at = payload.size() - 12, contacts_at = payload.size() - 4;
  REQUIRE(restore_error(with_payload(payload)) == "no error");
  const std::string bodies_byte = std::to_string(bodies_at + 4), contacts_byte = std::to_string(contacts_at + 4);

  std::vector<uint8_t> bad = payload;
  put_u32(bad, bodies_at, UINT32_MAX);
  CHECK(restore_error(with_payload(bad)) ==
        "4294967295 bodies: more than the limit of 1100000 (payload byte " + bodies_byte + ")");
  // At the limit, the count must still fit the bytes left (5 a body at least).
  put_u32(bad, bodies_at, limits::max_world_bodies);
  CHECK(restore_error(with_payload(bad)) ==
        "1100000 bodies: more than the 8 bytes left could hold (payload byte " + bodies_byte + ")");

  bad = payload;
  put_u32(bad, contacts_at, limits::max_world_contacts + 1);
  CHECK(restore_error(with_payload(bad)) ==
        "4400001 contacts: more than the limit of 4400000 (payload byte " + contacts_byte + ")");

  // The joints' block follows when there are bytes left.
  bad = payload;
  bad.insert(bad.end(), {0xff, 0xff, 0xff, 0xff});
  CHECK(restore_error(with_payload(bad)) ==
        "4294967295 joints: more than the limit of 1100000 (payload byte " + std::to_string(payload.size() + 4) + ")");
}
