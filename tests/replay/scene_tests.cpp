#include <catch2/catch.hpp>

#include <algorithm>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>

#include "core/envelope.h"
#include "core/world.h"
#include "fixed/decimal.h"
#include "replay/generators.h"
#include "replay/replay.h"
#include "replay/scene.h"
#include "fixed/splitmix64.h"

using namespace bitstep;

namespace {

const std::string scenes_dir = std::string(BITSTEP_SOURCE_DIR) + "/scenes";

Scene load_ok(std::string_view text) {
  auto result = parse_scene(text, "f.json");
  if (!result.ok()) FAIL(result.error().message());
  return std::move(result).value();
}

Scene load_file_ok(const std::string& name) {
  auto result = load_scene_file(scenes_dir + "/" + name);
  if (!result.ok()) FAIL(result.error().message());
  return std::move(result).value();
}

std::string error_of(std::string_view text) {
  const auto result = parse_scene(text, "f.json");
  if (!result.ok()) return result.error().message();
  return "no error";
}

// A scene with the given "bodies" array contents and extra top-level members.
std::string scene_text(const std::string& bodies, const std::string& extra = "") {
  return R"({"format": "bitstep-scene", "version": 1, )" + extra + R"("bodies": [)" + bodies + "]}";
}

const std::string unit_box = R"("shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}])";

bool same_vec(Vec3 a, Vec3 b) { return a == b; }

bool same_shape(const Shape& a, const Shape& b) {
  return a.type == b.type && same_vec(a.half_extents, b.half_extents) && a.radius == b.radius &&
         a.half_height == b.half_height && a.local == b.local;
}

bool same_body(const SceneBody& a, const SceneBody& b) {
  const BodyDef &x = a.def, &y = b.def;
  bool shapes = x.shapes.size() == y.shapes.size();
  for (size_t i = 0; shapes && i < x.shapes.size(); ++i) shapes = same_shape(x.shapes[i], y.shapes[i]);
  return a.name == b.name && x.type == y.type && x.pose == y.pose && x.linear_velocity == y.linear_velocity &&
         x.angular_velocity == y.angular_velocity && shapes && x.density == y.density && x.mass == y.mass &&
         x.material.static_friction == y.material.static_friction &&
         x.material.dynamic_friction == y.material.dynamic_friction &&
         x.material.restitution == y.material.restitution &&
         x.material.rolling_resistance == y.material.rolling_resistance && x.linear_damping == y.linear_damping &&
         x.angular_damping == y.angular_damping;
}

bool same_settings(const Settings& a, const Settings& b) {
  return a.dt == b.dt && a.gravity == b.gravity && a.velocity_iterations == b.velocity_iterations &&
         a.position_iterations == b.position_iterations && a.penetration_slop == b.penetration_slop &&
         a.split_impulse_factor == b.split_impulse_factor && a.max_push_out_speed == b.max_push_out_speed &&
         a.baumgarte == b.baumgarte && a.baumgarte_factor == b.baumgarte_factor &&
         a.restitution_threshold == b.restitution_threshold && a.speculative_distance == b.speculative_distance &&
         a.max_linear_speed == b.max_linear_speed && a.max_angular_speed == b.max_angular_speed &&
         a.warm_starting == b.warm_starting && a.substeps == b.substeps;
}

bool same_scene(const Scene& a, const Scene& b) {
  if (!same_settings(a.settings, b.settings) || a.bodies.size() != b.bodies.size()) return false;
  for (size_t i = 0; i < a.bodies.size(); ++i) {
    if (!same_body(a.bodies[i], b.bodies[i])) return false;
  }
  return true;
}

Fixed fx(std::string_view text) { return parse_fixed(text).value; }

}  // namespace

TEST_CASE("every shipped scene loads", "[scene]") {
  // Every .json file in scenes/ except golden replays (format bitstep-replay).
  std::vector<std::string> names;
  for (const auto& entry : std::filesystem::directory_iterator(scenes_dir)) {
    if (entry.path().extension() != ".json") continue;
    std::ifstream file(entry.path());
    std::stringstream text;
    text << file.rdbuf();
    if (text.str().find("\"bitstep-replay\"") != std::string::npos) continue;
    names.push_back(entry.path().filename().string());
  }
  std::sort(names.begin(), names.end());
  REQUIRE(names.size() >= 13);
  for (const std::string& name : names) {
    INFO(name);
    const auto result = load_scene_file(scenes_dir + "/" + name);
    if (!result.ok()) FAIL(result.error().message());
    CHECK(result.value().bodies.size() >= 2);
  }
}

TEST_CASE("shipped scenes have the documented body counts", "[scene]") {
  CHECK(load_file_ok("bounce.json").bodies.size() == 2);
  CHECK(load_file_ok("stack20.json").bodies.size() == 20 + 1);
  CHECK(load_file_ok("stack50.json").bodies.size() == 50 + 1);
  CHECK(load_file_ok("pyramid20.json").bodies.size() == 210 + 1);
  CHECK(load_file_ok("wall128.json").bodies.size() == 8256 + 1);
  CHECK(load_file_ok("jenga.json").bodies.size() == 54 + 1);
  CHECK(load_file_ok("dominoes.json").bodies.size() == 40 + 1);
  CHECK(load_file_ok("tables.json").bodies.size() == 5 + 1);
  CHECK(load_file_ok("thrown.json").bodies.size() == 15 + 60 + 1);
  CHECK(load_file_ok("incline.json").bodies.size() == 5);
  CHECK(load_file_ok("slide_stop.json").bodies.size() == 2);
  CHECK(load_file_ok("spheres.json").bodies.size() == 60 + 2);
  CHECK(load_file_ok("dice.json").bodies.size() == 2 + 3 + 10 + 5 + 2);
  CHECK(load_file_ok("terrain.json").bodies.size() == 2 + 4 + 6 + 4 + 3 + ragdoll_parts_count);
  // Ground, pit and the car's chassis, the stacks, pyramid, jenga,
  // dominoes, tables, pile, thrown cubes, balls; the chain (its anchor and
  // 10 links), 3 ragdolls; one car.
  const Scene playground = load_file_ok("playground.json");
  CHECK(playground.bodies.size() == 3 + 10 + 10 + 55 + 54 + 30 + 5 + 15 + 50 + 40 + 11 + 3 * ragdoll_parts_count);
  CHECK(playground.joints.size() == 10 + 3 * ragdoll_joints_count);
  CHECK(playground.cars.size() == 1u);
}

TEST_CASE("shipped scenes: what the physics tests rely on", "[scene]") {
  const Scene bounce = load_file_ok("bounce.json");
  CHECK(bounce.bodies[1].def.material.restitution == 0.5_fx);
  CHECK(bounce.settings.restitution_threshold == 0.1_fx);
  CHECK(bounce.bodies[1].def.pose.position.y == 2.5_fx);  // bottom face at 2 m

  const Scene stack = load_file_ok("stack20.json");
  for (size_t i = 1; i < stack.bodies.size(); ++i) {  // exactly touching: centres at 0.5, 1.5, ...
    CHECK(stack.bodies[i].def.pose.position.y == Fixed::from_ratio(2 * static_cast<int64_t>(i) - 1, 2));
    CHECK(stack.bodies[i].name == "stack." + std::to_string(i - 1));
  }

  const Scene slide = load_file_ok("slide_stop.json");
  CHECK(slide.bodies[0].def.shapes[0].type == ShapeType::plane);
  CHECK(slide.bodies[1].def.linear_velocity == Vec3{5.0_fx, Fixed{}, Fixed{}});

  const Scene incline = load_file_ok("incline.json");
  const Quat tilt = incline.bodies[1].def.pose.orientation;
  CHECK(tilt == incline.bodies[3].def.pose.orientation);
  // 30 degrees about z: (cos 15, 0, 0, sin 15) within a few ulp.
  CHECK(abs(tilt.w - 0.96592582628906829_fx) <= Fixed::from_raw(4));
  CHECK(abs(tilt.z - 0.25881904510252076_fx) <= Fixed::from_raw(4));

  const Scene dominoes = load_file_ok("dominoes.json");
  CHECK(dominoes.bodies[1].def.angular_velocity == Vec3{Fixed{}, Fixed{}, -1.0_fx});  // tips toward +x
  CHECK(dominoes.bodies[1].def.linear_velocity == Vec3{1.0_fx, 0.1_fx, Fixed{}});
  CHECK(dominoes.bodies[2].def.angular_velocity == Vec3{});

  const Scene tables = load_file_ok("tables.json");
  CHECK(tables.bodies[1].def.shapes.size() == 5);
  CHECK(tables.bodies[2].def.pose.position.y - tables.bodies[1].def.pose.position.y ==
        Fixed::from_int(2) * (0.05_fx + 0.35_fx));  // exactly touching: a table's height
}

TEST_CASE("numbers are exact whatever their spelling and key order", "[scene]") {
  const std::string a = R"({
    "format": "bitstep-scene", "version": 1,
    "settings": {"dt": "1/60", "gravity": [0, -9.81, 0], "penetration_slop": 0.005, "velocity_iterations": 8},
    "materials": {"wood": {"static_friction": 0.5, "dynamic_friction": 0.25, "restitution": 0.1,
                           "rolling_resistance": 0.002}},
    "bodies": [{"name": "b", "type": "dynamic", "position": [0.5, 1.5, -2.5], "material": "wood", "density": 1000,
                "velocity": [0.1, 0, 0], "orientation": {"axis": [0, 1, 0], "degrees": 30},
                "shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}]}],
    "generators": [{"type": "stack", "count": 3, "half_extents": [0.5, 0.5, 0.5], "overlap": 0.005}]
  })";
  const std::string b = R"({
    "generators": [{"overlap": "5/1000", "half_extents": ["1/2", 5e-1, 0.50], "count": 3.0, "type": "stack"}],
    "bodies": [{"shapes": [{"half_extents": [5e-1, "raw:80000000", "0.5"], "type": "box"}],
                "orientation": {"degrees": "30", "axis": [0, "raw:100000000", 0]}, "velocity": ["1/10", 0.0, -0],
                "density": "1e3", "material": "wood", "position": ["1/2", 15e-1, "-5/2"], "type": "dynamic", "name": "b"}],
    "materials": {"wood": {"rolling_resistance": "2/1000", "restitution": "1/10", "dynamic_friction": "1/4",
                           "static_friction": 0.5e0}},
    "settings": {"velocity_iterations": "8", "penetration_slop": 5E-3, "gravity": [0, "-981/100", 0], "dt": "raw:4444444"},
    "version": 1, "format": "bitstep-scene"
  })";
  const Scene first = load_ok(a), second = load_ok(b);
  CHECK(same_scene(first, second));
  CHECK(first.settings.dt == "1/60"_fx);
  CHECK(first.bodies[0].def.material.rolling_resistance == 0.002_fx);
  CHECK(first.settings.dt.raw() == 0x4444444);
  CHECK(first.settings.gravity.y == fx("-9.81"));
  CHECK(first.bodies[0].def.linear_velocity.x == 0.1_fx);
  CHECK(first.bodies[0].def.pose.position == Vec3{0.5_fx, 1.5_fx, -2.5_fx});
  REQUIRE(first.bodies.size() == 4);
  CHECK(first.bodies[3].def.pose.position.y == 0.5_fx - 0.005_fx + Fixed::from_int(2) * (1.0_fx - 0.005_fx));
}

TEST_CASE("defaults come from the structs, only present keys override", "[scene]") {
  const Scene scene = load_ok(scene_text("{" + unit_box + "}", R"("settings": {"dt": "1/240"}, )"));
  Settings expected;
  expected.dt = "1/240"_fx;
  CHECK(same_settings(scene.settings, expected));
  SceneBody body;
  body.def.shapes.push_back(Shape{ShapeType::box, {0.5_fx, 0.5_fx, 0.5_fx}, {}, {}, {}});
  CHECK(same_body(scene.bodies[0], body));
}

TEST_CASE("orientation as a quaternion is normalised", "[scene]") {
  const Scene scene = load_ok(scene_text(R"({"orientation": {"quaternion": [2, 0, 0, 0]}, )" + unit_box + "}"));
  CHECK(scene.bodies[0].def.pose.orientation == Quat{});
}

TEST_CASE("scene errors name the file, the JSON path and the reason", "[scene]") {
  SECTION("unknown key") {
    CHECK(error_of(scene_text(R"({"colour": "red", )" + unit_box + "}")) ==
          "f.json: $.bodies[0].colour: unknown key (known keys: name, type, position, orientation, velocity, "
          "angular_velocity, density, mass, material, linear_damping, angular_damping, asleep, layers, collides_with, "
          "sensor, shapes)");
    CHECK(error_of(R"({"format": "bitstep-scene", "version": 1, "setings": {}})") ==
          "f.json: $.setings: unknown key (known keys: format, version, description, settings, materials, bodies, "
          "generators, joints, cars, characters)");
    CHECK(error_of(scene_text(R"({"shapes": [{"type": "sphere", "radius": 1, "half_extents": [1, 1, 1]}]})")) ==
          "f.json: $.bodies[0].shapes[0].half_extents: unknown key (known keys: type, radius, position, orientation)");
  }
  SECTION("wrong type") {
    CHECK(error_of(scene_text(R"({"position": "up", )" + unit_box + "}")) ==
          "f.json: $.bodies[0].position: expected an array of 3 numbers, got a string");
    CHECK(error_of(scene_text(R"({"position": [1, 2], )" + unit_box + "}")) ==
          "f.json: $.bodies[0].position: expected 3 numbers, got 2");
    CHECK(error_of(scene_text(R"({"position": [1, true, 2], )" + unit_box + "}")) ==
          "f.json: $.bodies[0].position[1]: expected a number, got a boolean");
    CHECK(error_of(scene_text(R"({"type": "floating", )" + unit_box + "}")) ==
          "f.json: $.bodies[0].type: expected \"static\", \"kinematic\" or \"dynamic\", got \"floating\"");
    CHECK(error_of(scene_text("", R"("settings": {"warm_starting": 1}, )")) ==
          "f.json: $.settings.warm_starting: expected true or false, got a number");
  }
  SECTION("bad number text") {
    CHECK(error_of(scene_text(R"({"shapes": [{"type": "sphere", "radius": "abc"}]})")) ==
          "f.json: $.bodies[0].shapes[0].radius: bad number \"abc\": not a number (expected decimal, ratio a/b or "
          "raw:<hex>)");
    CHECK(error_of(scene_text(R"({"shapes": [{"type": "sphere", "radius": "1/0"}]})")) ==
          "f.json: $.bodies[0].shapes[0].radius: bad number \"1/0\": ratio with a zero denominator");
    CHECK(error_of(scene_text("", R"("settings": {"velocity_iterations": 2.5}, )")) ==
          "f.json: $.settings.velocity_iterations: expected an integer, got \"2.5\"");
  }
  SECTION("out-of-range number") {
    CHECK(error_of(scene_text(R"({"velocity": [1e20, 0, 0], )" + unit_box + "}")) ==
          "f.json: $.bodies[0].velocity[0]: bad number \"1e20\": outside the Q32.32 range [-2147483648, "
          "2147483647.99999999977]");
    CHECK(error_of(scene_text("", R"("materials": {"wood": {"restitution": 1.5}}, )")) ==
          "f.json: $.materials.wood.restitution: outside 0..1");
    CHECK(error_of(scene_text("", R"("materials": {"wood": {"rolling_resistance": -0.001}}, )")) ==
          "f.json: $.materials.wood.rolling_resistance: outside 0..1");
    CHECK(error_of(scene_text("", R"("settings": {"velocity_iterations": 0}, )")) ==
          "f.json: $.settings.velocity_iterations: outside 1..1000");
    CHECK(error_of(scene_text("", R"("settings": {"dt": 0}, )")) == "f.json: $.settings.dt: outside 0.0001..0.1 s");
  }
  SECTION("settings outside the world envelope") {
    // Each aborted the checked build (dt 1000 s, dt of one raw unit) or let
    // a velocity clamp admit products the envelope does not bound.
    const auto settings_error = [&](const std::string& settings) {
      return error_of(scene_text("", R"("settings": {)" + settings + "}, "));
    };
    CHECK(settings_error(R"("dt": 1000)") == "f.json: $.settings.dt: outside 0.0001..0.1 s");
    CHECK(settings_error(R"("dt": "raw:1")") == "f.json: $.settings.dt: outside 0.0001..0.1 s");
    CHECK(settings_error(R"("gravity": [0, -1e6, 0])") == "f.json: $.settings.gravity[1]: outside +-1000 m/s^2");
    CHECK(settings_error(R"("max_linear_speed": 501)") == "f.json: $.settings.max_linear_speed: outside 0..500 m/s");
    CHECK(settings_error(R"("max_linear_speed": 0)") == "f.json: $.settings.max_linear_speed: must be > 0");
    CHECK(settings_error(R"("max_angular_speed": 1000)") ==
          "f.json: $.settings.max_angular_speed: outside 0..100 rad/s");
    CHECK(settings_error(R"("max_push_out_speed": 1e6)") ==
          "f.json: $.settings.max_push_out_speed: outside 0..500 m/s");
    CHECK(settings_error(R"("restitution_threshold": 600)") ==
          "f.json: $.settings.restitution_threshold: outside 0..500 m/s");
    CHECK(settings_error(R"("speculative_distance": 1e5)") == "f.json: $.settings.speculative_distance: outside 0..50 m");
    CHECK(settings_error(R"("penetration_slop": 51)") == "f.json: $.settings.penetration_slop: outside 0..50 m");
    CHECK(settings_error(R"("substeps": 0)") == "f.json: $.settings.substeps: outside 1..16");
    CHECK(settings_error(R"("substeps": 17)") == "f.json: $.settings.substeps: outside 1..16");
    // Each substep's dt stays inside the envelope, whichever key comes first.
    CHECK(settings_error(R"("substeps": 2, "dt": 0.0001)") ==
          "f.json: $.settings.substeps: dt / substeps below 0.0001 s (the shortest step of the world envelope)");
    CHECK(settings_error(R"("dt": 0.0001, "substeps": 2)") ==
          "f.json: $.settings.substeps: dt / substeps below 0.0001 s (the shortest step of the world envelope)");
    CHECK(load_ok(scene_text("", R"("settings": {"substeps": 16, "dt": 0.0016}, )")).settings.substeps == 16);
    CHECK(settings_error(R"("soft_substeps": 17)") == "f.json: $.settings.soft_substeps: outside 0..16");
    CHECK(settings_error(R"("soft_substeps": 4, "substeps": 4, "dt": 0.001)") ==
          "f.json: $.settings.soft_substeps: dt / (substeps x soft_substeps) below 0.0001 s (the shortest step of "
          "the world envelope)");
    CHECK(settings_error(R"("contact_hertz": 1001)") == "f.json: $.settings.contact_hertz: outside 0..1000 Hz");
    CHECK(settings_error(R"("contact_damping_ratio": -1)") ==
          "f.json: $.settings.contact_damping_ratio: outside 0..1000");
    const Settings soft = load_ok(scene_text("", R"("settings": {"soft_substeps": 4, "contact_hertz": 60, )"
                                                 R"("contact_damping_ratio": 5}, )"))
                              .settings;
    CHECK((soft.soft_substeps == 4 && soft.contact_hertz == 60.0_fx && soft.contact_damping_ratio == 5.0_fx));
    // The bounds themselves are admitted, and the core check agrees.
    Scene edge = load_ok(scene_text("", R"("settings": {"dt": 0.1, "gravity": [1000, -1000, 0], )"
                                        R"("max_linear_speed": 500, "max_angular_speed": 100}, )"));
    CHECK(check_settings(edge.settings).ok());
    edge.settings.dt = 0.2_fx;
    CHECK(check_settings(edge.settings).error().place == "dt");
    edge.settings.dt = 0.0016_fx;
    edge.settings.substeps = 16;
    CHECK(check_settings(edge.settings).ok());
    edge.settings.substeps = 17;
    CHECK(check_settings(edge.settings).error().place == "substeps");
    edge.settings.dt = 0.0015_fx;
    edge.settings.substeps = 16;
    CHECK(check_settings(edge.settings).error().place == "substeps");
    edge.settings.substeps = 1;
    edge.settings.dt = 0.0016_fx;
    edge.settings.soft_substeps = 16;
    CHECK(check_settings(edge.settings).ok());
    edge.settings.soft_substeps = 17;
    CHECK(check_settings(edge.settings).error().place == "soft_substeps");
    edge.settings.soft_substeps = 4;
    edge.settings.contact_hertz = 1001.0_fx;
    CHECK(check_settings(edge.settings).error().place == "contact_hertz");
  }
  SECTION("missing key") {
    CHECK(error_of(scene_text(R"({"shapes": [{"type": "box"}]})")) ==
          "f.json: $.bodies[0].shapes[0]: missing key \"half_extents\"");
    CHECK(error_of(scene_text(R"({"shapes": [{"half_extents": [1, 1, 1]}]})")) ==
          "f.json: $.bodies[0].shapes[0]: missing key \"type\"");
    CHECK(error_of(scene_text(R"({"type": "static"})")) == "f.json: $.bodies[0]: missing key \"shapes\"");
    CHECK(error_of(R"({"version": 1, "bodies": []})") == "f.json: $: missing key \"format\"");
  }
  SECTION("unknown material") {
    CHECK(error_of(scene_text(R"({"material": "stone", )" + unit_box + "}", R"("materials": {"wood": {}}, )")) ==
          "f.json: $.bodies[0].material: unknown material \"stone\" (defined: \"wood\")");
    CHECK(error_of(scene_text("", R"("materials": {"oak wood": {"colour": 1}}, )")) ==
          "f.json: $.materials[\"oak wood\"].colour: unknown key (known keys: static_friction, dynamic_friction, "
          "restitution, rolling_resistance)");
    std::string many = R"("materials": {)";
    for (int i = 0; i < 1000; ++i) many += (i == 0 ? "" : ", ") + ("\"m" + std::to_string(i) + "\": {}");
    CHECK(error_of(scene_text(R"({"material": "stone", )" + unit_box + "}", many + "}, ")) ==
          "f.json: $.bodies[0].material: unknown material \"stone\" (defined: \"m0\", \"m1\", \"m2\", \"m3\", \"m4\", "
          "\"m5\", \"m6\", \"m7\", ... (1000 in all))");
    CHECK(error_of(scene_text(R"({"material": "a\nb", )" + unit_box + "}")) ==
          "f.json: $.bodies[0].material: unknown material \"a\\u000ab\" (defined: none)");
    CHECK(error_of(R"({"format": "bitstep-scene", "version": 1,
                       "generators": [{"type": "stack", "material": "stone"}]})") ==
          "f.json: $.generators[0].material: unknown material \"stone\" (defined: none)");
  }
  SECTION("envelope violation") {
    CHECK(error_of(scene_text(R"({"shapes": [{"type": "box", "half_extents": [60, 1, 1]}]})")) ==
          "f.json: $.bodies[0].shapes[0].half_extents: outside 0.01..50 m");
    CHECK(error_of(scene_text(R"({"position": [0, 20000, 0], )" + unit_box + "}")) ==
          "f.json: $.bodies[0].position: outside +-16000 m");
    CHECK(error_of(scene_text(R"({"shapes": []})")) == "f.json: $.bodies[0].shapes: a body needs at least one shape");
    CHECK(error_of(scene_text(R"({"type": "dynamic", "shapes": [{"type": "plane"}]})")) ==
          "f.json: $.bodies[0].shapes[0].type: a plane belongs to a static body");
    CHECK(error_of(R"({"format": "bitstep-scene", "version": 1,
                       "generators": [{"type": "stack", "count": 10000, "half_extents": [1, 1, 1]}]})") ==
          "f.json: $.generators[0]: generated body \"stack.8000\": position outside +-16000 m");
    CHECK(error_of(R"({"format": "bitstep-scene", "version": 1,
                       "generators": [{"type": "stack", "count": 2, "half_extents": [0.001, 0.5, 0.5]}]})") ==
          "f.json: $.generators[0].half_extents[0]: outside 0.01..50 m");
    CHECK(error_of(scene_text(R"({"velocity": [0, 600, 0], )" + unit_box + "}")) ==
          "f.json: $.bodies[0].velocity: faster than 500 m/s");
    CHECK(error_of(scene_text(R"({"velocity": [300, 300, 300], )" + unit_box + "}")) ==
          "f.json: $.bodies[0].velocity: faster than 500 m/s");
  }
  SECTION("malformed JSON") {
    CHECK(error_of(R"({"format": "bitstep-scene",})") ==
          "f.json: byte 28: malformed JSON: line 1, column 28: syntax error while parsing object key - unexpected "
          "'}'; expected string literal");
    CHECK(error_of("") ==
          "f.json: byte 1: malformed JSON: line 1, column 1: syntax error while parsing value - unexpected end of "
          "input; expected '[', '{', or a literal");
    CHECK(error_of(R"({"format": "bitstep-scene", "format": "x"})") == "f.json: $.format: duplicate key");
    CHECK(error_of(std::string(100, '[') + std::string(100, ']')) ==
          "f.json: $" + [] {
            std::string path;
            for (int i = 0; i < 64; ++i) path += "[0]";
            return path;
          }() + ": nesting deeper than 64 levels");
  }
  SECTION("wrong format or version") {
    CHECK(error_of(R"({"format": "bitstep-replay", "version": 1})") ==
          "f.json: $.format: expected \"bitstep-scene\", got \"bitstep-replay\"");
    CHECK(error_of(R"({"format": "bitstep-scene", "version": 2})") ==
          "f.json: $.version: unsupported version 2 (this build reads version 1)");
    CHECK(error_of(R"([1, 2])") == "f.json: $: expected an object, got an array");
  }
  SECTION("names and generators") {
    CHECK(error_of(scene_text(R"({"name": "a", )" + unit_box + R"(}, {"name": "a", )" + unit_box + "}")) ==
          "f.json: $.bodies[1].name: duplicate body name \"a\"");
    CHECK(error_of(scene_text(R"({"name": "stack.1", )" + unit_box + "}", R"("generators": [{"type": "stack"}], )")) ==
          "f.json: $.generators[0]: generated body name \"stack.1\" is already taken");
    CHECK(error_of(R"({"format": "bitstep-scene", "version": 1, "generators": [{"type": "tower"}]})") ==
          "f.json: $.generators[0].type: expected \"stack\", \"pyramid\", \"wall\", \"jenga\", \"dominoes\", "
          "\"tables\", \"throw\", \"chain\" or \"ragdoll\", got \"tower\"");
    CHECK(error_of(R"({"format": "bitstep-scene", "version": 1, "generators": [{"type": "stack", "base": 3}]})") ==
          "f.json: $.generators[0].base: unknown key (known keys: type, name, material, density, mass, asleep, count, "
          "half_extents, position, overlap, direction, layers, collides_with)");
    CHECK(error_of(R"({"format": "bitstep-scene", "version": 1, "generators": [{"type": "throw", "count": 100,
                       "spread": [0, 0, 0]}]})") ==
          "f.json: $.generators[0]: no free spot for body 1 after 1000 draws: make \"spread\" larger or \"count\" "
          "smaller");
  }
  SECTION("unreadable file") {
    const auto result = load_scene_file(scenes_dir + "/no_such_scene.json");
    REQUIRE(!result.ok());
    CHECK(result.error().message() ==
          scenes_dir + "/no_such_scene.json: cannot read the file (no such regular file)");
  }
}

TEST_CASE("generators: counts, names and exact placement", "[scene]") {
  WallParams wall;
  wall.base = 128;
  CHECK(generate_wall(wall).size() == 8256);
  wall.shape = WallShape::rectangle;
  wall.base = 10;
  wall.rows = 4;
  const auto rectangle = generate_wall(wall);
  REQUIRE(rectangle.size() == 40);
  // Running bond: odd rows shifted by half a brick (0.25 m).
  CHECK(rectangle[10].def.pose.position.x - rectangle[0].def.pose.position.x == 0.25_fx);
  CHECK(rectangle[20].def.pose.position.x == rectangle[0].def.pose.position.x);

  PyramidParams pyramid;
  pyramid.base = 20;
  const auto boxes = generate_pyramid(pyramid);
  REQUIRE(boxes.size() == 210);
  CHECK(boxes[0].def.pose.position == Vec3{-9.5_fx, 0.5_fx, Fixed{}});
  CHECK(boxes[209].def.pose.position == Vec3{Fixed{}, 19.5_fx, Fixed{}});
  CHECK(boxes[209].name == "pyramid.209");

  JengaParams jenga;
  const auto blocks = generate_jenga(jenga);
  REQUIRE(blocks.size() == 54);
  CHECK(blocks[0].def.shapes[0].half_extents == Vec3{0.375_fx, 0.075_fx, 0.125_fx});
  CHECK(blocks[3].def.shapes[0].half_extents == Vec3{0.125_fx, 0.075_fx, 0.375_fx});  // turned 90 degrees
  CHECK(blocks[0].def.pose.position == Vec3{Fixed{}, 0.075_fx, -0.25_fx});
  CHECK(blocks[4].def.pose.position == Vec3{Fixed{}, Fixed::from_int(3) * 0.075_fx, Fixed{}});
  CHECK(blocks[53].def.pose.position.y == 0.075_fx + Fixed::from_int(17) * 0.15_fx);

  TableParams tables;
  const auto table = generate_tables(tables);
  REQUIRE(table.size() == 5);
  CHECK(table[0].def.pose.position.y == 0.05_fx + 0.35_fx);
  CHECK(table[0].def.shapes[0].local.position.y == 0.35_fx);  // top: 0.7 + 0.05 above the floor
  CHECK(table[0].def.shapes[1].local.position == Vec3{0.05_fx - 0.6_fx, -0.05_fx, 0.05_fx - 0.4_fx});

  StackParams stack;
  stack.count = 3;
  stack.overlap = 0.005_fx;
  const auto stacked = generate_stack(stack);
  CHECK(stacked[0].def.pose.position.y == 0.495_fx);
  CHECK(stacked[2].def.pose.position.y == 0.5_fx - 0.005_fx + Fixed::from_int(2) * (1.0_fx - 0.005_fx));
}

TEST_CASE("a stack grows along its direction, +y as before", "[scene]") {
  auto stack_of = [](const std::string& keys) {
    return load_ok(R"({"format": "bitstep-scene", "version": 1, "generators": [{"type": "stack", "count": 3, )" + keys +
                   "}]}")
        .bodies;
  };
  // Default and "+y" are the stack the goldens were recorded with, bit for bit.
  const auto up = stack_of(R"("position": [1, 2, 3], "overlap": 0.005)");
  const auto plus_y = stack_of(R"("position": [1, 2, 3], "overlap": 0.005, "direction": "+y")");
  REQUIRE(up.size() == 3);
  for (size_t i = 0; i < up.size(); ++i) CHECK(same_body(up[i], plus_y[i]));
  CHECK(up[2].def.pose.position == Vec3{1.0_fx, 2.0_fx + 0.495_fx + Fixed::from_int(2) * 0.995_fx, 3.0_fx});

  // Along x: the half-extent along x is the half height; y and z stay put.
  const auto along_x = stack_of(R"("half_extents": [0.25, 0.5, 0.5], "position": [1, 2, 3], "direction": "+x")");
  REQUIRE(along_x.size() == 3);
  for (size_t i = 0; i < along_x.size(); ++i) {
    CHECK(along_x[i].def.pose.position == Vec3{1.0_fx + 0.25_fx + Fixed::from_int(static_cast<int>(i)) * 0.5_fx, 2.0_fx, 3.0_fx});
    CHECK(along_x[i].def.shapes[0].half_extents == Vec3{0.25_fx, 0.5_fx, 0.5_fx});
  }
  const auto down_z = stack_of(R"("position": [0, 5, 0], "direction": "-z")");
  CHECK(down_z[1].def.pose.position == Vec3{Fixed{}, 5.0_fx, -1.5_fx});
  const auto down_y = stack_of(R"("position": [0, 5, 0], "direction": "-y", "overlap": 0.25)");
  CHECK(down_y[1].def.pose.position.y == 5.0_fx - (0.25_fx + 0.75_fx));

  CHECK(error_of(R"({"format": "bitstep-scene", "version": 1, "generators": [{"type": "stack", "direction": "up"}]})") ==
        "f.json: $.generators[0].direction: expected \"+x\", \"-x\", \"+y\", \"-y\", \"+z\" or \"-z\", got \"up\"");
  // The overlap is checked against the half height along the direction.
  CHECK(error_of(R"({"format": "bitstep-scene", "version": 1, "generators": [{"type": "stack", "direction": "+x",
                     "half_extents": [0.1, 1, 1], "overlap": 0.2}]})") ==
        "f.json: $.generators[0].overlap: must be less than the boxes' half height");
}

TEST_CASE("generators take a per-body mass instead of a density", "[scene]") {
  auto generated = [](const std::string& generator) {
    return R"({"format": "bitstep-scene", "version": 1, "generators": [)" + generator + "]}";
  };
  // Each generator type with a key that keeps it small.
  for (const char* type_and_size : {R"("stack", "count": 2)", R"("pyramid", "base": 2)", R"("wall", "base": 2)",
                                           R"("jenga", "levels": 1)", R"("dominoes", "count": 2)",
                                           R"("tables", "count": 2)", R"("throw", "count": 2)"}) {
    INFO(type_and_size);
    const Scene scene = load_ok(generated(R"({"type": )" + std::string(type_and_size) + R"(, "mass": 2.5})"));
    REQUIRE_FALSE(scene.bodies.empty());
    for (const SceneBody& body : scene.bodies) CHECK(body.def.mass == 2.5_fx);
  }
  // The world gives the body that mass, whatever its size.
  World world;
  const Scene light = load_ok(generated(R"({"type": "stack", "count": 1, "half_extents": [2, 2, 2], "mass": 2})"));
  const BodyId id = world.create_body(light.bodies[0].def).value();
  CHECK(world.bodies()[id.index].inverse_mass == 0.5_fx);
  // Without "mass", the density as before.
  CHECK(load_ok(generated(R"({"type": "stack", "count": 1, "density": 500})")).bodies[0].def.mass == Fixed{});

  CHECK(error_of(generated(R"({"type": "stack", "mass": 0.001})")) == "f.json: $.generators[0].mass: outside 0.01..100000 kg");
  CHECK(error_of(generated(R"({"type": "wall", "mass": 100001})")) == "f.json: $.generators[0].mass: outside 0.01..100000 kg");
  CHECK(error_of(generated(R"({"type": "throw", "mass": "heavy"})")).rfind("f.json: $.generators[0].mass: bad number", 0) == 0);
  CHECK(error_of(generated(R"({"type": "jenga", "density": 500, "mass": 1})")) ==
        "f.json: $.generators[0].mass: give \"mass\" or \"density\", not both");
}

TEST_CASE("throw is a pure function of its seed", "[scene]") {
  ThrowParams params;
  const ThrowResult a = generate_throw(params), b = generate_throw(params);
  REQUIRE(a.placed_all);
  REQUIRE(a.bodies.size() == 50);
  bool all_same = true;
  for (size_t i = 0; i < a.bodies.size(); ++i) all_same = all_same && same_body(a.bodies[i], b.bodies[i]);
  CHECK(all_same);
  params.seed = 2;
  const ThrowResult c = generate_throw(params);
  CHECK_FALSE(same_body(a.bodies[0], c.bodies[0]));
  for (const SceneBody& body : a.bodies) {
    const Vec3 p = body.def.pose.position;
    CHECK(abs(p.x) <= 2.0_fx);
    CHECK(abs(p.y - 5.0_fx) <= 2.0_fx);
    CHECK(abs(length(body.def.linear_velocity) - 10.0_fx) <= Fixed::from_raw(64));
  }
  // Golden values: a change here moves every scene that throws (SplitMix64 seed 1).
  CHECK(to_raw_string(a.bodies[0].def.pose.position.x) == "raw:4428b7b2");
  CHECK(to_raw_string(a.bodies[0].def.pose.orientation.w) == "raw:-1e87210c");
  CHECK(to_raw_string(a.bodies[49].def.linear_velocity.z) == "raw:a01ac430");
}

TEST_CASE("hostile values are refused, never a crash or a checked-build abort", "[scene]") {
  const std::vector<std::string> bodies = {
      R"({"velocity": [2147483647, 2147483647, -2147483648], )" + unit_box + "}",
      R"({"angular_velocity": [2147483647, 2147483647, 2147483647], )" + unit_box + "}",
      R"({"position": [2147483647, 2147483647, 2147483647], )" + unit_box + "}",
      R"({"mass": 2147483647, )" + unit_box + "}",
      R"({"shapes": [{"type": "box", "half_extents": [2147483647, -2147483648, 1],
                      "position": [2147483647, 0, 0], "orientation": {"quaternion": [0, 0, 0, "raw:1"]}}]})",
      R"({"shapes": [{"type": "capsule", "radius": -2147483648, "half_height": 2147483647}]})",
  };
  for (const std::string& body : bodies) {
    INFO(body);
    CHECK(error_of(scene_text(body)) != "no error");
  }
  // Extreme but valid orientations load.
  const std::vector<std::string> orientations = {
      R"({"axis": [2147483647, 2147483647, 2147483647], "degrees": 2147483647})",
      R"({"quaternion": [2147483647, -2147483648, 2147483647, 2147483647]})",
      R"({"axis": ["raw:1", 0, 0], "radians": -2147483648})",
  };
  for (const std::string& orientation : orientations) {
    INFO(orientation);
    CHECK(error_of(scene_text(R"({"orientation": )" + orientation + ", " + unit_box + "}")) == "no error");
  }
  const std::vector<std::string> generators = {
      R"({"type": "stack", "count": 10000, "half_extents": [50, 50, 50], "position": [0, 2147483647, 0]})",
      R"({"type": "pyramid", "base": 1000, "gap": 2147483647})",
      R"({"type": "wall", "base": 1000, "rows": 1000, "shape": "rectangle", "half_extents": [2147483647, 1, 1]})",
      R"({"type": "jenga", "levels": 10000, "half_extents": [1, 2147483647, 1]})",
      R"({"type": "dominoes", "count": 100000, "spacing": 2147483647, "push": 2147483647})",
      R"({"type": "dominoes", "count": 1, "push": 2147483647})",
      R"({"type": "tables", "count": 1000, "top_half_extents": [2147483647, 2147483647, 2147483647]})",
      R"({"type": "throw", "count": 2, "position": [2147483647, 0, 0], "spread": [1000, 1000, 1000],
          "target": [-2147483648, 0, 0], "speed": 500, "half_extents": [2147483647, 1, 1]})",
      R"({"type": "throw", "count": 2, "shapes": ["capsule"], "radius": 2147483647, "half_height": 2147483647})",
  };
  for (const std::string& generator : generators) {
    INFO(generator);
    CHECK(error_of(R"({"format": "bitstep-scene", "version": 1, "generators": [)" + generator + "]}") != "no error");
  }
}

TEST_CASE("mutated scenes load or fail cleanly", "[scene]") {
  // Seeded byte mutations of the shipped scenes: every result is a scene or
  // an error with a message, under ASan/UBSan and the checked build too.
  const std::string pieces[] = {"0",  "9",  "-",  ".",  "e",  "/",  "\"", "{",  "}",  "[",  "]",
                                ",",  ":",  " ",  "1e9", "99999999999", "raw:7fffffffffffffff", "-2147483648", "null"};
  SplitMix64 rng{42};
  int loaded = 0, refused = 0;
  for (const char* name : {"bounce.json", "incline.json", "tables.json", "playground.json", "spheres.json"}) {
    std::ifstream file(scenes_dir + "/" + name);
    std::stringstream buffer;
    buffer << file.rdbuf();
    const std::string original = buffer.str();
    REQUIRE_FALSE(original.empty());
    for (int trial = 0; trial < 300; ++trial) {
      std::string text = original;
      const int edits = 1 + rng.below(3);
      for (int e = 0; e < edits; ++e) {
        const auto at = static_cast<size_t>(rng.below(static_cast<int>(text.size())));
        const std::string& piece = pieces[rng.below(static_cast<int>(std::size(pieces)))];
        switch (rng.below(3)) {
          case 0: text.replace(at, 1, piece); break;
          case 1: text.insert(at, piece); break;
          default: text.erase(at, 1 + static_cast<size_t>(rng.below(8))); break;
        }
      }
      const auto result = parse_scene(text, name);
      if (!result.ok()) {
        ++refused;
        REQUIRE_FALSE(result.error().reason.empty());
        REQUIRE(result.error().message().find('\n') == std::string::npos);
      } else {
        ++loaded;
      }
    }
  }
  CHECK(refused > 0);
  CHECK(loaded > 0);
}

TEST_CASE("collision filters: layer numbers in scenes and generators, errors with their paths", "[scene][filter]") {
  const Scene scene = load_ok(scene_text(R"({"name": "a", "layers": [1, 3], "collides_with": [0], )" + unit_box + "}",
                                         R"("generators": [{"type": "stack", "count": 2, "layers": [4]}], )"));
  REQUIRE(scene.bodies.size() == 3u);
  CHECK(scene.bodies[0].def.filter == CollisionFilter{0b1010, 0b1});
  CHECK(scene.bodies[1].def.filter == CollisionFilter{0b10000, UINT32_MAX});
  CHECK(scene.bodies[2].def.filter == CollisionFilter{0b10000, UINT32_MAX});
  const Scene plain = load_ok(scene_text("{" + unit_box + "}"));
  CHECK(plain.bodies[0].def.filter == CollisionFilter{});
  CHECK(error_of(scene_text(R"({"layers": [32], )" + unit_box + "}")) ==
        "f.json: $.bodies[0].layers[0]: outside 0..31");
  CHECK(error_of(scene_text(R"({"collides_with": 3, )" + unit_box + "}")) ==
        "f.json: $.bodies[0].collides_with: expected an array of layer numbers 0..31, got a number");
}

TEST_CASE("cars: a chassis by name, wheels, parameters in range, errors with their paths", "[scene][car]") {
  const std::string chassis = R"({"name": "c", "mass": 1000, "shapes": [{"type": "box", "half_extents": [0.9, 0.3, 2]}]})";
  const std::string wheels = R"("wheels": [{"attachment": [0.8, -0.3, 1.4], "steered": true}, {"attachment": [0, -0.3, -1.4], "driven": true}])";
  const Scene scene = load_ok(scene_text(chassis, R"("cars": [{"name": "car", "chassis": "c", "grip": 0.9, "rays_per_wheel": 3, )" + wheels + "}], "));
  REQUIRE(scene.cars.size() == 1u);
  CHECK(scene.cars[0].name == "car");
  CHECK(scene.cars[0].chassis == 0u);
  CHECK(scene.cars[0].def.grip == 0.9_fx);
  CHECK(scene.cars[0].def.rays_per_wheel == 3);
  REQUIRE(scene.cars[0].def.wheels.size() == 2u);
  CHECK(scene.cars[0].def.wheels[0].steered);
  CHECK(scene.cars[0].def.wheels[1].driven);
  CHECK(scene.cars[0].def.stiffness == CarDef{}.stiffness);  // defaults from the struct
  World world;
  REQUIRE(build_world(scene, world).ok());
  CHECK(world.cars().size() == 1u);
  CHECK(error_of(scene_text(chassis, R"("cars": [{"name": "car", "chassis": "d", )" + wheels + "}], ")) ==
        "f.json: $.cars[0].chassis: no body named \"d\"");
  CHECK(error_of(scene_text(chassis, R"("cars": [{"name": "car", "chassis": "c", "wheels": []}], )")) ==
        "f.json: $.cars[0].wheels: expected an array of 1..8 wheels");
  CHECK(error_of(scene_text(chassis, R"("cars": [{"name": "car", "chassis": "c", "grip": 11, )" + wheels + "}], ")) ==
        "f.json: $.cars[0].grip: outside 0..10");
  CHECK(error_of(scene_text(R"({"name": "s", "type": "static", "shapes": [{"type": "box", "half_extents": [1, 1, 1]}]})",
                            R"("cars": [{"name": "car", "chassis": "s", )" + wheels + "}], ")) ==
        "f.json: $.cars[0].chassis: the chassis must be a dynamic body");
}
