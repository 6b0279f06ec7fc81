// The C API's misuse battery (replay/bitstep.h): every NULL where a call
// needs a pointer gets BITSTEP_NULL_ARGUMENT and a last error naming the
// call and the argument; the create calls set *out to NULL and write their
// message on every failure; an input a body's type cannot take is refused,
// not silently dropped; and a refused call changes nothing.
#include <catch2/catch.hpp>
#include <cstring>
#include <string>
#include <vector>

#include "replay/bitstep.h"
#include "tests/replay/c_api_support.h"

namespace {

// A static ground, a kinematic platform and a dynamic ball.
const char* const kinds_scene = R"({"format": "bitstep-scene", "version": 1, "bodies": [
  {"name": "ground", "type": "static", "position": [0, -1, 0], "shapes": [{"type": "box", "half_extents": [30, 1, 30]}]},
  {"name": "platform", "type": "kinematic", "position": [5, 2, 0], "shapes": [{"type": "box", "half_extents": [1, 0.1, 1]}]},
  {"name": "ball", "position": [0, 3, 0], "shapes": [{"type": "sphere", "radius": 0.5}]}]})";

bitstep_simulation* made() { return simulation_of(kinds_scene, "kinds.json"); }

}  // namespace

TEST_CASE("C API: every NULL argument is refused, named in the last error, and changes nothing", "[c_api]") {
  bitstep_simulation* sim = made();
  const bitstep_body ball = body(sim, "ball");
  const uint64_t hash = bitstep_hash(sim);
  const auto null_refused = [&](bitstep_status status, const char* message) {
    CHECK(status == BITSTEP_NULL_ARGUMENT);
    CHECK(std::string(bitstep_last_error(sim)) == message);
    CHECK(bitstep_hash(sim) == hash);
  };
  bitstep_body b{};
  bitstep_joint j{};
  bitstep_pose pose{};
  bitstep_render_pose render{};
  bitstep_ray_hit hit{};
  size_t size = 0;
  uint8_t byte = 0;
  null_refused(bitstep_find_body(sim, nullptr, &b), "find_body: name is NULL");
  null_refused(bitstep_find_body(sim, "ball", nullptr), "find_body: out is NULL");
  null_refused(bitstep_add_body(sim, nullptr, &b), "add_body: body_json is NULL");
  null_refused(bitstep_add_body(sim, "{}", nullptr), "add_body: out is NULL");
  null_refused(bitstep_add_joint(sim, nullptr, &j), "add_joint: joint_json is NULL");
  null_refused(bitstep_add_joint(sim, "{}", nullptr), "add_joint: out is NULL");
  null_refused(bitstep_body_in_slot(sim, 0, nullptr), "body_in_slot: out is NULL");
  null_refused(bitstep_drive(sim, nullptr, 0, 0, 0), "drive: car is NULL");
  null_refused(bitstep_get_pose(sim, ball, nullptr), "get_pose: out is NULL");
  null_refused(bitstep_get_render_pose(sim, ball, nullptr), "get_render_pose: out is NULL");
  null_refused(bitstep_save(sim, nullptr, 0, nullptr), "save: size is NULL");
  null_refused(bitstep_save(sim, nullptr, 10, &size), "save: buffer (of capacity > 0) is NULL");
  null_refused(bitstep_load(sim, nullptr, 10), "load: image is NULL");
  null_refused(bitstep_save_state(sim, nullptr, 0, nullptr), "save_state: size is NULL");
  null_refused(bitstep_save_state(sim, nullptr, 10, &size), "save_state: buffer (of capacity > 0) is NULL");
  null_refused(bitstep_load_state(sim, nullptr, 10), "load_state: image is NULL");
  null_refused(bitstep_cast_ray(sim, {0, units(5), 0}, {0, units(-10), 0}, nullptr), "cast_ray: out is NULL");
  // A call that succeeds leaves the last message as it was.
  REQUIRE(bitstep_get_pose(sim, ball, &pose) == BITSTEP_OK);
  CHECK(std::string(bitstep_last_error(sim)) == "cast_ray: out is NULL");
  // Without a handle: the status alone.
  CHECK(bitstep_step(nullptr) == BITSTEP_NULL_ARGUMENT);
  CHECK(std::string(bitstep_last_error(nullptr)).empty());
  bitstep_fixed value = 0;
  CHECK(bitstep_fixed_parse(nullptr, &value) == BITSTEP_NULL_ARGUMENT);
  uint64_t checksum = 0;
  CHECK(bitstep_state_checksum(&byte, 0, nullptr) == BITSTEP_NULL_ARGUMENT);
  CHECK(bitstep_state_checksum(nullptr, 0, &checksum) == BITSTEP_NULL_ARGUMENT);
  (void)render;
  (void)hit;
  bitstep_destroy(sim);
}

TEST_CASE("C API: create sets *out to NULL and writes its message on every failure", "[c_api]") {
  bitstep_simulation* sim = reinterpret_cast<bitstep_simulation*>(&sim);  // not NULL: it must be cleared
  char error[128] = "untouched";
  CHECK(bitstep_create_from_text(nullptr, 0, "x.json", &sim, error, sizeof error) == BITSTEP_NULL_ARGUMENT);
  CHECK(sim == nullptr);
  CHECK(std::string(error) == "create_from_text: json is NULL");
  sim = reinterpret_cast<bitstep_simulation*>(&sim);
  CHECK(bitstep_create_from_text("{}", 2, nullptr, &sim, error, sizeof error) == BITSTEP_NULL_ARGUMENT);
  CHECK(sim == nullptr);
  CHECK(std::string(error) == "create_from_text: name is NULL");
  CHECK(bitstep_create_from_text("{}", 2, "x.json", nullptr, error, sizeof error) == BITSTEP_NULL_ARGUMENT);
  CHECK(std::string(error) == "create_from_text: out is NULL");
  sim = reinterpret_cast<bitstep_simulation*>(&sim);
  CHECK(bitstep_create_from_file(nullptr, &sim, error, sizeof error) == BITSTEP_NULL_ARGUMENT);
  CHECK(sim == nullptr);
  CHECK(std::string(error) == "create_from_file: path is NULL");
  sim = reinterpret_cast<bitstep_simulation*>(&sim);
  CHECK(bitstep_create_from_text("{", 1, "x.json", &sim, error, sizeof error) == BITSTEP_INVALID);
  CHECK(sim == nullptr);
  CHECK(std::string(error).rfind("x.json", 0) == 0);
  // A NULL error buffer is allowed: the status alone.
  CHECK(bitstep_create_from_text(nullptr, 0, "x.json", &sim, nullptr, 0) == BITSTEP_NULL_ARGUMENT);
}

TEST_CASE("C API: an input the body's type cannot take is refused, named, and changes nothing", "[c_api]") {
  bitstep_simulation* sim = made();
  const bitstep_body ground = body(sim, "ground"), platform = body(sim, "platform"), ball = body(sim, "ball");
  const bitstep_vec3 push{units(10), 0, 0}, at{0, 0, 0}, slow{units(1), 0, 0};
  const uint64_t hash = bitstep_hash(sim);
  const auto refused = [&](bitstep_status status, const char* message) {
    CHECK(status == BITSTEP_INVALID);
    CHECK(std::string(bitstep_last_error(sim)) == message);
    CHECK(bitstep_hash(sim) == hash);
  };
  refused(bitstep_apply_impulse(sim, ground, push, at),
          "apply_impulse: the body is static: impulses move dynamic bodies");
  refused(bitstep_apply_impulse(sim, platform, push, at),
          "apply_impulse: the body is kinematic: impulses move dynamic bodies");
  refused(bitstep_apply_force(sim, ground, push, at), "apply_force: the body is static: forces move dynamic bodies");
  refused(bitstep_apply_force(sim, platform, push, at),
          "apply_force: the body is kinematic: forces move dynamic bodies");
  refused(bitstep_set_velocity(sim, ground, slow, {0, 0, 0}),
          "set_velocity: the body is static: a static body never moves");
  bitstep_body_type type = BITSTEP_DYNAMIC;
  REQUIRE(bitstep_get_body_type(sim, ground, &type) == BITSTEP_OK);
  CHECK(type == BITSTEP_STATIC);
  REQUIRE(bitstep_get_body_type(sim, platform, &type) == BITSTEP_OK);
  CHECK(type == BITSTEP_KINEMATIC);
  REQUIRE(bitstep_get_body_type(sim, ball, &type) == BITSTEP_OK);
  CHECK(type == BITSTEP_DYNAMIC);
  CHECK(bitstep_get_body_type(sim, ball, nullptr) == BITSTEP_NULL_ARGUMENT);
  CHECK(bitstep_get_body_type(sim, {ball.index, ball.generation + 1}, &type) == BITSTEP_NOT_FOUND);
  // What the types take: a velocity on the kinematic platform, a push on the ball.
  CHECK(bitstep_set_velocity(sim, platform, slow, {0, 0, 0}) == BITSTEP_OK);
  CHECK(bitstep_apply_impulse(sim, ball, push, at) == BITSTEP_OK);
  CHECK(bitstep_hash(sim) != hash);
  bitstep_destroy(sim);
}

TEST_CASE("C API: small buffers, corrupt and foreign images are refused, named, and change nothing", "[c_api]") {
  bitstep_simulation* sim = made();
  REQUIRE(bitstep_apply_impulse(sim, body(sim, "ball"), {units(3), 0, 0}, {0, units(3), 0}) == BITSTEP_OK);
  for (int i = 0; i < 10; ++i) REQUIRE(bitstep_step(sim) == BITSTEP_OK);
  const uint64_t hash = bitstep_hash(sim);
  // Sizes: asked with a NULL buffer, refused one byte short, each naming both.
  size_t size = 0;
  CHECK(bitstep_save_state(sim, nullptr, 0, &size) == BITSTEP_BUFFER_TOO_SMALL);
  std::vector<uint8_t> state(size);
  CHECK(bitstep_save_state(sim, state.data(), size - 1, &size) == BITSTEP_BUFFER_TOO_SMALL);
  CHECK(std::string(bitstep_last_error(sim)) ==
        "save_state: " + std::to_string(size) + " bytes needed, " + std::to_string(size - 1) + " given");
  REQUIRE(bitstep_save_state(sim, state.data(), state.size(), &size) == BITSTEP_OK);
  size_t image_size = 0;
  CHECK(bitstep_save(sim, nullptr, 0, &image_size) == BITSTEP_BUFFER_TOO_SMALL);
  std::vector<uint8_t> image(image_size);
  REQUIRE(bitstep_save(sim, image.data(), image.size(), &image_size) == BITSTEP_OK);
  uint64_t checksum = 0;
  REQUIRE(bitstep_state_checksum(state.data(), state.size(), &checksum) == BITSTEP_OK);
  CHECK(checksum == bitstep_checksum(sim));
  for (int i = 0; i < 5; ++i) REQUIRE(bitstep_step(sim) == BITSTEP_OK);
  const uint64_t later = bitstep_hash(sim);
  const auto refused = [&](bitstep_status status, const char* starts) {
    CHECK(status == BITSTEP_INVALID);
    INFO(bitstep_last_error(sim));
    CHECK(std::string(bitstep_last_error(sim)).rfind(starts, 0) == 0);
    CHECK(bitstep_hash(sim) == later);
  };
  // Every byte flipped in turn is refused (the payload's checksum, the
  // header's fields) or, where it is a value, refused by its bound; a
  // truncated image is refused; nothing changes either way.
  int refused_flips = 0;
  for (size_t at = 0; at < state.size(); at += 7) {
    std::vector<uint8_t> flipped = state;
    flipped[at] ^= 0x10;
    if (bitstep_load_state(sim, flipped.data(), flipped.size()) == BITSTEP_INVALID) {
      ++refused_flips;
      CHECK(bitstep_hash(sim) == later);
    } else {
      FAIL("a flipped byte at " << at << " loaded");
    }
  }
  CHECK(refused_flips > 10);
  refused(bitstep_load_state(sim, state.data(), state.size() / 2), "load_state: ");
  refused(bitstep_load(sim, image.data(), image.size() - 1), "load: ");
  std::vector<uint8_t> flipped_image = image;
  flipped_image[image.size() / 2] ^= 1;
  refused(bitstep_load(sim, flipped_image.data(), flipped_image.size()), "load: ");
  // A state is not a snapshot, nor the other way round.
  refused(bitstep_load(sim, state.data(), state.size()), "load: ");
  refused(bitstep_load_state(sim, image.data(), image.size()), "load_state: ");
  CHECK(bitstep_state_checksum(image.data(), image.size(), &checksum) == BITSTEP_INVALID);
  CHECK(bitstep_state_checksum(nullptr, 0, &checksum) == BITSTEP_NULL_ARGUMENT);
  // The good ones restore: the hash of the tick they were saved at.
  REQUIRE(bitstep_load_state(sim, state.data(), state.size()) == BITSTEP_OK);
  CHECK(bitstep_hash(sim) == hash);
  REQUIRE(bitstep_load(sim, image.data(), image.size()) == BITSTEP_OK);
  CHECK(bitstep_hash(sim) == hash);
  bitstep_destroy(sim);
}
