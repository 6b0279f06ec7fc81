// The game-facing facade (replay/simulation.h) and the C API over it
// (replay/bitstep.h): worlds from scenes, poses in the scene's frames,
// bodies and joints added from JSON with their errors, inputs, rollback by
// save and load, and the same bits as a world built and stepped directly.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstring>
#include <string>
#include <vector>

#include "replay/bitstep.h"
#include "replay/render_pose.h"
#include "replay/simulation.h"
#include "replay/state_hash.h"
#include "tests/replay/test_scenes.h"
#include "tests/test_support.h"

using namespace bitstep;

namespace {

// A table defined at y 0.4 (its frame's origin between its legs, its top
// 0.37 m above that) on a ground, and a ball.
const char* const table_scene = R"({"format": "bitstep-scene", "version": 1, "bodies": [
  {"name": "ground", "type": "static", "position": [0, -1, 0], "shapes": [{"type": "box", "half_extents": [20, 1, 20]}]},
  {"name": "table", "position": [0, 0.4, 0], "shapes": [
    {"type": "box", "half_extents": [0.6, 0.03, 0.4], "position": [0, 0.37, 0]},
    {"type": "box", "half_extents": [0.03, 0.385, 0.03], "position": [0.5, -0.015, 0.3]},
    {"type": "box", "half_extents": [0.03, 0.385, 0.03], "position": [-0.5, -0.015, 0.3]},
    {"type": "box", "half_extents": [0.03, 0.385, 0.03], "position": [0.5, -0.015, -0.3]},
    {"type": "box", "half_extents": [0.03, 0.385, 0.03], "position": [-0.5, -0.015, -0.3]}]},
  {"name": "ball", "position": [3, 0.5, 0], "shapes": [{"type": "sphere", "radius": 0.5}]}]})";

Simulation table_simulation() {
  Result<Simulation> sim = Simulation::from_text(table_scene, "table.json");
  if (!sim.ok()) FAIL(sim.error().message());
  return std::move(sim).value();
}

}  // namespace

TEST_CASE("a simulation reads poses in the frames its scene defined, not centres of mass", "[simulation]") {
  Simulation sim = table_simulation();
  const BodyId table = *sim.find_body("table");
  // The world holds the centre of mass (raised by the top), the facade the frame.
  CHECK(sim.world().body(table).pose.position.y > 0.5_fx);
  CHECK(sim.pose(table)->position == Vec3{Fixed{}, 0.4_fx, Fixed{}});
  const double offset = test::to_double(length(sim.world().body(table).pose.position - sim.pose(table)->position));
  // Tipped over by a push at the top, the frame's origin follows the body:
  // it stays as far from the centre of mass, and it moved.
  sim.apply_impulse(table, {Fixed::from_int(200), Fixed{}, Fixed{}}, {Fixed{}, 0.8_fx, Fixed{}});
  for (int i = 0; i < 60; ++i) sim.step();
  const Body& body = sim.world().body(table);
  CHECK(std::abs(test::to_double(length(body.pose.position - sim.pose(table)->position)) - offset) < 1e-8);
  CHECK(test::to_double(length(sim.pose(table)->position - Vec3{Fixed{}, 0.4_fx, Fixed{}})) > 0.1);
  CHECK(sim.pose(table)->orientation == body.pose.orientation);
  CHECK(sim.tick() == 60u);
  CHECK_FALSE(sim.find_body("chair"));
}

TEST_CASE("a simulation steps the same bits as a world built and stepped directly", "[simulation]") {
  auto sim = Simulation::from_file(test::scenes_dir + "/car.json");
  REQUIRE(sim.ok());
  World world = test::world_of("car.json");
  CHECK(sim->hash() == state_hash(world));
  REQUIRE(sim->drive("car.0", {0.7_fx, Fixed{}, 0.1_fx}));
  world.set_car_controls({0}, {0.7_fx, Fixed{}, 0.1_fx});
  const BodyId crate = *sim->find_body("crate.0");
  for (int i = 0; i < 120; ++i) {
    if (i == 30) {
      REQUIRE(sim->apply_impulse(crate, {Fixed::from_int(40), Fixed{}, Fixed{}}, sim->world().body(crate).pose.position));
      world.apply_impulse(crate, {Fixed::from_int(40), Fixed{}, Fixed{}}, world.body(crate).pose.position);
    }
    sim->step();
    world.step();
  }
  CHECK(sim->hash() == state_hash(world));
  CHECK_FALSE(sim->drive("car.9", {}));
}

TEST_CASE("a simulation rolls back: load a saved tick and the same ticks follow", "[simulation]") {
  Simulation sim = table_simulation();
  const BodyId ball = *sim.find_body("ball");
  sim.apply_impulse(ball, {Fixed::from_int(-5), Fixed{}, Fixed{}}, sim.world().body(ball).pose.position);
  for (int i = 0; i < 10; ++i) sim.step();
  const std::vector<uint8_t> saved = sim.save();
  std::vector<uint64_t> first, again;
  for (int i = 0; i < 40; ++i) {
    sim.step();
    first.push_back(sim.hash());
  }
  REQUIRE(sim.load(saved).ok());
  CHECK(sim.tick() == 10u);
  for (int i = 0; i < 40; ++i) {
    sim.step();
    again.push_back(sim.hash());
  }
  CHECK(first == again);
  // A damaged image is refused and changes nothing.
  std::vector<uint8_t> damaged = saved;
  damaged[damaged.size() / 2] ^= 1;
  const uint64_t before = sim.hash();
  const Result<void> loaded = sim.load(damaged);
  REQUIRE_FALSE(loaded.ok());
  CHECK(loaded.error().message().find("checksum") != std::string::npos);
  CHECK(sim.hash() == before);
}

TEST_CASE("bodies and joints added from JSON, and their errors with the JSON path", "[simulation]") {
  Simulation sim = table_simulation();
  const auto error_of = [](const auto& result) { return result.ok() ? std::string("no error") : result.error().message(); };
  const Result<BodyId> crate = sim.add_body(R"({"name": "crate", "position": [-3, 0.25, 0], "orientation": {"axis": [0, 1, 0],
      "degrees": 30}, "shapes": [{"type": "box", "half_extents": [0.25, 0.25, 0.25], "position": [0, 0, 0.1]}]})");
  INFO(error_of(crate));
  REQUIRE(crate.ok());
  CHECK(sim.find_body("crate") == crate.value());
  CHECK(sim.pose(*crate)->position == Vec3{-3.0_fx, 0.25_fx, Fixed{}});
  CHECK(error_of(sim.add_body(R"({"name": "crate", "shapes": [{"type": "sphere", "radius": 1}]})")) ==
        "add_body: $.name: \"crate\" is already taken");
  CHECK(error_of(sim.add_body(R"({"shapes": [{"type": "sphere", "radius": 100}]})"))
            .rfind("add_body: $.shapes[0].radius: ", 0) == 0);
  CHECK(error_of(sim.add_body(R"({"shapes": [{"type": "sphere", "radius": 1}], "colour": "red"})"))
            .rfind("add_body: $.colour: unknown key", 0) == 0);
  CHECK(error_of(sim.add_body(R"({"shapes": [)")).rfind("add_body: byte ", 0) == 0);
  // A rope from the ball to the crate; a joint naming no body is refused.
  const Result<JointId> rope = sim.add_joint(R"({"type": "max_distance", "body_a": "ball", "body_b": "crate",
      "anchor": [3, 0.5, 0], "anchor_b": [-3, 0.25, 0], "length": 7})");
  INFO(error_of(rope));
  REQUIRE(rope.ok());
  CHECK(error_of(sim.add_joint(R"({"type": "point", "body_a": "ball", "body_b": "lamp", "anchor": [0, 0, 0]})")) ==
        "add_joint: $.body_b: no body named \"lamp\"");
  // Removed, its handle is refused; the slot's next body has a new generation.
  CHECK(sim.remove_joint(*rope));
  CHECK_FALSE(sim.remove_joint(*rope));
  CHECK(sim.remove_body(*crate));
  CHECK_FALSE(sim.pose(*crate));
  CHECK_FALSE(sim.apply_impulse(*crate, {}, {}));
  CHECK_FALSE(sim.find_body("crate"));
  const Result<BodyId> next = sim.add_body(R"({"name": "crate", "shapes": [{"type": "sphere", "radius": 0.2}]})");
  REQUIRE(next.ok());
  CHECK(next->index == crate->index);
  CHECK(next->generation != crate->generation);
}

TEST_CASE("render poses: floats of the exact pose, interpolated along the shorter arc", "[simulation]") {
  Pose pose{{1.5_fx, -2.25_fx, 0.125_fx}, {}};
  RenderPose r = render_pose(pose);
  CHECK(r.position[0] == 1.5f);
  CHECK(r.position[1] == -2.25f);
  CHECK(r.orientation[3] == 1.0f);
  // A quarter turn about y, halfway: an eighth of a turn.
  const float s = std::sqrt(0.5f);
  const RenderPose from{{0, 0, 0}, {0, 0, 0, 1}}, to{{2, 4, 0}, {0, s, 0, s}};
  const RenderPose mid = interpolate(from, to, 0.5f);
  CHECK(mid.position[0] == 1.0f);
  CHECK(mid.position[1] == 2.0f);
  CHECK(std::abs(2 * std::atan2(mid.orientation[1], mid.orientation[3]) - 3.14159265f / 4) < 1e-6f);
  // -q is the same turn: the shorter arc is taken either way.
  const RenderPose negated{{2, 4, 0}, {0, -s, 0, -s}};
  const RenderPose mid_negated = interpolate(from, negated, 0.5f);
  CHECK(std::abs(mid_negated.orientation[1] - mid.orientation[1]) < 1e-6f);
  CHECK(std::abs(mid_negated.orientation[3] - mid.orientation[3]) < 1e-6f);
  const RenderPose end = interpolate(from, to, 1.0f);
  CHECK(std::abs(end.orientation[1] - s) < 1e-6f);
}

TEST_CASE("the C API: create, errors in caller buffers, step, poses, save into a buffer, load, rays", "[simulation][c_api]") {
  char error[256] = "";
  bitstep_simulation* sim = nullptr;
  const std::string bad = R"({"format": "bitstep-scene", "version": 1, "bodies": [{"shapes": []}]})";
  CHECK(bitstep_create_from_text(bad.data(), bad.size(), "bad.json", &sim, error, sizeof error) == BITSTEP_INVALID);
  CHECK(sim == nullptr);
  CHECK(std::string(error).rfind("bad.json: $.bodies[0].shapes", 0) == 0);
  char tiny[8];
  CHECK(bitstep_create_from_file("no/such/scene.json", &sim, tiny, sizeof tiny) == BITSTEP_INVALID);
  CHECK(std::strlen(tiny) == 7);  // cut, NUL-terminated

  REQUIRE(bitstep_create_from_text(table_scene, std::strlen(table_scene), "table.json", &sim, error, sizeof error) ==
          BITSTEP_OK);
  bitstep_body table{}, ball{};
  REQUIRE(bitstep_find_body(sim, "table", &table) == BITSTEP_OK);
  REQUIRE(bitstep_find_body(sim, "ball", &ball) == BITSTEP_OK);
  CHECK(bitstep_find_body(sim, "lamp", &ball) == BITSTEP_NOT_FOUND);
  CHECK(std::string(bitstep_last_error(sim)) == "no body named \"lamp\"");
  bitstep_pose pose{};
  REQUIRE(bitstep_get_pose(sim, table, &pose) == BITSTEP_OK);
  bitstep_fixed y = 0;
  REQUIRE(bitstep_fixed_parse("0.4", &y) == BITSTEP_OK);
  CHECK(pose.position.y == y);
  CHECK(bitstep_fixed_parse("zero", &y) == BITSTEP_INVALID);
  CHECK(bitstep_fixed_to_double(bitstep_fixed{1} << 31) == 0.5);

  bitstep_fixed push = 0;
  REQUIRE(bitstep_fixed_parse("-5", &push) == BITSTEP_OK);
  REQUIRE(bitstep_apply_impulse(sim, ball, {push, 0, 0}, {0, 0, 0}) == BITSTEP_OK);
  for (int i = 0; i < 10; ++i) REQUIRE(bitstep_step(sim) == BITSTEP_OK);
  CHECK(bitstep_tick(sim) == 10u);

  // Save: the size asked first, a short buffer refused, then written.
  size_t size = 0;
  CHECK(bitstep_save(sim, nullptr, 0, &size) == BITSTEP_BUFFER_TOO_SMALL);
  REQUIRE(size > 0);
  std::vector<uint8_t> image(size);
  REQUIRE(bitstep_save(sim, image.data(), image.size(), &size) == BITSTEP_OK);
  const uint64_t saved_hash = bitstep_hash(sim);
  for (int i = 0; i < 30; ++i) bitstep_step(sim);
  const uint64_t later = bitstep_hash(sim);
  REQUIRE(bitstep_load(sim, image.data(), image.size()) == BITSTEP_OK);
  CHECK(bitstep_hash(sim) == saved_hash);
  for (int i = 0; i < 30; ++i) bitstep_step(sim);
  CHECK(bitstep_hash(sim) == later);
  CHECK(bitstep_load(sim, image.data(), 10) == BITSTEP_INVALID);
  CHECK(std::string(bitstep_last_error(sim)).rfind("load: ", 0) == 0);
  CHECK(bitstep_hash(sim) == later);
  // The same rollback with a step's state alone, into a buffer that is kept.
  size_t state_size = 0;
  CHECK(bitstep_save_state(sim, nullptr, 0, &state_size) == BITSTEP_BUFFER_TOO_SMALL);
  std::vector<uint8_t> state(state_size);
  REQUIRE(bitstep_save_state(sim, state.data(), state.size(), &state_size) == BITSTEP_OK);
  CHECK(state_size < size);  // no shapes, masses or materials in it
  const uint64_t state_hash_then = bitstep_hash(sim);
  for (int i = 0; i < 5; ++i) bitstep_step(sim);
  REQUIRE(bitstep_load_state(sim, state.data(), state.size()) == BITSTEP_OK);
  CHECK(bitstep_hash(sim) == state_hash_then);
  // The checksum the state carries is the simulation's then, and what a
  // second simulation of the scene in the same state has.
  uint64_t carried = 0;
  REQUIRE(bitstep_state_checksum(state.data(), state.size(), &carried) == BITSTEP_OK);
  CHECK(carried == bitstep_checksum(sim));
  CHECK(bitstep_state_checksum(state.data(), 10, &carried) == BITSTEP_INVALID);
  CHECK(bitstep_state_checksum(nullptr, 0, &carried) == BITSTEP_NULL_ARGUMENT);
  bitstep_step(sim);
  CHECK(bitstep_checksum(sim) != carried);
  REQUIRE(bitstep_load_state(sim, state.data(), state.size()) == BITSTEP_OK);
  state[state.size() / 2] ^= 1;
  CHECK(bitstep_load_state(sim, state.data(), state.size()) == BITSTEP_INVALID);
  CHECK(std::string(bitstep_last_error(sim)) == "load_state: checksum mismatch: the image is corrupt");
  CHECK(bitstep_hash(sim) == state_hash_then);

  // A ray down onto the table's top at y 0.8.
  bitstep_fixed x = 0, down = 0, top = 0;
  REQUIRE(bitstep_fixed_parse("0.1", &x) == BITSTEP_OK);
  REQUIRE(bitstep_fixed_parse("-10", &down) == BITSTEP_OK);
  REQUIRE(bitstep_fixed_parse("5", &top) == BITSTEP_OK);
  bitstep_ray_hit hit{};
  REQUIRE(bitstep_cast_ray(sim, {x, top, 0}, {0, down, 0}, &hit) == BITSTEP_OK);
  CHECK(hit.body.index == table.index);
  CHECK(std::abs(bitstep_fixed_to_double(hit.point.y) - 0.8) < 1e-3);
  CHECK(bitstep_cast_ray(sim, {x, top, 0}, {0, top, 0}, &hit) == BITSTEP_NOT_FOUND);

  bitstep_render_pose a{}, b{}, mid{};
  REQUIRE(bitstep_get_render_pose(sim, table, &a) == BITSTEP_OK);
  b = a;
  b.position[0] += 2;
  bitstep_interpolate(&a, &b, 0.5f, &mid);
  CHECK(mid.position[0] == a.position[0] + 1);

  bitstep_body added{};
  CHECK(bitstep_add_body(sim, R"({"shapes": [{"type": "sphere", "radius": -1}]})", &added) == BITSTEP_INVALID);
  CHECK(std::string(bitstep_last_error(sim)).rfind("add_body: $.shapes[0].radius", 0) == 0);
  REQUIRE(bitstep_add_body(sim, R"({"name": "pebble", "position": [0, 3, 0], "shapes": [{"type": "sphere", "radius": 0.1}]})",
                           &added) == BITSTEP_OK);
  CHECK(bitstep_slot_count(sim) == 4u);
  bitstep_body in_slot{};
  REQUIRE(bitstep_body_in_slot(sim, 3, &in_slot) == BITSTEP_OK);
  CHECK(in_slot.generation == added.generation);
  REQUIRE(bitstep_remove_body(sim, added) == BITSTEP_OK);
  CHECK(bitstep_remove_body(sim, added) == BITSTEP_NOT_FOUND);
  CHECK(bitstep_body_in_slot(sim, 3, &in_slot) == BITSTEP_NOT_FOUND);
  CHECK(bitstep_step(nullptr) == BITSTEP_NULL_ARGUMENT);
  bitstep_destroy(sim);
}

// A 2 cm die of 10 g through the C API's getters (the checked build
// aborted in the kinetic energy report on such a body).
TEST_CASE("C API: a 10 g die steps, and every getter reads it", "[simulation][capi][envelope]") {
  const char* scene = R"({"format": "bitstep-scene", "version": 1, "bodies": [
    {"name": "table", "type": "static", "position": [0, -0.5, 0], "shapes": [{"type": "box", "half_extents": [1, 0.5, 1]}]},
    {"name": "die", "position": [0, 0.3, 0], "mass": 0.01, "velocity": [2, 0, 0], "angular_velocity": [0, 0, 30],
     "shapes": [{"type": "box", "half_extents": [0.01, 0.01, 0.01]}]}]})";
  bitstep_simulation* sim = nullptr;
  REQUIRE(bitstep_create_from_text(scene, std::strlen(scene), "die", &sim, nullptr, 0) == BITSTEP_OK);
  bitstep_body die;
  REQUIRE(bitstep_find_body(sim, "die", &die) == BITSTEP_OK);
  bitstep_render_pose before{}, after{}, between{};
  REQUIRE(bitstep_get_render_pose(sim, die, &before) == BITSTEP_OK);
  for (int i = 0; i < 120; ++i) REQUIRE(bitstep_step(sim) == BITSTEP_OK);
  bitstep_pose pose;
  CHECK(bitstep_get_pose(sim, die, &pose) == BITSTEP_OK);
  REQUIRE(bitstep_get_render_pose(sim, die, &after) == BITSTEP_OK);
  bitstep_interpolate(&before, &after, 0.5f, &between);
  CHECK(bitstep_tick(sim) == 120u);
  CHECK(bitstep_hash(sim) != 0u);
  bitstep_ray_hit hit;
  CHECK(bitstep_cast_ray(sim, {0, bitstep_fixed{1} << 32, 0}, {0, -(bitstep_fixed{2} << 32), 0}, &hit) == BITSTEP_OK);
  size_t size = 0;
  CHECK(bitstep_save(sim, nullptr, 0, &size) == BITSTEP_BUFFER_TOO_SMALL);
  std::vector<uint8_t> image(size);
  REQUIRE(bitstep_save(sim, image.data(), image.size(), &size) == BITSTEP_OK);
  CHECK(bitstep_load(sim, image.data(), image.size()) == BITSTEP_OK);
  bitstep_destroy(sim);
}
