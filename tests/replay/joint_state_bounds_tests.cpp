// A joint read back from a snapshot or a rollback state is checked against
// what World::create_joint makes (core/joint.h, check_joint_state): a
// forged image with its checksum made right again, one joint field out of
// bounds, is refused by both readers and by the C API's loads, with a
// message naming the field, and nothing changes (issue 48, finding 2: such
// an image loaded, then saturated the step and aborted the checked build).
#include <xxhash.h>

#include <catch2/catch.hpp>
#include <cstring>
#include <string>
#include <utility>
#include <vector>

#include "replay/bitstep.h"
#include "replay/simulation.h"
#include "replay/state_bytes.h"
#include "replay/state_description.h"
#include "replay/state_hash.h"
#include "tests/replay/image_seal.h"

using namespace bitstep;

namespace {

// A static bar and five boxes hanging from it, one by each joint type,
// with limits, motors and friction where the type has them; swinging.
const char* const joints_scene = R"({"format": "bitstep-scene", "version": 1, "bodies": [
  {"name": "bar", "type": "static", "position": [0, 5, 0], "shapes": [{"type": "box", "half_extents": [6, 0.1, 0.1]}]},
  {"name": "p", "position": [-4, 4.5, 0], "velocity": [1, 0, 0.5], "shapes": [{"type": "box", "half_extents": [0.2, 0.4, 0.2]}]},
  {"name": "r", "position": [-2, 4.2, 0], "velocity": [0, 0, 1], "shapes": [{"type": "sphere", "radius": 0.2}]},
  {"name": "h", "position": [0, 4.5, 0], "velocity": [1, 0, 0], "shapes": [{"type": "box", "half_extents": [0.2, 0.4, 0.2]}]},
  {"name": "c", "position": [2, 4.5, 0], "velocity": [1, 0, 1], "angular_velocity": [0, 1, 0],
   "shapes": [{"type": "capsule", "radius": 0.1, "half_height": 0.3}]},
  {"name": "s", "position": [4, 4.7, 0], "velocity": [0.5, 0, 0], "angular_velocity": [1, 0, 1], "shapes": [{"type": "box", "half_extents": [0.3, 0.1, 0.3]}]}],
  "joints": [
    {"type": "point", "body_a": "bar", "body_b": "p", "anchor": [-4, 4.9, 0], "friction": 1, "break_impulse": 100000},
    {"type": "max_distance", "body_a": "bar", "body_b": "r", "anchor": [-2, 4.9, 0], "anchor_b": [-2, 4.4, 0], "length": 0.6},
    {"type": "hinge", "body_a": "bar", "body_b": "h", "anchor": [0, 4.9, 0], "axis": [0, 0, 1], "limits": [-60, 45],
     "motor": {"speed": 1, "max_torque": 20}, "friction": 0.5},
    {"type": "cone", "body_a": "bar", "body_b": "c", "anchor": [2, 4.9, 0], "axis": [0, -1, 0], "swing": 30, "twist": [-20, 20]},
    {"type": "slider", "body_a": "bar", "body_b": "s", "anchor": [4, 4.7, 0], "axis": [1, 0, 0],
     "lower_translation": -1, "upper_translation": 1, "motor": {"speed": 0.5, "max_force": 50}, "friction": 2}]})";

// Counts the bytes of a state as its writer writes them and notes where
// each named Fixed or vector starts: the joints' fields, by name, in order.
struct Count {
  size_t* at;
  void operator()(uint64_t, int count) const { *at += static_cast<size_t>(count); }
  void serial(uint64_t) const {}  // a rollback state's serials are not in its payload
};
struct NoStatics final : state_bytes::BodyStatics {
  void remember(const Body&) override {}
  bool recall(uint64_t, Body&) const override { return false; }
};
struct Locator : state_bytes::ByteWriter<Count> {
  size_t* at;
  std::vector<std::pair<std::string, size_t>>* found;
  void note(const char* name) {
    if (name != nullptr) found->emplace_back(name, *at);
  }
  void fixed(const char* name, Fixed f) {
    note(name);
    ByteWriter::fixed(name, f);
  }
  void fixeds(const char* name, const Fixed* values, size_t n) {
    note(name);
    ByteWriter::fixeds(name, values, n);
  }
  void vec(const char* name, Vec3 v) {
    note(name);
    ByteWriter::vec(name, v);
  }
};

// Where each named field starts in a state's payload (a rollback state's:
// `step_alone`), in the order written.
std::vector<std::pair<std::string, size_t>> locate(const World& world, bool step_alone) {
  size_t at = 0;
  std::vector<std::pair<std::string, size_t>> found;
  NoStatics statics;
  Locator locator{{Count{&at}, step_alone ? &statics : nullptr}, &at, &found};
  const uint64_t step = world.step_count();
  describe_state(locator, state_parts_of(world, step));
  return found;
}

void put_raw(std::vector<uint8_t>& image, size_t at, int64_t raw) {
  for (int i = 0; i < 8; ++i) image[at + static_cast<size_t>(i)] = static_cast<uint8_t>(static_cast<uint64_t>(raw) >> (8 * i));
}

// The joint fields a state holds (state_description.h, describe_joint) and
// a word the refusal names for each (the field, or its group's word).
const std::pair<const char*, const char*> joint_fields[] = {
    {"local_anchor_a", "local_anchor_a"},       {"local_anchor_b", "local_anchor_b"},
    {"local_axis_a", "local_axis_a"},           {"local_axis_b", "local_axis_b"},
    {"local_reference_a", "local_reference_a"}, {"local_reference_b", "local_reference_b"},
    {"length", "length"},                       {"lower_angle", "limits"},
    {"upper_angle", "limits"},                  {"swing_angle", "swing_angle"},
    {"break_impulse", "break_impulse"},         {"friction_torque", "friction_torque"},
    {"point_impulse", "point_impulse"},         {"distance_impulse", "distance_impulse"},
    {"hinge_impulse", "hinge_impulse"},         {"limit_impulse", "limit_impulse"},
    {"lower_translation", "translation"},       {"upper_translation", "translation"},
    {"angular_impulse", "angular_impulse"},     {"motor_speed", "motor"},
    {"motor_max", "motor"},                     {"motor_impulse", "motor_impulse"},
};

// Values no joint of create_joint holds in any of those fields, written
// into a field's first 8 bytes: far out (2^30 units, either sign) and just
// past the impulses' bound.
const int64_t forged_values[] = {-(int64_t{1} << 62), int64_t{1} << 62, (int64_t{1} << 59) + 1};

bitstep_simulation* made(const char* text) {
  bitstep_simulation* sim = nullptr;
  char error[256] = "";
  const bitstep_status status = bitstep_create_from_text(text, std::strlen(text), "joints.json", &sim, error, sizeof error);
  INFO(error);
  REQUIRE(status == BITSTEP_OK);
  return sim;
}

}  // namespace

TEST_CASE("a snapshot or rollback state with a joint field out of bounds is refused, naming it, and changes nothing",
          "[snapshot][rollback_state][joint]") {
  auto made_sim = Simulation::from_text(joints_scene, "joints.json");
  if (!made_sim.ok()) FAIL(made_sim.error().message());
  Simulation& sim = *made_sim;
  for (int i = 0; i < 30; ++i) sim.step();
  const World& world = sim.world();
  REQUIRE(world.joints().size() == 5u);
  for (const Joint& joint : world.joints()) REQUIRE(joint.alive);
  // Swinging: the impulses are there to forge.
  CHECK(world.joints()[0].point_impulse != Vec3{});
  const std::vector<uint8_t> snap = sim.save();
  std::vector<uint8_t> state(sim.save_state({}));
  REQUIRE(sim.save_state(state) == state.size());
  const uint64_t hash = state_hash(world);
  // The C API's twin (the same scene and steps: the same bytes).
  bitstep_simulation* capi = made(joints_scene);
  for (int i = 0; i < 30; ++i) REQUIRE(bitstep_step(capi) == BITSTEP_OK);
  REQUIRE(bitstep_hash(capi) == hash);
  size_t capi_size = 0;
  REQUIRE(bitstep_save_state(capi, nullptr, 0, &capi_size) == BITSTEP_BUFFER_TOO_SMALL);
  std::vector<uint8_t> capi_state(capi_size);
  REQUIRE(bitstep_save_state(capi, capi_state.data(), capi_state.size(), &capi_size) == BITSTEP_OK);

  // Unforged, each image loads (and leaves the state as it was); a
  // rollback state saved again after the load (states do not cross one).
  REQUIRE(sim.load_state(state).ok());
  REQUIRE(sim.load(snap).ok());
  std::vector<uint8_t> fresh(sim.save_state({}));
  REQUIRE(sim.save_state(fresh) == fresh.size());
  REQUIRE(sim.load_state(fresh).ok());
  REQUIRE(state_hash(sim.world()) == hash);

  struct Image {
    const char* what;
    std::vector<uint8_t>* bytes;
    size_t header;
    bool step_alone;
  };
  std::vector<uint8_t> capi_snap = snap;
  Image images[] = {{"snapshot", &capi_snap, 8 + 4 + 8, false},
                    {"rollback state", &fresh, test::rollback_payload_at(fresh), true}};
  size_t forged = 0;
  for (const Image& image : images) {
    const auto fields = locate(sim.world(), image.step_alone);
    for (const auto& [field, word] : joint_fields) {
      size_t joint = 0;  // the live joints in order: a field's k-th occurrence is joint k's (absent fields skipped)
      bool seen = false;
      for (const auto& [name, at] : fields) {
        if (name != field) continue;
        seen = true;
        for (const int64_t raw : forged_values) {
          if (std::string(field) == "break_impulse" && raw > 0) continue;  // any break impulse >= 0 is one's
          INFO(image.what << ": joint " << joint << " (" << state_description::joint_types[static_cast<size_t>(
                                                          sim.world().joints()[joint].type)]
                          << ") " << field << " raw " << raw);
          std::vector<uint8_t> bad = *image.bytes;
          put_raw(bad, image.header + at, raw);
          image.step_alone ? test::reseal_rollback_state(bad) : test::reseal_snapshot(bad);
          ++forged;
          const Result<void> loaded = image.step_alone ? sim.load_state(bad) : sim.load(bad);
          REQUIRE_FALSE(loaded.ok());
          const std::string why = loaded.error().message();
          INFO(why);
          CHECK(why.find("a joint's") != std::string::npos);
          CHECK(why.find(word) != std::string::npos);
          CHECK(why.find('\n') == std::string::npos);
          CHECK(state_hash(sim.world()) == hash);
          // Through the C API too.
          if (image.step_alone) {
            std::vector<uint8_t> capi_bad = capi_state;
            put_raw(capi_bad, image.header + at, raw);
            test::reseal_rollback_state(capi_bad);
            CHECK(bitstep_load_state(capi, capi_bad.data(), capi_bad.size()) == BITSTEP_INVALID);
          } else {
            CHECK(bitstep_load(capi, bad.data(), bad.size()) == BITSTEP_INVALID);
          }
          const std::string capi_error = bitstep_last_error(capi);
          CHECK(capi_error.find(word) != std::string::npos);
          CHECK(bitstep_hash(capi) == hash);
        }
        ++joint;
      }
      INFO(image.what << " " << field);
      CHECK(seen);
    }
  }
  CHECK(forged > 200);
  // Both step on unchanged (the checked build: without a saturation).
  const uint64_t twin = bitstep_hash(capi);
  sim.step();
  REQUIRE(bitstep_step(capi) == BITSTEP_OK);
  CHECK(state_hash(sim.world()) == bitstep_hash(capi));
  CHECK(twin == hash);
  bitstep_destroy(capi);
}
