// Every C API call on the world envelope's corners (tests/envelope_corners.h),
// as a game calls them each frame: per body its pose, render pose and an
// interpolation, a ray from the far corner of the world at it, and once the
// largest impulse and force at the farthest point, a velocity set at the
// input bounds (the world clamps it to the body's limits) and a wake; then
// steps, a snapshot and a rollback state saved and loaded back (the hash
// kept), and a corner body added from JSON and removed. In the checked
// build any saturation aborts and the sanitizers report.
#include <catch2/catch.hpp>

#include <cstdint>
#include <string>
#include <utility>
#include <vector>

#include "replay/bitstep.h"
#include "tests/envelope_corners.h"

using namespace bitstep;
using namespace bitstep::test_envelope;

namespace {

constexpr bitstep_fixed units(int64_t value) { return value * (int64_t{1} << 32); }

// Every body's getters, a ray at it and, at `push`, every input call.
void call_every_body(bitstep_simulation* sim, bool push) {
  const bitstep_fixed far = units(16000), big = units(1000000);
  for (uint32_t slot = 0; slot < bitstep_slot_count(sim); ++slot) {
    bitstep_body body;
    if (bitstep_body_in_slot(sim, slot, &body) != BITSTEP_OK) continue;
    bitstep_pose pose;
    bitstep_render_pose render, halfway;
    REQUIRE(bitstep_get_pose(sim, body, &pose) == BITSTEP_OK);
    REQUIRE(bitstep_get_render_pose(sim, body, &render) == BITSTEP_OK);
    bitstep_interpolate(&render, &render, 0.5f, &halfway);
    bitstep_ray_hit hit;
    const bitstep_status ray = bitstep_cast_ray(
        sim, {far, far, far}, {pose.position.x - far, pose.position.y - far, pose.position.z - far}, &hit);
    CHECK((ray == BITSTEP_OK || ray == BITSTEP_NOT_FOUND));
    if (!push) continue;
    // What the body's type takes is applied; the rest is refused (c_api_errors_tests.cpp).
    bitstep_body_type type = BITSTEP_STATIC;
    REQUIRE(bitstep_get_body_type(sim, body, &type) == BITSTEP_OK);
    const bitstep_status pushed = type == BITSTEP_DYNAMIC ? BITSTEP_OK : BITSTEP_INVALID;
    const bitstep_status moved = type == BITSTEP_STATIC ? BITSTEP_INVALID : BITSTEP_OK;
    CHECK(bitstep_apply_impulse(sim, body, {big, -big, big}, {far, -far, far}) == pushed);
    CHECK(bitstep_apply_force(sim, body, {-big, big, big}, {-far, far, -far}) == pushed);
    CHECK(bitstep_set_velocity(sim, body, {units(500), 0, 0}, {0, 0, units(100)}) == moved);
    CHECK(bitstep_wake(sim, body) == BITSTEP_OK);
  }
}

// Saves with `save`, steps, loads with `load`: the saved hash is back.
template <class Save, class Load>
void round_trip(bitstep_simulation* sim, Save save, Load load) {
  size_t size = 0;
  REQUIRE(save(sim, nullptr, 0, &size) == BITSTEP_BUFFER_TOO_SMALL);
  std::vector<uint8_t> image(size);
  REQUIRE(save(sim, image.data(), image.size(), &size) == BITSTEP_OK);
  const uint64_t saved = bitstep_hash(sim);
  for (int i = 0; i < 5; ++i) REQUIRE(bitstep_step(sim) == BITSTEP_OK);
  REQUIRE(load(sim, image.data(), size) == BITSTEP_OK);
  CHECK(bitstep_hash(sim) == saved);
}

}  // namespace

TEST_CASE("C API: every call on the envelope's corners", "[simulation][c_api][envelope]") {
  std::vector<std::pair<std::string, std::string>> scenes;
  std::string heaviest_largest;  // a body's JSON to add later
  for (const auto& [kind, sizes] : corner_kinds()) {
    const std::vector<Corner> corners = corners_of(kind, sizes);
    scenes.emplace_back(kind, throw_scene(corners));
    if (kind == "box") {
      heaviest_largest = "{\"name\": \"added\", \"position\": [0, 500, 0], \"mass\": " + num(corners.back().mass) +
                         ", \"velocity\": " + vec(corners.back().velocity) + ", \"shapes\": [" +
                         corners.back().shapes_json + "]}";
    }
  }
  scenes.emplace_back("stack", stack_scene(envelope::min_size));
  scenes.emplace_back("meeting", meeting_scene());
  for (const auto& [name, text] : scenes) {
    INFO(name);
    bitstep_simulation* sim = nullptr;
    char error[512] = "";
    REQUIRE(bitstep_create_from_text(text.data(), text.size(), name.c_str(), &sim, error, sizeof error) == BITSTEP_OK);
    for (int step = 0; step < 20; ++step) {
      call_every_body(sim, step == 3);
      REQUIRE(bitstep_step(sim) == BITSTEP_OK);
    }
    round_trip(sim, bitstep_save, bitstep_load);
    round_trip(sim, bitstep_save_state, bitstep_load_state);
    bitstep_body added;
    REQUIRE(bitstep_add_body(sim, heaviest_largest.c_str(), &added) == BITSTEP_OK);
    for (int step = 0; step < 5; ++step) {
      call_every_body(sim, step == 0);
      REQUIRE(bitstep_step(sim) == BITSTEP_OK);
    }
    CHECK(bitstep_remove_body(sim, added) == BITSTEP_OK);
    REQUIRE(bitstep_step(sim) == BITSTEP_OK);
    bitstep_destroy(sim);
  }
}
