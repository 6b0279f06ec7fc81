// The state is described once (replay/state_description.h): whatever the
// hash and the snapshot hold, the dump shows, so `diff` names every desync.
#include <xxhash.h>

#include <algorithm>
#include <catch2/catch.hpp>
#include <set>
#include <string>

#include "replay/snapshot.h"
#include "replay/state_dump.h"
#include "replay/state_hash.h"
#include "tests/replay/image_seal.h"
#include "tests/replay/test_scenes.h"

using namespace bitstep;

namespace {

constexpr size_t header_bytes = 8 + 4 + 8;

// "$.bodies[7].linear_velocity[1]: 1 vs 2" -> "$.bodies[].linear_velocity[]".
std::string field_of(const std::string& difference) {
  std::string path = difference.substr(0, difference.find(':'));
  std::string out;
  for (size_t i = 0; i < path.size(); ++i) {
    out += path[i];
    if (path[i] == '[') {
      while (i + 1 < path.size() && path[i + 1] != ']') ++i;
    }
  }
  return out;
}

// A small world with every kind of part: a static ground, a stack of two
// boxes, a sphere, a capsule and a two-box compound, materials of their own.
const char* const small_scene = R"({"format": "bitstep-scene", "version": 1,
  "materials": {"m": {"static_friction": 0.6, "dynamic_friction": 0.4, "restitution": 0.1, "rolling_resistance": 0.01}},
  "bodies": [
    {"type": "static", "position": [0, -1, 0], "shapes": [{"type": "box", "half_extents": [20, 1, 20]}]},
    {"position": [0, 0.5, 0], "material": "m", "shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}]},
    {"position": [0.1, 1.5, 0], "angular_damping": 0.1, "shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}]},
    {"position": [3, 0.5, 0], "velocity": [1, 0, 0], "shapes": [{"type": "sphere", "radius": 0.5}]},
    {"position": [-3, 0.5, 0], "shapes": [{"type": "capsule", "radius": 0.5, "half_height": 0.5}]},
    {"position": [0, 0.5, 3], "linear_damping": 0.05, "shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]},
      {"type": "box", "half_extents": [0.25, 0.25, 0.25], "position": [0.75, 0, 0]}]},
    {"position": [6, 0.5, 6], "shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}]}]})";

}  // namespace

TEST_CASE("every byte of the state is in the dump: flipped, it is restored and dumped differently or refused",
          "[snapshot][dump]") {
  for (const bool sleep : {false, true}) {
    INFO("sleep " << sleep);
    auto parsed = parse_scene(small_scene, "small.json");
    if (!parsed.ok()) FAIL(parsed.error().message());
    Scene scene = parsed.value();
    // With sleep, the sleep block of the settings and of every body.
    if (sleep) scene.settings.sleep_method = SleepMethod::motion;
    World world(scene.settings);
    REQUIRE(build_world(scene, world).ok());
    // A hinge with limits between the stacked boxes and a rope from the
    // sphere to the ground: every joint field set.
    JointDef hinge;
    hinge.type = JointType::hinge;
    hinge.body_a = {1, 0};
    hinge.body_b = {2, 0};
    hinge.anchor_a = {0.05_fx, 1.0_fx, Fixed{}};
    hinge.axis = {Fixed{}, Fixed{}, Fixed::one()};
    hinge.limited = true;
    hinge.lower_angle = -0.5_fx;
    hinge.upper_angle = 0.25_fx;
    hinge.break_impulse = 1000.0_fx;
    REQUIRE(world.create_joint(hinge).ok());
    JointDef rope;
    rope.type = JointType::max_distance;
    rope.body_a = {0, 0};
    rope.body_b = {3, 0};
    rope.anchor_a = {3.0_fx, Fixed{}, Fixed{}};
    rope.anchor_b = {3.0_fx, 0.5_fx, Fixed{}};
    rope.length = 0.75_fx;
    REQUIRE(world.create_joint(rope).ok());
    for (int i = 0; i < 20; ++i) world.step();
    REQUIRE(world.remove_body(BodyId{6, 0}));  // a dead slot in the free list
    world.step();
    REQUIRE(world.contacts().size() >= 3);
    const std::vector<uint8_t> image = snapshot(world);
    const std::string dump = dump_state(world);
    const uint64_t hash = state_hash(world);
    size_t accepted = 0, refused = 0;
    std::set<std::string> fields;
    for (size_t at = header_bytes; at + 8 < image.size(); ++at) {
      {
        std::vector<uint8_t> flipped = image;
        flipped[at] ^= 1;
        test::reseal_snapshot(flipped);
        World restored;
        if (!restore(flipped, restored).ok()) {
          ++refused;
          continue;
        }
        ++accepted;
        INFO("payload byte " << at - header_bytes);
        REQUIRE(state_hash(restored) != hash);
        const Result<DumpDifference> diff = diff_dumps(dump, dump_state(restored));
        REQUIRE(diff.ok());
        REQUIRE(diff->has_value());
        const std::string& first = **diff;
        fields.insert(field_of(first));
        // A joint's difference names it: "(the hinge joint between bodies [1, 2])".
        if (first.rfind("$.joints[0].", 0) == 0) {
          REQUIRE(first.find("(the hinge joint between bodies [1, 2])") != std::string::npos);
        }
      }
    }
    INFO("accepted " << accepted << ", refused " << refused);
    // Most flips land in a value (a coordinate, an impulse) and restore;
    // those refused broke a count, a flag or an order, or put a value
    // where no world holds one (a high bit of a position, a velocity, a
    // quaternion or a shape size, a joint's axis, anchor or limit, or a
    // field its type does not have, e.g. a rope's axes: about 4.4 accepted
    // for 1 refused, 6 before joints were checked as create_joint makes them).
    CHECK(accepted > 4 * refused);
    // Among them, every field the dump used to leave out.
    for (const char* field : {"$.settings.dt", "$.settings.flags", "$.settings.shock_iterations", "$.bodies[].inertia_local[][]",
                              "$.bodies[].inverse_inertia_local[][]", "$.bodies[].material.rolling_resistance",
                              "$.bodies[].linear_damping", "$.bodies[].shapes[].half_extents[]",
                              "$.bodies[].shapes[].orientation[]", "$.contacts[].points[].feature", "$.joints[].type",
                              "$.joints[].local_anchor_a[]", "$.joints[].local_reference_b[]",
                              "$.joints[].upper_angle", "$.joints[].break_impulse", "$.joints[].friction_torque", "$.joints[].point_impulse[]",
                              "$.joints[].hinge_impulse[]",
                              "$.joints[].velocity_iterations", "$.joints[].position_iterations"}) {
      INFO(field);
      CHECK(std::any_of(fields.begin(), fields.end(), [&](const std::string& f) { return f.rfind(field, 0) == 0; }));
    }
    if (sleep) CHECK(fields.count("$.settings.sleep_epsilon") == 1);
  }
}

// state_hash streams the canonical bytes into XXH3 through a small buffer:
// it must be XXH3-64 of exactly what serialize_state writes (the snapshot's
// payload), for states smaller and much larger than that buffer, moving or
// at rest, with contacts, joints and a car.
TEST_CASE("the state hash is XXH3-64 of the serialised state", "[hash]") {
  for (const char* scene : {"stack20.json", "pyramid20.json", "playground.json"}) {
    World world = test::world_of(scene);
    for (int step = 0; step <= 90; ++step) {
      if (step % 30 == 0) {
        std::vector<uint8_t> bytes;
        serialize_state(world, bytes);
        INFO(scene << " step " << step << ", " << bytes.size() << " bytes");
        CHECK(state_hash(world) == XXH3_64bits(bytes.data(), bytes.size()));
      }
      world.step();
    }
  }
}
