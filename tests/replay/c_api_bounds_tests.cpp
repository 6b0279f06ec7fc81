// The C API's and the facade's input bounds (replay/input_bounds.h): every
// call that takes numbers, just inside and just outside each bound. Inside
// is taken; outside is refused with BITSTEP_INVALID and a message naming
// the call, the argument and the bound, and changes nothing: the hash
// stays, and a step after it gives the hash of a twin that never saw the
// call (so inputs the hash does not hold yet, forces and car controls, are
// seen to be unchanged too).
#include <catch2/catch.hpp>
#include <cstdint>
#include <cstring>
#include <functional>
#include <limits>
#include <string>

#include "replay/bitstep.h"
#include "replay/simulation.h"

using namespace bitstep;

namespace {

// A ground, a ball in the air and a car on the ground.
const char* const bounds_scene = R"({"format": "bitstep-scene", "version": 1, "bodies": [
  {"name": "ground", "type": "static", "position": [0, -1, 0], "shapes": [{"type": "box", "half_extents": [30, 1, 30]}]},
  {"name": "ball", "position": [5, 3, 0], "shapes": [{"type": "sphere", "radius": 0.5}]},
  {"name": "chassis", "position": [0, 1, 0], "mass": 1200, "shapes": [{"type": "box", "half_extents": [0.9, 0.3, 2.1]}]}],
  "cars": [{"name": "car", "chassis": "chassis", "rays_per_wheel": 1, "wheels": [
    {"attachment": [0.8, -0.3, 1.45], "steered": true}, {"attachment": [-0.8, -0.3, 1.45], "steered": true},
    {"attachment": [0.8, -0.3, -1.45], "driven": true}, {"attachment": [-0.8, -0.3, -1.45], "driven": true}]}]})";

constexpr bitstep_fixed units(int64_t value) { return value * (int64_t{1} << 32); }
constexpr bitstep_fixed ulp = 1;  // one raw unit, 2^-32
constexpr bitstep_fixed huge = std::numeric_limits<int64_t>::max();
constexpr bitstep_fixed most_negative = std::numeric_limits<int64_t>::min();

bitstep_simulation* made() {
  bitstep_simulation* sim = nullptr;
  char error[256] = "";
  const bitstep_status status =
      bitstep_create_from_text(bounds_scene, std::strlen(bounds_scene), "bounds.json", &sim, error, sizeof error);
  INFO(error);
  REQUIRE(status == BITSTEP_OK);
  return sim;
}

bitstep_body body_named(bitstep_simulation* sim, const char* name) {
  bitstep_body body{};
  REQUIRE(bitstep_find_body(sim, name, &body) == BITSTEP_OK);
  return body;
}

using Call = std::function<bitstep_status(bitstep_simulation*, bitstep_body)>;

// `call` on the ball is taken.
void check_taken(const Call& call) {
  bitstep_simulation* sim = made();
  const bitstep_status status = call(sim, body_named(sim, "ball"));
  INFO(bitstep_last_error(sim));
  CHECK(status == BITSTEP_OK);
  CHECK(bitstep_step(sim) == BITSTEP_OK);
  bitstep_destroy(sim);
}

// `call` on the ball is refused with `message`, and changes nothing.
void check_refused(const Call& call, const std::string& message) {
  bitstep_simulation* sim = made();
  bitstep_simulation* twin = made();
  const uint64_t before = bitstep_hash(sim);
  CHECK(call(sim, body_named(sim, "ball")) == BITSTEP_INVALID);
  CHECK(std::string(bitstep_last_error(sim)) == message);
  CHECK(bitstep_hash(sim) == before);
  REQUIRE(bitstep_step(sim) == BITSTEP_OK);
  REQUIRE(bitstep_step(twin) == BITSTEP_OK);
  CHECK(bitstep_hash(sim) == bitstep_hash(twin));
  bitstep_destroy(sim);
  bitstep_destroy(twin);
}

bitstep_vec3 along_x(bitstep_fixed x) { return {x, 0, 0}; }
bitstep_vec3 along_y(bitstep_fixed y) { return {0, y, 0}; }
bitstep_vec3 along_z(bitstep_fixed z) { return {0, 0, z}; }

Call impulse(bitstep_vec3 impulse, bitstep_vec3 point) {
  return [=](bitstep_simulation* sim, bitstep_body ball) { return bitstep_apply_impulse(sim, ball, impulse, point); };
}
Call force(bitstep_vec3 force, bitstep_vec3 point) {
  return [=](bitstep_simulation* sim, bitstep_body ball) { return bitstep_apply_force(sim, ball, force, point); };
}
Call velocity(bitstep_vec3 linear, bitstep_vec3 angular) {
  return [=](bitstep_simulation* sim, bitstep_body ball) { return bitstep_set_velocity(sim, ball, linear, angular); };
}
Call drive(bitstep_fixed throttle, bitstep_fixed brake, bitstep_fixed steer) {
  return [=](bitstep_simulation* sim, bitstep_body) { return bitstep_drive(sim, "car", throttle, brake, steer); };
}

}  // namespace

TEST_CASE("C API bounds: apply_impulse within +-1e6 N s at a point within +-16000 m", "[simulation][c_api][bounds]") {
  const bitstep_fixed limit = units(1000000), far = units(16000);
  const bitstep_vec3 at{units(5), units(3), 0};
  check_taken(impulse(along_x(limit), at));
  check_taken(impulse({-limit, -limit, -limit}, at));
  check_taken(impulse(along_y(1), {far, -far, far}));
  check_refused(impulse(along_x(limit + ulp), at), "apply_impulse: impulse.x: outside +-1000000 N s");
  check_refused(impulse(along_y(-limit - ulp), at), "apply_impulse: impulse.y: outside +-1000000 N s");
  check_refused(impulse(along_z(huge), at), "apply_impulse: impulse.z: outside +-1000000 N s");
  check_refused(impulse(along_x(most_negative), at), "apply_impulse: impulse.x: outside +-1000000 N s");
  check_refused(impulse(along_y(1), {far + ulp, 0, 0}), "apply_impulse: world_point.x: outside +-16000 m");
  check_refused(impulse(along_y(1), {0, 0, -far - ulp}), "apply_impulse: world_point.z: outside +-16000 m");
  check_refused(impulse(along_y(1), {0, most_negative, 0}), "apply_impulse: world_point.y: outside +-16000 m");
}

TEST_CASE("C API bounds: apply_force within +-1e6 N at a point within +-16000 m", "[simulation][c_api][bounds]") {
  const bitstep_fixed limit = units(1000000), far = units(16000);
  const bitstep_vec3 at{units(5), units(3), 0};
  check_taken(force({limit, -limit, limit}, at));
  check_taken(force(along_y(1), {-far, far, -far}));
  check_refused(force(along_z(limit + ulp), at), "apply_force: force.z: outside +-1000000 N");
  check_refused(force(along_x(-limit - ulp), at), "apply_force: force.x: outside +-1000000 N");
  check_refused(force(along_y(huge), at), "apply_force: force.y: outside +-1000000 N");
  check_refused(force(along_y(1), {0, far + ulp, 0}), "apply_force: world_point.y: outside +-16000 m");
  check_refused(force(along_y(1), {huge, huge, huge}), "apply_force: world_point.x: outside +-16000 m");
}

TEST_CASE("C API bounds: set_velocity within 500 m/s and 100 rad/s, per component and in length",
          "[simulation][c_api][bounds]") {
  const bitstep_fixed v = units(500), w = units(100);
  check_taken(velocity(along_x(v), along_z(w)));
  check_taken(velocity(along_y(-v), along_x(-w)));
  check_taken(velocity({units(353), units(353), 0}, {units(70), 0, units(70)}));  // lengths 499.2, 98.99
  check_refused(velocity(along_x(v + ulp), {}), "set_velocity: linear.x: outside +-500 m/s");
  check_refused(velocity(along_z(-v - ulp), {}), "set_velocity: linear.z: outside +-500 m/s");
  check_refused(velocity({units(354), units(354), 0}, {}), "set_velocity: linear: faster than 500 m/s");
  check_refused(velocity({}, along_y(w + ulp)), "set_velocity: angular.y: outside +-100 rad/s");
  check_refused(velocity({}, along_x(-w - ulp)), "set_velocity: angular.x: outside +-100 rad/s");
  check_refused(velocity({}, {units(71), units(71), 0}), "set_velocity: angular: faster than 100 rad/s");
  // The checked build aborted on this one (the clamp's length overflowed),
  // and Release clamped it silently.
  check_refused(velocity({huge, huge, huge}, {}), "set_velocity: linear.x: outside +-500 m/s");
  check_refused(velocity({}, {most_negative, 0, 0}), "set_velocity: angular.x: outside +-100 rad/s");
}

TEST_CASE("C API bounds: drive's throttle and steer within -1..1, its brake 0..1", "[simulation][c_api][bounds]") {
  const bitstep_fixed one = units(1);
  check_taken(drive(one, one, one));
  check_taken(drive(-one, 0, -one));
  check_refused(drive(one + ulp, 0, 0), "drive: throttle: outside +-1");
  check_refused(drive(-one - ulp, 0, 0), "drive: throttle: outside +-1");
  check_refused(drive(0, -ulp, 0), "drive: brake: outside 0..1");
  check_refused(drive(0, one + ulp, 0), "drive: brake: outside 0..1");
  check_refused(drive(0, 0, one + ulp), "drive: steer: outside +-1");
  check_refused(drive(0, 0, most_negative), "drive: steer: outside +-1");
}

TEST_CASE("C API bounds: a stale handle is NOT_FOUND before its values are looked at", "[simulation][c_api][bounds]") {
  bitstep_simulation* sim = made();
  const bitstep_body ball = body_named(sim, "ball");
  REQUIRE(bitstep_remove_body(sim, ball) == BITSTEP_OK);
  const uint64_t before = bitstep_hash(sim);
  CHECK(bitstep_set_velocity(sim, ball, along_x(huge), {}) == BITSTEP_NOT_FOUND);
  CHECK(std::string(bitstep_last_error(sim)) == "no body in slot 1 of generation 0");
  CHECK(bitstep_apply_impulse(sim, {99, 0}, {}, {}) == BITSTEP_NOT_FOUND);
  CHECK(bitstep_apply_force(sim, {1, 7}, {}, along_x(huge)) == BITSTEP_NOT_FOUND);
  CHECK(bitstep_drive(sim, "van", huge, 0, 0) == BITSTEP_NOT_FOUND);
  CHECK(std::string(bitstep_last_error(sim)) == "no car named \"van\"");
  CHECK(bitstep_hash(sim) == before);
  bitstep_destroy(sim);
}

TEST_CASE("the facade refuses what the C API refuses, with the same reason", "[simulation][bounds]") {
  auto sim = Simulation::from_text(bounds_scene, "bounds.json");
  REQUIRE(sim.ok());
  const BodyId ball = *sim->find_body("ball");
  const uint64_t before = sim->hash();
  const Vec3 fast{Fixed::from_int(501), Fixed{}, Fixed{}};
  const InputResult refused = sim->set_velocity(ball, fast, {});
  CHECK(refused.status == InputResult::Status::refused);
  CHECK(refused.refusal.message() == "set_velocity: linear.x: outside +-500 m/s");
  CHECK_FALSE(sim->apply_impulse(ball, {Fixed::from_int(1000001), Fixed{}, Fixed{}}, {}));
  CHECK_FALSE(sim->apply_force(ball, {}, {Fixed{}, Fixed::from_int(-16001), Fixed{}}));
  CHECK(sim->drive("car", {Fixed{}, -Fixed::one(), Fixed{}}).refusal.message() == "drive: brake: outside 0..1");
  CHECK(sim->hash() == before);
  CHECK(sim->set_velocity(ball, {Fixed::from_int(500), Fixed{}, Fixed{}}, {}).status == InputResult::Status::applied);
  CHECK(sim->hash() != before);
  CHECK(sim->set_velocity({ball.index, ball.generation + 1}, fast, {}).status == InputResult::Status::not_found);
}

// A query changes nothing, so it takes any numbers: past the casts' reach
// (an origin beyond 65536 m, a translation beyond 131072 m) a ray meets
// nothing. The checked build aborted on the lowest value (its abs saturated).
TEST_CASE("C API bounds: a ray takes any numbers, and past the casts' reach meets nothing",
          "[simulation][c_api][bounds]") {
  bitstep_simulation* sim = made();
  const uint64_t before = bitstep_hash(sim);
  const bitstep_fixed reach = units(131072), coordinate = units(65536);
  bitstep_ray_hit hit{};
  CHECK(bitstep_cast_ray(sim, {units(10), units(5), 0}, along_y(-reach), &hit) == BITSTEP_OK);
  CHECK(hit.body.index == 0);  // the ground
  CHECK(bitstep_cast_ray(sim, {0, units(5), 0}, along_y(-reach - ulp), &hit) == BITSTEP_NOT_FOUND);
  CHECK(bitstep_cast_ray(sim, {0, units(5), 0}, along_y(most_negative), &hit) == BITSTEP_NOT_FOUND);
  CHECK(bitstep_cast_ray(sim, {0, units(5), 0}, {huge, most_negative, huge}, &hit) == BITSTEP_NOT_FOUND);
  CHECK(bitstep_cast_ray(sim, {units(10), coordinate, 0}, along_y(-reach), &hit) == BITSTEP_OK);
  CHECK(bitstep_cast_ray(sim, {0, coordinate + ulp, 0}, along_y(-reach), &hit) == BITSTEP_NOT_FOUND);
  CHECK(bitstep_cast_ray(sim, {most_negative, most_negative, most_negative}, along_y(-units(10)), &hit) ==
        BITSTEP_NOT_FOUND);
  CHECK(bitstep_cast_ray(sim, {huge, units(5), 0}, along_x(-units(10)), &hit) == BITSTEP_NOT_FOUND);
  CHECK(bitstep_hash(sim) == before);
  bitstep_destroy(sim);
}
