// The JSON reader at the sizes the readers must take in time proportional to
// the text. Nothing here measures time (tests assert
// behaviour only): a reader that is quadratic again makes these cases take
// minutes (100,000 keys took 165 s on this machine before), which the
// ctest timeout reports.
#include <catch2/catch.hpp>

#include <string>

#include "replay/json_tree.h"
#include "replay/scene.h"

using namespace bitstep;

namespace {

constexpr int many = 100000;

// {"k0": 0, "k1": 1, ..., "k<count-1>": count-1} plus `tail` before the '}'.
std::string object_of_keys(int count, const std::string& tail = "") {
  std::string text = "{";
  for (int i = 0; i < count; ++i) {
    const std::string number = std::to_string(i);
    text.append(i == 0 ? "\"k" : ", \"k").append(number).append("\": ").append(number);
  }
  return text + tail + "}";
}

std::string error_of(std::string_view text) {
  const auto result = json::parse(text);
  if (!result.ok()) return result.error().message();
  return "no error";
}

}  // namespace

TEST_CASE("an object of 100,000 keys is read, members in document order", "[json]") {
  const auto result = json::parse(object_of_keys(many));
  REQUIRE(result.ok());
  const json::Node& root = result.value();
  REQUIRE(root.children.size() == static_cast<size_t>(many));
  for (int i : {0, 1, 9, 10, many / 2, many - 1}) {
    const std::string number = std::to_string(i);
    CHECK(root.children[static_cast<size_t>(i)].key == std::string("k").append(number));
    CHECK(root.children[static_cast<size_t>(i)].text == number);
  }
}

TEST_CASE("a duplicate key after 100,000 others is found", "[json]") {
  CHECK(error_of(object_of_keys(many, ", \"k0\": 1")) == "$.k0: duplicate key");
  CHECK(error_of(object_of_keys(many, ", \"k99999\": 1")) == "$.k99999: duplicate key");
  // The same key in two objects is no duplicate.
  CHECK(error_of(R"({"a": {"k": 1}, "b": {"k": 2}, "k": 3})") == "no error");
}

TEST_CASE("an array of 100,000 elements is read", "[json]") {
  std::string text = "[";
  for (int i = 0; i < many; ++i) text += i == 0 ? "0" : ", 0";
  const auto result = json::parse(text + "]");
  REQUIRE(result.ok());
  const json::Node& root = result.value();
  REQUIRE(root.children.size() == static_cast<size_t>(many));
  CHECK(root.children.back().path == "$[99999]");
}

TEST_CASE("nesting is read to the depth limit and refused beyond it", "[json]") {
  auto nested = [](int depth) { return std::string(static_cast<size_t>(depth), '[') + std::string(static_cast<size_t>(depth), ']'); };
  CHECK(error_of(nested(json::max_depth)) == "no error");
  const std::string too_deep = error_of(nested(json::max_depth + 1));
  CHECK(too_deep.rfind("$[0]", 0) == 0);
  CHECK(too_deep.find(": nesting deeper than 64 levels") != std::string::npos);
}

TEST_CASE("a path names a long key by its first 60 bytes", "[json]") {
  // Every node keeps its path: a long key written out in full under a long
  // array would cost key length x elements.
  const std::string key(1000, 'k');
  const auto result = json::parse("{\"" + key + "\": [0, 0]}");
  REQUIRE(result.ok());
  const json::Node& element = result.value().children[0].children[1];
  CHECK(element.path == "$[\"" + std::string(60, 'k') + "...\"][1]");
  CHECK(json::member_path("$", std::string(60, 'k')) == "$." + std::string(60, 'k'));
}

TEST_CASE("100,000 materials, each body naming the last, load", "[json][scene]") {
  std::string text = R"({"format": "bitstep-scene", "version": 1, "materials": {)";
  for (int i = 0; i < many; ++i) text.append(i == 0 ? "\"m" : ", \"m").append(std::to_string(i)).append("\": {\"restitution\": 0}");
  text += "}, \"bodies\": [";
  constexpr int bodies = 10000;
  for (int i = 0; i < bodies; ++i) {
    text.append(i == 0 ? "" : ", ").append(R"({"material": "m99999", "position": [)").append(std::to_string(i));
    text.append(R"(, 0, 0], "shapes": [{"type": "sphere", "radius": 0.25}]})");
  }
  const auto result = parse_scene(text + "]}", "f.json");
  REQUIRE(result.ok());
  const Scene& scene = result.value();
  CHECK(scene.bodies.size() == static_cast<size_t>(bodies));
  CHECK(scene.materials.names().size() == static_cast<size_t>(many));
  CHECK(scene.materials.names().back() == "m99999");
}
