// The raycast car (core/car.h) against analytic answers: the static
// compression of its springs, acceleration F / m, braking distance
// v^2 / (2 mu g), riding a moving platform, and its state through a
// snapshot.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>

#include "tests/core/test_world.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::TestWorld;
using bitstep::test::to_double;

namespace {

constexpr double g = 9.81, mass = 1000, stiffness = 40000;

Material tarmac() {
  Material m;
  m.static_friction = m.dynamic_friction = 0.8_fx;
  return m;
}

// A 1,000 kg chassis 1.8 x 0.6 x 4 m, wheels at (+-0.8, -0.3, +-1.4): the
// rear driven, the front steered; defaults otherwise (r 0.35 m, rest
// length 0.3 m, 40,000 N/m, 3,000 N s/m, 2,000 N per driven wheel). On
// the ground, or on a kinematic platform (its top at y = 0) moving at
// `platform_velocity` with the car on it moving with it.
struct TestCar {
  TestWorld t;
  BodyId chassis;
  BodyId platform;
  CarId car;
  explicit TestCar(Settings settings = {}, Vec3 platform_velocity = {}, int rays_per_wheel = 1) : t(settings) {
    if (platform_velocity == Vec3{}) {
      platform = t.add_ground(tarmac());
    } else {
      BodyDef slab;
      slab.type = BodyType::kinematic;
      slab.pose.position = {Fixed{}, -0.25_fx, Fixed{}};
      slab.linear_velocity = platform_velocity;
      slab.shapes.push_back({ShapeType::box, {30.0_fx, 0.25_fx, 30.0_fx}, {}, {}, {}});
      slab.material = tarmac();
      platform = t.world.create_body(slab).id;
    }
    BodyDef body;
    body.pose.position = {Fixed{}, 0.9_fx, Fixed{}};
    body.linear_velocity = platform_velocity;
    body.mass = Fixed::from_int(1000);
    body.shapes.push_back({ShapeType::box, {0.9_fx, 0.3_fx, 2.0_fx}, {}, {}, {}});
    chassis = t.world.create_body(body).id;
    CarDef def;
    def.chassis = chassis;
    def.rays_per_wheel = rays_per_wheel;
    for (int w = 0; w < 4; ++w) {
      const bool front = w < 2;
      def.wheels.push_back({{w % 2 == 0 ? 0.8_fx : -0.8_fx, -0.3_fx, front ? 1.4_fx : -1.4_fx}, !front, front});
    }
    std::string error;
    car = t.world.create_car(def, error);
    REQUIRE(error.empty());
  }
  const Car& state() const { return t.world.cars()[car.index]; }
  const Body& body() const { return t.world.body(chassis); }
};

}  // namespace

TEST_CASE("a parked car settles to its springs' static compression within 1 mm and does not creep", "[car]") {
  TestCar c;
  c.t.simulate_steps(300);
  const double compression = mass * g / (4 * stiffness);  // 61.3 mm
  for (const WheelState& wheel : c.state().wheels) {
    REQUIRE(wheel.on_ground);
    CHECK(std::abs(to_double(wheel.compression) - compression) < 0.001);
  }
  // The chassis's centre: wheel bottom 0.65 m below the attachments, which
  // are 0.3 m below it.
  CHECK(std::abs(to_double(c.body().pose.position.y) - (0.65 - compression + 0.3)) < 0.001);
  const Vec3 settled = c.body().pose.position;
  c.t.simulate_steps(600);
  CHECK(to_double(length(c.body().pose.position - settled)) < 0.001);
}

TEST_CASE("a parked car rides a platform that starts moving across it, along it (braked) and up", "[car]") {
  struct Case {
    const char* name;
    Vec3 velocity;
    bool braked;
  };
  for (const Case& m : {Case{"across", {2.0_fx, Fixed{}, Fixed{}}, false}, Case{"along", {Fixed{}, Fixed{}, 2.0_fx}, true},
                        Case{"up", {Fixed{}, 0.5_fx, Fixed{}}, false}}) {
    INFO("platform moving " << m.name);
    TestCar c({}, {Fixed{}, Fixed{}, Fixed::from_raw(1)});  // a platform, still
    if (m.braked) c.t.world.set_car_controls(c.car, {Fixed{}, Fixed::one(), Fixed{}});
    c.t.simulate_steps(120);  // settled on its springs
    const auto offset = [&] { return c.body().pose.position - c.t.body(c.platform).pose.position; };
    const Vec3 parked = offset();
    c.t.world.set_velocity(c.platform, m.velocity, {});  // at once: the tyres must grip
    c.t.simulate_steps(180);
    // Sideways or braked, the jolt slides it as far as full grip would,
    // v^2 / (2 mu g), within 25%: the roll (across: 1.17x) and the pitch
    // (along: 0.93x) move load between the wheels and take part of the grip.
    if (m.velocity.y == Fixed{}) {
      const double v = to_double(length(m.velocity)), mu = std::sqrt(1.0 * 0.8);
      CHECK(std::abs(to_double(length(offset() - parked)) / (v * v / (2 * mu * g)) - 1) < 0.25);
    }
    const Vec3 settled = offset();
    c.t.simulate_steps(300);  // 5 s more: the platform moves 10 m (2.5 m up)
    // Then it holds its place on the platform within 1 mm, at its velocity.
    CHECK(to_double(length(offset() - settled)) < 0.001);
    CHECK(to_double(length(c.body().linear_velocity - m.velocity)) < 0.001);
    for (const WheelState& wheel : c.state().wheels) {
      REQUIRE(wheel.on_ground);
      CHECK(wheel.ground == c.platform.index);
      CHECK(std::abs(to_double(wheel.compression) - mass * g / (4 * stiffness)) < 0.001);
    }
  }
}

TEST_CASE("a free-rolling car stays put in the world on a platform moving along it", "[car]") {
  TestCar c({}, {Fixed{}, Fixed{}, Fixed::from_raw(1)});
  c.t.simulate_steps(120);
  const Vec3 parked = c.body().pose.position;
  c.t.world.set_velocity(c.platform, {Fixed{}, Fixed{}, 2.0_fx}, {});  // the wheels roll, nothing pushes
  c.t.simulate_steps(300);
  CHECK(to_double(length(c.body().linear_velocity)) < 0.01);
  CHECK(to_double(length(c.body().pose.position - parked)) < 0.05);
}

TEST_CASE("full throttle accelerates the car at the drive force over its mass within 2%", "[car]") {
  TestCar c;
  c.t.simulate_steps(180);
  c.t.world.set_car_controls(c.car, {Fixed::one(), Fixed{}, Fixed{}});
  const double v0 = to_double(c.body().linear_velocity.z);
  c.t.simulate_steps(120);  // 2 s
  const double a = (to_double(c.body().linear_velocity.z) - v0) / 2.0;
  INFO("acceleration " << a << " m/s^2");
  CHECK(std::abs(a - 2 * 2000 / mass) < 0.02 * 4.0);
  CHECK(std::abs(to_double(c.body().pose.position.x)) < 0.001);  // straight ahead
}

TEST_CASE("braking from 20 m/s stops within 3% of v^2 / (2 mu g)", "[car]") {
  TestCar c;
  c.t.simulate_steps(180);
  c.t.world.set_velocity(c.chassis, {Fixed{}, Fixed{}, 20.0_fx}, {});
  c.t.world.set_car_controls(c.car, {Fixed{}, Fixed::one(), Fixed{}});
  const double z0 = to_double(c.body().pose.position.z);
  int steps = 0;
  while (to_double(c.body().linear_velocity.z) > 0.001 && steps < 600) {
    c.t.world.step();
    ++steps;
  }
  const double mu = std::sqrt(1.0 * 0.8);  // the tyre's grip and the ground's, mixed
  const double expected = 20.0 * 20.0 / (2 * mu * g);
  const double distance = to_double(c.body().pose.position.z) - z0;
  INFO("stopped after " << distance << " m in " << steps << " steps; v^2 / (2 mu g) = " << expected << " m");
  CHECK(std::abs(distance - expected) < 0.03 * expected);
}

TEST_CASE("steering turns the car toward +x for a positive steer", "[car]") {
  TestCar c;
  c.t.simulate_steps(120);
  c.t.world.set_car_controls(c.car, {0.5_fx, Fixed{}, 0.5_fx});
  c.t.simulate_steps(180);
  CHECK(to_double(c.body().pose.position.x) > 0.5);
  CHECK(to_double(c.body().angular_velocity.y) > 0.05);
}

TEST_CASE("a driven car restores from a snapshot and continues bit for bit", "[car][snapshot]") {
  // tests/replay covers snapshots; here the world copy keeps every car field.
  TestCar c;
  c.t.world.set_car_controls(c.car, {Fixed::one(), Fixed{}, 0.3_fx});
  c.t.simulate_steps(60);
  REQUIRE(c.state().controls.throttle == Fixed::one());
  REQUIRE(c.state().controls.steer == 0.3_fx);
  // Removing the chassis kills the car.
  c.t.world.remove_body(c.chassis);
  CHECK_FALSE(c.state().alive);
  c.t.simulate_steps(2);
}

TEST_CASE("over a 10 cm bump at 15 m/s no wheel ray starts inside the ground and the chassis never touches it",
          "[car]") {
  TestCar car({}, {}, 3);  // three rays per wheel trace the bump
  TestWorld& t = car.t;
  BodyDef bump;
  bump.type = BodyType::static_body;
  bump.pose = {{Fixed{}, Fixed{}, 20.0_fx}, bitstep::test::about_degrees({Fixed{}, Fixed{}, Fixed::one()}, 90.0_fx)};
  bump.shapes.push_back({ShapeType::capsule, {}, 0.1_fx, 3.0_fx, {}});  // lying across the road, 10 cm high
  bump.material = tarmac();
  const BodyId bump_id = t.world.create_body(bump).id;
  const BodyId chassis = car.chassis;
  t.simulate_steps(120);
  t.world.set_velocity(chassis, {Fixed{}, Fixed{}, 15.0_fx}, {});
  const CarDef& def = car.state().def;
  const Fixed full = def.rest_length + def.wheel_radius;
  double deepest = 0;
  bool met_bump = false;
  for (int step = 0; step < 150; ++step) {  // 2.5 s: 37 m, over the bump at 20 m
    t.world.step();
    for (const WheelState& wheel : t.world.cars()[0].wheels) {
      if (!wheel.on_ground) continue;
      CHECK(wheel.compression < full);  // the ray did not start inside
      deepest = std::max(deepest, to_double(wheel.compression));
      met_bump = met_bump || wheel.ground == bump_id.index;
    }
    for (const Contact& c : t.world.contacts()) {
      if (c.key.body_b != chassis.index && c.key.body_a != chassis.index) continue;
      CHECK_FALSE(touches(c.manifold));  // the chassis touches neither the ground nor the bump
    }
  }
  INFO("deepest compression " << deepest << " m");
  CHECK(met_bump);
  CHECK(deepest < to_double(full) - 0.1);
  CHECK(to_double(t.world.body(chassis).pose.position.z) > 30.0);
}
