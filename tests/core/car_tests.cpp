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

// The chassis's mass, its suspension and where its centre starts.
struct Chassis {
  Fixed mass = Fixed::from_int(1000);    // kg
  Fixed stiffness = 40000.0_fx;          // N/m per wheel
  Fixed damping = 3000.0_fx;             // N s/m per wheel
  Fixed height = 0.9_fx;                 // m
};

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
  explicit TestCar(Settings settings = {}, Vec3 platform_velocity = {}, int rays_per_wheel = 1,
                   Material road = tarmac(), Chassis spec = {})
      : t(settings) {
    if (platform_velocity == Vec3{}) {
      platform = t.add_ground(road);
    } else {
      BodyDef slab;
      slab.type = BodyType::kinematic;
      slab.pose.position = {Fixed{}, -0.25_fx, Fixed{}};
      slab.linear_velocity = platform_velocity;
      slab.shapes.push_back({ShapeType::box, {30.0_fx, 0.25_fx, 30.0_fx}, {}, {}, {}});
      slab.material = road;
      platform = t.world.create_body(slab).value();
    }
    BodyDef body;
    body.pose.position = {Fixed{}, spec.height, Fixed{}};
    body.linear_velocity = platform_velocity;
    body.mass = spec.mass;
    body.shapes.push_back({ShapeType::box, {0.9_fx, 0.3_fx, 2.0_fx}, {}, {}, {}});
    chassis = t.world.create_body(body).value();
    CarDef def;
    def.chassis = chassis;
    def.rays_per_wheel = rays_per_wheel;
    def.stiffness = spec.stiffness;
    def.damping = spec.damping;
    for (int w = 0; w < 4; ++w) {
      const bool front = w < 2;
      def.wheels.push_back({{w % 2 == 0 ? 0.8_fx : -0.8_fx, -0.3_fx, front ? 1.4_fx : -1.4_fx}, !front, front});
    }
    const Result<CarId> made = t.world.create_car(def);
    REQUIRE(made.ok());
    car = made.value();
  }
  const Car& state() const { return t.world.cars()[car.index]; }
  const Body& body() const { return t.world.body(chassis); }
};

}  // namespace

// Under either pipeline: with guendelman's the wheels' rows join the
// contact pass (after the forces), not the collision pass.
TEST_CASE("a parked car settles to its springs' static compression m g / 4k within 1% and does not creep", "[car]") {
  for (const Pipeline pipeline : {Pipeline::standard, Pipeline::guendelman}) {
    INFO((pipeline == Pipeline::standard ? "standard" : "guendelman") << " pipeline");
    Settings settings;
    settings.pipeline = pipeline;
    TestCar c(settings);
    c.t.simulate_steps(300);
    const double compression = mass * g / (4 * stiffness);  // 61.3 mm
    for (const WheelState& wheel : c.state().wheels) {
      REQUIRE(wheel.on_ground);
      INFO("compression " << to_double(wheel.compression) * 1000 << " mm");
      CHECK(std::abs(to_double(wheel.compression) - compression) < 0.01 * compression);
      // The suspension's force is the solve's impulse over dt: m g / 4.
      CHECK(std::abs(to_double(wheel.suspension_force) - mass * g / 4) < 0.01 * mass * g / 4);
    }
    // The chassis's centre: wheel bottom 0.65 m below the attachments,
    // which are 0.3 m below it.
    CHECK(std::abs(to_double(c.body().pose.position.y) - (0.65 - compression + 0.3)) < 0.01 * compression);
    const Vec3 settled = c.body().pose.position;
    c.t.simulate_steps(600);
    CHECK(to_double(length(c.body().pose.position - settled)) < 0.001);
  }
}

namespace {

// The chassis's centre height at which its level wheels just touch the
// ground at y = 0: the attachments 0.3 m below the centre, the rest length
// 0.3 m and the wheel's 0.35 m below them.
constexpr double touching_height = 0.3 + 0.3 + 0.35;

Fixed fixed_of(double x) { return Fixed::from_raw(static_cast<int64_t>(std::llround(x * 4294967296.0))); }

// The car's energy (J): the chassis's kinetic energy, gravity's potential
// (zero at the ground) and its springs', 1/2 k s^2 per wheel with s the
// compression its attachment's height gives (the chassis stays level).
double car_energy(const TestCar& c, double k) {
  const Body& b = c.body();
  const double m = 1 / to_double(b.inverse_mass);
  const Vec3 v = b.linear_velocity, w = rotate_inverse(b.pose.orientation, b.angular_velocity);
  const Vec3 iw = b.inertia_local * w;
  double e = 0.5 * m * to_double(dot(v, v)) + 0.5 * to_double(dot(w, iw)) + m * g * to_double(b.pose.position.y);
  for (const WheelDef& wheel : c.state().def.wheels) {
    const double top = to_double((b.pose.position + rotate(b.pose.orientation, wheel.attachment)).y);
    const double s = std::max(0.0, (touching_height - 0.3) - top);
    e += 0.5 * k * s * s;
  }
  return e;
}

}  // namespace

// Dropped level from 0.5 m above its rest height, the chassis falls 0.44 m
// onto its wheels at 2.9 m/s. Each wheel carries m / 4 = 250 kg on k and c:
// omega = sqrt(k / 250) = 12.6 rad/s, damping ratio zeta = c / (2 sqrt(k
// 250)) = 0.47, so past the deepest compression the chassis may rise above
// its rest height by at most exp(-zeta pi / sqrt(1 - zeta^2)) = 0.18 of how
// far it sank below it (the implicit step damps more, never less). Its
// energy (kinetic, gravity's, the springs') never grows in a step its
// wheels began on the ground (the step in which they reach it compresses
// the springs unresisted: a ray sees the ground only from the step's start,
// 0.61 J here), beyond rounding.
TEST_CASE("a car dropped onto its wheels settles with the overshoot its damping ratio allows, gaining no energy",
          "[car]") {
  const double rest = touching_height - mass * g / (4 * stiffness);
  Chassis spec;
  spec.height = fixed_of(rest + 0.5);
  TestCar c({}, {}, 1, tarmac(), spec);
  const double zeta = 3000.0 / (2 * std::sqrt(stiffness * mass / 4));
  const double decay = std::exp(-zeta * 3.14159265358979 / std::sqrt(1 - zeta * zeta));
  double lowest = rest + 0.5, highest_after = 0, gained = 0, energy = car_energy(c, stiffness);
  bool rising = false;
  for (int step = 0; step < 300; ++step) {
    c.t.world.step();
    const double y = to_double(c.body().pose.position.y);
    if (!rising && to_double(c.body().linear_velocity.y) > 0) rising = y < rest;
    if (!rising) lowest = std::min(lowest, y);
    if (rising) highest_after = std::max(highest_after, y);
    const double now = car_energy(c, stiffness);
    bool grounded = true;
    for (const WheelState& wheel : c.state().wheels) grounded = grounded && wheel.on_ground;
    if (grounded) gained = std::max(gained, now - energy);
    energy = now;
  }
  const double sank = rest - lowest, overshoot = highest_after - rest;
  INFO("sank " << sank * 1000 << " mm below rest, rose " << overshoot * 1000 << " mm above it (allowed "
               << decay * sank * 1000 << "), most energy gained in a step " << gained << " J");
  CHECK(sank > 0.05);
  CHECK(overshoot <= decay * sank);
  CHECK(gained <= 1e-5);  // rounding: the weight, 1e4 N, times a few ulp (2^-32 m) of height
  CHECK(std::abs(to_double(c.body().pose.position.y) - rest) < 0.01 * (touching_height - rest));
  CHECK(to_double(length(c.body().linear_velocity)) < 1e-3);
}

// A suspension too stiff for an explicit spring at 60 Hz: a 100 kg chassis
// (25 kg a wheel) on 1e7 N/m has k h^2 / m = 111, where an explicit
// spring-damper force diverges past 4 (omega h > 2). As a soft row of the
// solve (an implicit spring) the chassis comes to rest at the analytic sag,
// m g / 4k = 24.5 um, from just touching.
TEST_CASE("a suspension too stiff for an explicit spring stays bounded and sags m g / 4k", "[car]") {
  Chassis spec;
  spec.mass = Fixed::from_int(100);
  spec.stiffness = 10000000.0_fx;
  spec.damping = 1000.0_fx;
  spec.height = fixed_of(touching_height);
  TestCar c({}, {}, 1, tarmac(), spec);
  double fastest = 0, highest = 0;
  for (int step = 0; step < 120; ++step) {  // 2 s
    c.t.world.step();
    fastest = std::max(fastest, std::abs(to_double(c.body().linear_velocity.y)));
    highest = std::max(highest, to_double(c.body().pose.position.y));
  }
  const double sag = 100 * g / (4 * 1e7);
  const double y = to_double(c.body().pose.position.y);
  INFO("after 2 s: " << (touching_height - y) * 1e6 << " um below touching (m g / 4k = " << sag * 1e6
                     << " um); fastest " << fastest << " m/s, highest " << highest << " m");
  CHECK(std::abs(y - (touching_height - sag)) < 1e-3);
  CHECK(fastest < 1.0);
  CHECK(highest < touching_height + 0.01);
}

// Up a 5 cm step at 10 m/s on one ray a wheel: the ray's compression jumps
// by 5 cm in a step. The springs can then give the chassis no more than
// the energy they took, n k d^2 / 2 (4 x 50 J), so its vertical speed stays
// within sqrt(n k d^2 / m) = 0.63 m/s; no wheel's ray starts inside the
// ground, the chassis touches nothing, and it settles 5 cm higher.
TEST_CASE("up a 5 cm step at 10 m/s the chassis's vertical speed stays bounded and no wheel sinks through", "[car]") {
  TestCar car;
  TestWorld& t = car.t;
  BodyDef step_body;
  step_body.type = BodyType::static_body;
  step_body.pose.position = {Fixed{}, 0.025_fx, 35.0_fx};  // from z = 20 to 50, its top at 5 cm
  step_body.shapes.push_back({ShapeType::box, {5.0_fx, 0.025_fx, 15.0_fx}, {}, {}, {}});
  step_body.material = tarmac();
  const BodyId step_id = t.world.create_body(step_body).value();
  t.simulate_steps(120);
  t.world.set_velocity(car.chassis, {Fixed{}, Fixed{}, 10.0_fx}, {});
  const CarDef& def = car.state().def;
  const Fixed full = def.rest_length + def.wheel_radius;
  double fastest = 0, deepest = 0;
  int on_step = 0;
  for (int step = 0; step < 240; ++step) {  // 4 s: over the step at 2 s, 2 s on it
    t.world.step();
    fastest = std::max(fastest, std::abs(to_double(car.body().linear_velocity.y)));
    for (const WheelState& wheel : car.state().wheels) {
      if (!wheel.on_ground) continue;
      CHECK(wheel.compression < full);
      deepest = std::max(deepest, to_double(wheel.compression));
      if (wheel.ground == step_id.index) ++on_step;
    }
    for (const Contact& contact : t.world.contacts()) {
      if (contact.key.body_b != car.chassis.index && contact.key.body_a != car.chassis.index) continue;
      CHECK_FALSE(touches(contact.manifold));
    }
  }
  const double rest = touching_height - mass * g / (4 * stiffness);
  const double y = to_double(car.body().pose.position.y);
  INFO("fastest vertical " << fastest << " m/s, deepest compression " << deepest * 1000 << " mm, finally "
                           << (y - 0.05 - rest) * 1000 << " mm from rest on the step");
  CHECK(on_step > 0);
  CHECK(fastest < std::sqrt(4 * stiffness * 0.05 * 0.05 / mass));
  CHECK(deepest < to_double(full) - 0.1);
  CHECK(std::abs(y - (0.05 + rest)) < 0.001);
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
    // Every step each tyre's force stays within its friction circle,
    // mu_s N (the pair's mixed coefficient, N its suspension's force).
    const double mu = std::sqrt(1.0 * 0.8);
    double worst = 0;
    for (int step = 0; step < 180; ++step) {
      c.t.world.step();
      for (const WheelState& wheel : c.state().wheels) {
        worst = std::max(worst, to_double(length(wheel.tyre_force)) - mu * to_double(wheel.suspension_force));
      }
    }
    CHECK(worst < 1e-3);
    // Braked along it, the jolt slides it as far as full grip would,
    // v^2 / (2 mu g), within 25% (the pitch moves load between the axles).
    // Sideways the tyres' pull at mu g = 0.89 g meets this tall car's
    // static stability factor (track / 2 h = 0.89): the leading wheels lift,
    // the chassis heaves, and the loaded wheels' grip stops it sooner.
    if (m.braked) {
      const double v = to_double(length(m.velocity));
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
  const BodyId bump_id = t.world.create_body(bump).value();
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

namespace {

// A slope of `degrees` as gravity tilted on flat ground (the same physics,
// without a ramp's edges): downhill along -z (`along`, the car facing
// uphill) or along -x (across the car).
Settings on_slope(double degrees, bool along) {
  Settings s;
  const double rad = degrees * 3.14159265358979 / 180;
  const Fixed downhill = Fixed::from_raw(static_cast<int64_t>(std::llround(-g * std::sin(rad) * 4294967296.0)));
  s.gravity = {along ? Fixed{} : downhill, Fixed::from_raw(static_cast<int64_t>(std::llround(-g * std::cos(rad) * 4294967296.0))),
               along ? downhill : Fixed{}};
  return s;
}

// The chassis's speed down the slope's fall line, and its place along it.
double downhill(const Vec3& v, bool along) { return -to_double(along ? v.z : v.x); }

}  // namespace

// The tyres' static friction on tarmac is sqrt(1.0 x 0.8) = 0.894 (tan
// 41.8 deg): on every slope below it a braked car must not move at all
// along the slope, and across it (up to 30 degrees: at 38 the car tips
// over) the side grip alone holds it. Beyond its grip the locked tyres
// slide at g (sin - mu_d cos). The brake and the grip are rows of the
// solve: they hold the velocity this step's gravity gives the chassis, not
// only the one it had when the step began (which let a braked car creep
// down 20 degrees at 0.1 m/s).
TEST_CASE("a car holds still on every slope its tyres can hold: braked along it, by side grip across it", "[car]") {
  for (const bool along : {true, false}) {
    for (const double degrees : {5.0, 20.0, 30.0, 40.0}) {
      if (!along && degrees > 30) continue;
      INFO((along ? "along" : "across") << " a " << degrees << " degree slope");
      TestCar c(on_slope(degrees, along));
      if (along) c.t.world.set_car_controls(c.car, {Fixed{}, Fixed::one(), Fixed{}});  // across: no brake
      // Settled on its springs: across 30 degrees the implicit springs'
      // roll still moves the chassis 10 um uphill between 2 and 2.5 s.
      c.t.simulate_steps(180);
      const Vec3 parked = c.body().pose.position;
      double fastest = 0;
      for (int step = 0; step < 600; ++step) {  // 10 s, the springs' last sway in the first 5
        c.t.world.step();
        if (step >= 300) fastest = std::max(fastest, to_double(length(c.body().linear_velocity)));
      }
      const double moved = to_double(length(c.body().pose.position - parked));
      INFO("moved " << moved * 1000 << " mm in 10 s, fastest " << fastest << " m/s");
      CHECK(moved < 1e-5);
      CHECK(fastest < 1e-5);
    }
  }
}

TEST_CASE("beyond its grip a braked car slides down at g (sin - mu_d cos) within 3%", "[car]") {
  struct Case {
    bool along;
    double degrees, road_friction;
  };
  for (const Case& k : {Case{true, 50, 0.8}, Case{false, 30, 0.2}}) {
    const double rad = k.degrees * 3.14159265358979 / 180, mu = std::sqrt(1.0 * k.road_friction);
    INFO((k.along ? "along" : "across") << " a " << k.degrees << " degree slope, mu " << mu);
    Material road;
    road.static_friction = road.dynamic_friction = Fixed::from_ratio(static_cast<int64_t>(k.road_friction * 10), 10);
    TestCar c(on_slope(k.degrees, k.along), {}, 1, road);
    c.t.world.set_car_controls(c.car, {Fixed{}, Fixed::one(), Fixed{}});
    c.t.simulate_steps(60);
    const double v0 = downhill(c.body().linear_velocity, k.along);
    c.t.simulate_steps(120);  // 2 s
    const double a = (downhill(c.body().linear_velocity, k.along) - v0) / 2.0;
    const double expected = g * (std::sin(rad) - mu * std::cos(rad));
    INFO("acceleration " << a << " m/s^2, expected " << expected);
    CHECK(std::abs(a - expected) < 0.03 * expected);
  }
}

TEST_CASE("unbraked, a car rolls down a 20 degree slope at g sin 20 within 2% and keeps its heading", "[car]") {
  const double rad = 20 * 3.14159265358979 / 180;
  TestCar c(on_slope(20, true));
  c.t.world.set_car_controls(c.car, {Fixed{}, Fixed::one(), Fixed{}});
  c.t.simulate_steps(60);  // settled, braked
  c.t.world.set_car_controls(c.car, {});
  c.t.simulate_steps(120);  // 2 s rolling
  const double v = downhill(c.body().linear_velocity, true);
  INFO("speed after 2 s " << v << " m/s");
  CHECK(std::abs(v / 2.0 - g * std::sin(rad)) < 0.02 * g * std::sin(rad));
  CHECK(std::abs(to_double(c.body().pose.position.x)) < 0.001);
}
