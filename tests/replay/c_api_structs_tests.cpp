// The C API a binding is built on (replay/bitstep.h): bodies and joints
// from plain structs give the same bits as from JSON, in motion; the
// getters, the batch pose read and the step's events read what the world
// holds; the integer conversions round as documented; and their misuse
// gets the documented statuses and messages.
#include <catch2/catch.hpp>
#include <cstring>
#include <string>
#include <vector>

#include "replay/bitstep.h"
#include "tests/replay/c_api_support.h"

namespace {

const char* const ground_scene = R"({"format": "bitstep-scene", "version": 1, "bodies": [
  {"name": "ground", "type": "static", "position": [0, -1, 0], "shapes": [{"type": "box", "half_extents": [30, 1, 30]}]},
  {"name": "hook", "type": "static", "position": [0, 4, 0], "shapes": [{"type": "sphere", "radius": 0.05}]},
  {"name": "bob", "position": [1, 4, 0], "shapes": [{"type": "sphere", "radius": 0.2}]}]})";

constexpr bitstep_fixed quarter = units(1) / 4;

bitstep_simulation* made() { return simulation_of(ground_scene, "ground.json"); }

std::vector<bitstep_event> events_of(bitstep_simulation* sim) {
  size_t count = 0;
  const bitstep_status asked = bitstep_get_events(sim, nullptr, 0, &count);
  REQUIRE(asked == (count == 0 ? BITSTEP_OK : BITSTEP_BUFFER_TOO_SMALL));
  std::vector<bitstep_event> events(count);
  REQUIRE(bitstep_get_events(sim, events.data(), events.size(), &count) == BITSTEP_OK);
  return events;
}

bool same_event(const bitstep_event& a, const bitstep_event& b) { return std::memcmp(&a, &b, sizeof a) == 0; }

// A thrown ball: 0.25 m, its centre 0.5 m above its frame's origin, 2 m/s
// sideways and 1 m/s up from 3.5 m, spinning (clear of the bob's fall).
const char* const thrown_json = R"({"name": "thrown", "position": [0, 3, 5], "velocity": [2, 1, 0],
    "angular_velocity": [0, 0, -3], "shapes": [{"type": "sphere", "radius": 0.25, "position": [0, 0.5, 0]}]})";

bitstep_shape thrown_shape() {
  bitstep_shape shape{};
  shape.type = BITSTEP_SHAPE_SPHERE;
  shape.radius = quarter;
  shape.local = {{0, units(1) / 2, 0}, {units(1), 0, 0, 0}};
  return shape;
}

bitstep_body_def thrown_def(const bitstep_shape* shape) {
  bitstep_body_def def = bitstep_default_body_def();
  def.name = "thrown";
  def.pose.position = {0, units(3), units(5)};
  def.linear_velocity = {units(2), units(1), 0};
  def.angular_velocity = {0, 0, units(-3)};
  def.shapes = shape;
  def.shape_count = 1;
  return def;
}

}  // namespace

TEST_CASE("C API: a body from a struct is the body from JSON, bit for bit, thrown and landing", "[c_api]") {
  bitstep_simulation* by_json = made();
  bitstep_simulation* by_struct = made();
  bitstep_body a{}, b{};
  REQUIRE(bitstep_add_body(by_json, thrown_json, &a) == BITSTEP_OK);
  const bitstep_shape shape = thrown_shape();
  const bitstep_body_def def = thrown_def(&shape);
  REQUIRE(bitstep_create_body(by_struct, &def, &b) == BITSTEP_OK);
  CHECK((a.index == b.index && a.generation == b.generation));
  REQUIRE(bitstep_set_events(by_json, 1) == BITSTEP_OK);
  REQUIRE(bitstep_set_events(by_struct, 1) == BITSTEP_OK);
  const bitstep_body ground = body(by_struct, "ground");
  int landed_at = -1;
  for (int step = 1; step <= 120; ++step) {
    REQUIRE(bitstep_step(by_json) == BITSTEP_OK);
    REQUIRE(bitstep_step(by_struct) == BITSTEP_OK);
    REQUIRE(bitstep_hash(by_json) == bitstep_hash(by_struct));
    const std::vector<bitstep_event> x = events_of(by_json), y = events_of(by_struct);
    REQUIRE(x.size() == y.size());
    for (size_t i = 0; i < x.size(); ++i) CHECK(same_event(x[i], y[i]));
    for (const bitstep_event& e : y) {
      if (e.type == BITSTEP_CONTACT_BEGIN && e.body_b.index == b.index && landed_at < 0) {
        landed_at = step;
        CHECK((e.body_a.index == ground.index && e.body_b.generation == b.generation));
      }
    }
    if (step == 1) {  // in flight: its centre's velocities, against the parabola's
      bitstep_vec3 v{}, w{};
      REQUIRE(bitstep_get_velocity(by_struct, b, &v, &w) == BITSTEP_OK);
      CHECK(std::llabs(v.x - units(2)) < 5000);                        // ~1e-6 m/s
      CHECK(std::llabs(v.y - (units(1) - units(981) / 6000)) < 5000);  // 1 - 9.81 / 60
      CHECK(std::llabs(w.z - units(-3)) < 5000);
    }
  }
  // Its centre fell 3.25 m to touching after rising 0.05: t = (1 +
  // sqrt(1 + 2 g 3.25)) / g = 0.92 s, step 55 at 60 Hz.
  INFO("landed at step " << landed_at);
  CHECK((landed_at >= 53 && landed_at <= 57));
  bitstep_vec3 v{}, w{};
  REQUIRE(bitstep_get_velocity(by_struct, b, &v, &w) == BITSTEP_OK);
  CHECK(v.x > units(1) / 2);  // rolling on after landing

  // The getters read what the world holds.
  char name[16];
  size_t size = 0;
  CHECK(bitstep_get_body_name(by_struct, b, name, sizeof name, &size) == BITSTEP_OK);
  CHECK(std::string(name) == "thrown");
  CHECK(size == 7);
  CHECK(bitstep_get_body_name(by_struct, b, name, 3, &size) == BITSTEP_BUFFER_TOO_SMALL);
  CHECK(size == 7);
  CHECK(bitstep_get_body_name(by_struct, ground, name, sizeof name, &size) == BITSTEP_OK);
  CHECK(std::string(name) == "ground");
  uint32_t shapes = 0;
  CHECK(bitstep_get_shape_count(by_struct, b, &shapes) == BITSTEP_OK);
  CHECK(shapes == 1);
  bitstep_shape read{};
  CHECK(bitstep_get_shape(by_struct, b, 0, &read) == BITSTEP_OK);
  CHECK(std::memcmp(&read, &shape, sizeof read) == 0);  // in the frame it was defined in
  CHECK(bitstep_get_shape(by_struct, b, 1, &read) == BITSTEP_NOT_FOUND);
  CHECK(std::string(bitstep_last_error(by_struct)) == "get_shape: shape 1 of 1");
  bitstep_destroy(by_json);
  bitstep_destroy(by_struct);
}

TEST_CASE("C API: a hull from points is the hull from JSON, thrown and tumbling, its corners read back",
          "[c_api][hull]") {
  // A wedge of 6 corners and a point inside it (dropped), thrown spinning.
  const char* const wedge_json = R"({"name": "wedge", "position": [0, 2, 5], "velocity": [1, 0, 0],
      "angular_velocity": [2, 3, 1], "shapes": [{"type": "hull", "points":
      [[-0.5, 0, -0.5], [0.5, 0, -0.5], [-0.5, 0.625, -0.5], [0.5, 0.625, -0.5], [-0.5, 0, 0.5], [0.5, 0, 0.5], [0, 0.25, 0]]}]})";
  const bitstep_vec3 points[] = {{-units(1) / 2, 0, -units(1) / 2},
                                 {units(1) / 2, 0, -units(1) / 2},
                                 {-units(1) / 2, units(5) / 8, -units(1) / 2},
                                 {units(1) / 2, units(5) / 8, -units(1) / 2},
                                 {-units(1) / 2, 0, units(1) / 2},
                                 {units(1) / 2, 0, units(1) / 2},
                                 {0, units(1) / 4, 0}};  // on the hull's 2^-20 m grid: read back as given
  bitstep_shape shape{};
  shape.type = BITSTEP_SHAPE_HULL;
  shape.local.orientation = {units(1), 0, 0, 0};
  shape.points = points;
  shape.point_count = 7;
  bitstep_body_def def = bitstep_default_body_def();
  def.name = "wedge";
  def.pose.position = {0, units(2), units(5)};
  def.linear_velocity = {units(1), 0, 0};
  def.angular_velocity = {units(2), units(3), units(1)};
  def.shapes = &shape;
  def.shape_count = 1;
  bitstep_simulation* by_json = made();
  bitstep_simulation* by_struct = made();
  bitstep_body a{}, b{};
  REQUIRE(bitstep_add_body(by_json, wedge_json, &a) == BITSTEP_OK);
  REQUIRE(bitstep_create_body(by_struct, &def, &b) == BITSTEP_OK);
  for (int step = 1; step <= 120; ++step) {
    REQUIRE(bitstep_step(by_json) == BITSTEP_OK);
    REQUIRE(bitstep_step(by_struct) == BITSTEP_OK);
    REQUIRE(bitstep_hash(by_json) == bitstep_hash(by_struct));
  }
  bitstep_shape read{};
  REQUIRE(bitstep_get_shape(by_struct, b, 0, &read) == BITSTEP_OK);
  CHECK(read.type == BITSTEP_SHAPE_HULL);
  CHECK(read.points == nullptr);
  CHECK(read.point_count == 6);  // the inner point is no corner
  size_t count = 0;
  CHECK(bitstep_get_hull_points(by_struct, b, 0, nullptr, 0, &count) == BITSTEP_BUFFER_TOO_SMALL);
  CHECK(count == 6);
  bitstep_vec3 corners[6];
  REQUIRE(bitstep_get_hull_points(by_struct, b, 0, corners, 6, &count) == BITSTEP_OK);
  CHECK(std::memcmp(corners, points, sizeof corners) == 0);  // the corners, in input order
  // Refusals name the shape's place, and nothing is made.
  bitstep_vec3 far[] = {points[0], points[1], points[2], {0, units(51), 0}};
  shape.points = far;
  shape.point_count = 4;
  bitstep_body c{};
  CHECK(bitstep_create_body(by_struct, &def, &c) == BITSTEP_INVALID);
  CHECK(std::string(bitstep_last_error(by_struct)) == "create_body: shapes[0].points[3].y: outside -50..50 m");
  shape.points = nullptr;
  CHECK(bitstep_create_body(by_struct, &def, &c) == BITSTEP_INVALID);
  CHECK(std::string(bitstep_last_error(by_struct)) == "create_body: shapes[0].points: NULL with a point_count of 4");
  shape.point_count = 3;
  shape.points = points;
  CHECK(bitstep_create_body(by_struct, &def, &c) == BITSTEP_INVALID);
  CHECK(std::string(bitstep_last_error(by_struct)) ==
        "create_body: shapes[0].points: 3 points: a hull needs 4 to 1024");
  shape.type = BITSTEP_SHAPE_MESH;
  CHECK(bitstep_create_body(by_struct, &def, &c) == BITSTEP_INVALID);
  CHECK(std::string(bitstep_last_error(by_struct)) ==
        "create_body: shapes[0].type: a mesh comes from JSON (bitstep_add_body), not from a struct");
  shape.type = BITSTEP_SHAPE_HEIGHTFIELD;
  CHECK(bitstep_create_body(by_struct, &def, &c) == BITSTEP_INVALID);
  CHECK(std::string(bitstep_last_error(by_struct)) ==
        "create_body: shapes[0].type: a heightfield comes from JSON (bitstep_add_body), not from a struct");
  shape.type = BITSTEP_SHAPE_HEIGHTFIELD + 1;
  CHECK(bitstep_create_body(by_struct, &def, &c) == BITSTEP_INVALID);
  CHECK(std::string(bitstep_last_error(by_struct)) == "create_body: shapes[0].type: not a bitstep_shape_type");
  const bitstep_body ground = body(by_struct, "ground");
  CHECK(bitstep_get_hull_points(by_struct, ground, 0, corners, 6, &count) == BITSTEP_INVALID);
  CHECK(std::string(bitstep_last_error(by_struct)) == "get_hull_points: shape 0 is no hull");
  CHECK(bitstep_get_hull_points(by_struct, b, 0, corners, 6, nullptr) == BITSTEP_NULL_ARGUMENT);
  bitstep_destroy(by_json);
  bitstep_destroy(by_struct);
}

TEST_CASE("C API: a joint from a struct is the joint from JSON, and struck it breaks with an event", "[c_api]") {
  bitstep_simulation* by_json = made();
  bitstep_simulation* by_struct = made();
  bitstep_joint a{}, b{};
  REQUIRE(bitstep_add_joint(by_json, R"({"type": "point", "body_a": "hook", "body_b": "bob", "anchor": [0, 4, 0],
      "break_impulse": 30})",
                            &a) == BITSTEP_OK);
  bitstep_joint_def def = bitstep_default_joint_def();
  def.type = BITSTEP_JOINT_POINT;
  def.body_a = body(by_struct, "hook");
  def.body_b = body(by_struct, "bob");
  def.anchor_a = {0, units(4), 0};
  def.break_impulse = units(30);
  REQUIRE(bitstep_create_joint(by_struct, &def, &b) == BITSTEP_OK);
  CHECK((a.index == b.index && a.generation == b.generation));
  const bitstep_body bob = body(by_struct, "bob");
  int broke_at = -1;
  for (int step = 1; step <= 90; ++step) {
    if (step == 30) {  // a blow along the rod, outward: 40 N s on a 33.5 kg bob (0.2 m of water)
      for (bitstep_simulation* sim : {by_json, by_struct}) {
        REQUIRE(bitstep_apply_impulse(sim, bob, {units(40), 0, 0}, {units(1), units(4), 0}) == BITSTEP_OK);
      }
    }
    REQUIRE(bitstep_step(by_json) == BITSTEP_OK);
    REQUIRE(bitstep_step(by_struct) == BITSTEP_OK);
    REQUIRE(bitstep_hash(by_json) == bitstep_hash(by_struct));
    const std::vector<bitstep_event> x = events_of(by_json), y = events_of(by_struct);  // events off: breaks only
    REQUIRE(x.size() == y.size());
    for (const bitstep_event& e : y) {
      REQUIRE(e.type == BITSTEP_JOINT_BROKEN);
      CHECK((e.joint.index == b.index && e.joint.generation == b.generation));
      CHECK((e.body_a.index == def.body_a.index && e.body_b.index == bob.index));
      CHECK(broke_at < 0);
      broke_at = step;
    }
  }
  CHECK(broke_at == 30);  // the blow's step: 40 N s is past 30
  CHECK(bitstep_remove_joint(by_struct, b) == BITSTEP_NOT_FOUND);
  bitstep_destroy(by_json);
  bitstep_destroy(by_struct);
}

TEST_CASE("C API: every pose at once is each body's pose, in slot order", "[c_api]") {
  bitstep_simulation* sim = made();
  const bitstep_shape shape = thrown_shape();
  const bitstep_body_def def = thrown_def(&shape);
  bitstep_body thrown{};
  REQUIRE(bitstep_create_body(sim, &def, &thrown) == BITSTEP_OK);
  REQUIRE(bitstep_remove_body(sim, body(sim, "hook")) == BITSTEP_OK);  // a dead slot in the middle
  for (int i = 0; i < 30; ++i) REQUIRE(bitstep_step(sim) == BITSTEP_OK);
  size_t count = 0;
  CHECK(bitstep_get_poses(sim, nullptr, 0, &count) == BITSTEP_BUFFER_TOO_SMALL);
  REQUIRE(count == 3);
  std::vector<bitstep_body_pose> poses(2);
  CHECK(bitstep_get_poses(sim, poses.data(), poses.size(), &count) == BITSTEP_BUFFER_TOO_SMALL);
  CHECK(std::string(bitstep_last_error(sim)) == "get_poses: 3 needed, 2 given");
  poses.resize(3);
  REQUIRE(bitstep_get_poses(sim, poses.data(), poses.size(), &count) == BITSTEP_OK);
  std::vector<bitstep_body_render_pose> render(3);
  REQUIRE(bitstep_get_render_poses(sim, render.data(), render.size(), &count) == BITSTEP_OK);
  const uint32_t slots[] = {0, 2, 3};
  for (size_t i = 0; i < 3; ++i) {
    CHECK(poses[i].body.index == slots[i]);
    bitstep_pose one{};
    REQUIRE(bitstep_get_pose(sim, poses[i].body, &one) == BITSTEP_OK);
    CHECK(std::memcmp(&one, &poses[i].pose, sizeof one) == 0);
    bitstep_render_pose r{};
    REQUIRE(bitstep_get_render_pose(sim, render[i].body, &r) == BITSTEP_OK);
    CHECK(std::memcmp(&r, &render[i].pose, sizeof r) == 0);
  }
  bitstep_destroy(sim);
}

TEST_CASE("C API: integers to Q32.32 and back round once, to nearest, ties to even", "[c_api]") {
  CHECK(bitstep_fixed_from_int(-7) == units(-7));
  CHECK(bitstep_fixed_from_int(INT32_MIN) == units(INT32_MIN));
  bitstep_fixed f = 0;
  CHECK(bitstep_fixed_from_ratio(1, 3, &f) == BITSTEP_OK);
  CHECK(f == 1431655765);  // 2^32 / 3 = 1431655765.33
  CHECK(bitstep_fixed_from_ratio(-2, 3, &f) == BITSTEP_OK);
  CHECK(f == -2863311531);                                        // -2863311530.67
  CHECK(bitstep_fixed_from_ratio(1234, 1000, &f) == BITSTEP_OK);  // millimetres
  CHECK(f == 5299989643);                                         // 1.234 * 2^32 = 5299989643.26
  // Ties: 1/2^33 is half an ulp (0 is even), 3/2^33 one and a half (2 is even).
  CHECK(bitstep_fixed_from_ratio(1, int64_t{1} << 33, &f) == BITSTEP_OK);
  CHECK(f == 0);
  CHECK(bitstep_fixed_from_ratio(3, int64_t{1} << 33, &f) == BITSTEP_OK);
  CHECK(f == 2);
  CHECK(bitstep_fixed_from_ratio(INT64_MIN, INT64_MIN, &f) == BITSTEP_OK);
  CHECK(f == units(1));
  f = 99;
  CHECK(bitstep_fixed_from_ratio(1, 0, &f) == BITSTEP_INVALID);
  CHECK(bitstep_fixed_from_ratio(int64_t{1} << 31, 1, &f) == BITSTEP_INVALID);
  CHECK(bitstep_fixed_from_ratio(-(int64_t{1} << 40), 512, &f) == BITSTEP_INVALID);
  CHECK(bitstep_fixed_from_ratio(INT64_MIN, 1, &f) == BITSTEP_INVALID);
  CHECK(f == 99);  // refused, nothing written
  CHECK(bitstep_fixed_from_ratio(1, 1, nullptr) == BITSTEP_NULL_ARGUMENT);
  CHECK(bitstep_fixed_round(units(5) / 2) == 2);
  CHECK(bitstep_fixed_round(units(7) / 2) == 4);
  CHECK(bitstep_fixed_round(-units(5) / 2) == -2);
  CHECK(bitstep_fixed_round(units(5) / 2 + 1) == 3);
  CHECK(bitstep_fixed_round(units(-3) - 1) == -3);
}

TEST_CASE("C API misuse: the struct calls, getters and events name what is wrong and change nothing", "[c_api]") {
  bitstep_simulation* sim = made();
  const uint64_t hash = bitstep_hash(sim);
  const bitstep_body bob = body(sim, "bob");
  const auto refused = [&](bitstep_status got, bitstep_status status, const std::string& message) {
    CHECK(got == status);
    CHECK(std::string(bitstep_last_error(sim)) == message);
    CHECK(bitstep_hash(sim) == hash);
  };
  bitstep_body b{};
  bitstep_joint j{};
  bitstep_vec3 v{};
  int32_t flag = 0;
  uint32_t count32 = 0;
  size_t count = 0;
  bitstep_shape shape = thrown_shape();
  bitstep_body_def def = thrown_def(&shape);
  refused(bitstep_create_body(sim, nullptr, &b), BITSTEP_NULL_ARGUMENT, "create_body: def is NULL");
  refused(bitstep_create_body(sim, &def, nullptr), BITSTEP_NULL_ARGUMENT, "create_body: out is NULL");
  refused(bitstep_create_joint(sim, nullptr, &j), BITSTEP_NULL_ARGUMENT, "create_joint: def is NULL");
  refused(bitstep_get_velocity(sim, bob, nullptr, &v), BITSTEP_NULL_ARGUMENT, "get_velocity: linear is NULL");
  refused(bitstep_is_asleep(sim, bob, nullptr), BITSTEP_NULL_ARGUMENT, "is_asleep: out is NULL");
  refused(bitstep_get_body_name(sim, bob, nullptr, 4, &count), BITSTEP_NULL_ARGUMENT,
          "get_body_name: buffer (of capacity > 0) is NULL");
  refused(bitstep_get_shape_count(sim, bob, nullptr), BITSTEP_NULL_ARGUMENT, "get_shape_count: out is NULL");
  refused(bitstep_get_shape(sim, bob, 0, nullptr), BITSTEP_NULL_ARGUMENT, "get_shape: out is NULL");
  refused(bitstep_get_poses(sim, nullptr, 0, nullptr), BITSTEP_NULL_ARGUMENT, "get_poses: count is NULL");
  refused(bitstep_get_events(sim, nullptr, 3, &count), BITSTEP_NULL_ARGUMENT,
          "get_events: out (of capacity > 0) is NULL");
  // Bad handles.
  const bitstep_body stale{bob.index, bob.generation + 1};
  const std::string no_stale = "no body in slot 2 of generation " + std::to_string(stale.generation);
  refused(bitstep_get_velocity(sim, stale, &v, &v), BITSTEP_NOT_FOUND, no_stale);
  refused(bitstep_is_asleep(sim, {99, 1}, &flag), BITSTEP_NOT_FOUND, "no body in slot 99 of generation 1");
  refused(bitstep_get_shape_count(sim, stale, &count32), BITSTEP_NOT_FOUND, no_stale);
  // Definitions that are not ones: the field named.
  def.type = 7;
  refused(bitstep_create_body(sim, &def, &b), BITSTEP_INVALID, "create_body: type: not a bitstep_body_type");
  def = thrown_def(&shape);
  def.pose.orientation = {0, 0, 0, 0};
  refused(bitstep_create_body(sim, &def, &b), BITSTEP_INVALID, "create_body: pose.orientation: a zero quaternion");
  def = thrown_def(&shape);
  def.shapes = nullptr;
  refused(bitstep_create_body(sim, &def, &b), BITSTEP_INVALID, "create_body: shapes: NULL with a shape_count of 1");
  def = thrown_def(&shape);
  def.shape_count = 0;
  refused(bitstep_create_body(sim, &def, &b), BITSTEP_INVALID, "create_body: shapes: a body needs at least one shape");
  def = thrown_def(&shape);
  def.material.restitution = units(2);
  refused(bitstep_create_body(sim, &def, &b), BITSTEP_INVALID, "create_body: material.restitution: outside 0..1");
  shape.type = 9;
  def = thrown_def(&shape);
  refused(bitstep_create_body(sim, &def, &b), BITSTEP_INVALID, "create_body: shapes[0].type: not a bitstep_shape_type");
  shape = thrown_shape();
  shape.radius = units(100);
  refused(bitstep_create_body(sim, &def, &b), BITSTEP_INVALID, "create_body: shapes[0].radius: outside 0.01..50 m");
  shape = thrown_shape();
  def.name = "bob";
  refused(bitstep_create_body(sim, &def, &b), BITSTEP_INVALID, "create_body: name: \"bob\" is already taken");
  bitstep_joint_def joint = bitstep_default_joint_def();
  joint.body_a = body(sim, "hook");
  joint.body_b = stale;
  refused(bitstep_create_joint(sim, &joint, &j), BITSTEP_INVALID, "create_joint: body_b: not a live body");
  joint.body_b = bob;
  joint.type = -1;
  refused(bitstep_create_joint(sim, &joint, &j), BITSTEP_INVALID, "create_joint: type: not a bitstep_joint_type");
  joint.type = BITSTEP_JOINT_HINGE;  // no axis
  refused(bitstep_create_joint(sim, &joint, &j), BITSTEP_INVALID, "create_joint: axis: shorter than 0.001");
  // A NULL handle: NULL_ARGUMENT, nothing else to report to.
  CHECK(bitstep_create_body(nullptr, &def, &b) == BITSTEP_NULL_ARGUMENT);
  CHECK(bitstep_get_events(nullptr, nullptr, 0, &count) == BITSTEP_NULL_ARGUMENT);
  CHECK(bitstep_set_events(nullptr, 1) == BITSTEP_NULL_ARGUMENT);
  bitstep_destroy(sim);
}
