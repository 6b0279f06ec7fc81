// Sliders (prismatic joints) and motors, measured in motion: a slider
// struck off its axis, against its limit and sliding down a tilted axis;
// a hinge motor and a slider motor reaching their speed, holding it under
// a load within their bound and giving way beyond it.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "core/joint_solver.h"
#include "tests/core/test_world.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::TestWorld;
using bitstep::test::to_double;

namespace {

constexpr double pi = 3.14159265358979323846;

BodyId add_block(TestWorld& t, Vec3 position, Fixed mass) {
  BodyDef def;
  def.pose.position = position;
  def.shapes.push_back({ShapeType::box, {0.2_fx, 0.1_fx, 0.15_fx}, {}, {}, {}});
  def.mass = mass;
  return t.world.create_body(def).value();
}

JointDef joint_def(JointType type, BodyId a, BodyId b, Vec3 anchor, Vec3 axis) {
  JointDef def;
  def.type = type;
  def.body_a = a;
  def.body_b = b;
  def.anchor_a = anchor;
  def.axis = axis;
  return def;
}

JointId make_joint(TestWorld& t, const JointDef& def) {
  const Result<JointId> made = t.world.create_joint(def);
  if (!made.ok()) FAIL(made.error().message());
  return made.value();
}

const Joint& joint_of(const TestWorld& t, JointId id) { return t.world.joints()[id.index]; }

double translation(const TestWorld& t, JointId id) {
  const Joint& joint = joint_of(t, id);
  return to_double(slider_translation(joint, t.world.bodies()[joint.body_a], t.world.bodies()[joint.body_b]));
}

// How far b's anchor is off a's axis (m).
double off_axis(const TestWorld& t, JointId id) {
  const Joint& joint = joint_of(t, id);
  const Body& a = t.world.bodies()[joint.body_a];
  const Body& b = t.world.bodies()[joint.body_b];
  const Vec3 gap = b.pose.apply(joint.local_anchor_b) - a.pose.apply(joint.local_anchor_a);
  const Vec3 axis = rotate(a.pose.orientation, joint.local_axis_a);
  return to_double(length(gap - axis * dot(gap, axis)));
}

// The angle (degrees) between two orientations.
double turned_degrees(Quat from, Quat to) {
  const Quat relative = to * conjugate(from);
  const double w = std::min(1.0, std::abs(to_double(relative.w)));
  return 2 * std::acos(w) * 180 / pi;
}

double along(Vec3 v, Vec3 axis) { return to_double(dot(v, axis)); }

// A torque about z on `body` for the next step, as a couple of forces.
void apply_torque_z(TestWorld& t, BodyId body, double torque) {
  const Vec3 centre = t.body(body).pose.position;
  const Fixed half = Fixed::from_ratio(static_cast<int64_t>(torque * 1000), 2000);  // N at +-1 m
  t.world.apply_force(body, {Fixed{}, half, Fixed{}}, centre + Vec3{Fixed::one(), {}, {}});
  t.world.apply_force(body, {Fixed{}, -half, Fixed{}}, centre - Vec3{Fixed::one(), {}, {}});
}

}  // namespace

TEST_CASE("a slider struck off its axis keeps b on the axis, unturned, while it slides", "[joint][slider]") {
  TestWorld t;  // gravity across the axis too
  const BodyId anchor = t.add_anchor({Fixed{}, 2.0_fx, Fixed{}});
  const BodyId block = add_block(t, {Fixed{}, 2.0_fx, Fixed{}}, 1.0_fx);
  const Vec3 axis = normalize(Vec3{Fixed::one(), Fixed{}, 0.5_fx});
  const JointId slider = make_joint(t, joint_def(JointType::slider, anchor, block, {Fixed{}, 2.0_fx, Fixed{}}, axis));
  const Quat start = t.body(block).pose.orientation;
  // 4.3 N s, 2 N s across the axis, at a corner: it would tumble away.
  const Vec3 blow{3.0_fx, 2.0_fx, -1.5_fx};
  t.world.apply_impulse(block, blow, t.body(block).pose.position + Vec3{0.2_fx, 0.1_fx, 0.15_fx});
  const double expected_speed = along(blow, axis);  // 1 kg: the blow's part along the axis
  double worst_off = 0, worst_turn = 0;
  for (int step = 0; step < 120; ++step) {
    t.world.step();
    worst_off = std::max(worst_off, off_axis(t, slider));
    worst_turn = std::max(worst_turn, turned_degrees(start, t.body(block).pose.orientation));
  }
  INFO("off the axis " << worst_off * 1000 << " mm, turned " << worst_turn << " degrees");
  CHECK(worst_off < 0.001);
  CHECK(worst_turn < 0.1);
  // It slides on at the blow's speed along the axis (no friction).
  const double speed = along(t.body(block).linear_velocity, axis);
  INFO("speed " << speed << " m/s, expected " << expected_speed);
  CHECK(std::abs(speed - expected_speed) < 0.01 * expected_speed);
  CHECK(translation(t, slider) > 1.5 * expected_speed);
}

TEST_CASE("a slider between two free bodies keeps b on a's turning axis while the pair tumbles", "[joint][slider]") {
  Settings settings;
  settings.gravity = {};
  TestWorld t(settings);
  const BodyId a = add_block(t, {}, 2.0_fx);
  const BodyId b = add_block(t, {0.5_fx, Fixed{}, Fixed{}}, 1.0_fx);
  const JointId slider =
      make_joint(t, joint_def(JointType::slider, a, b, {0.5_fx, Fixed{}, Fixed{}}, {Fixed::one(), Fixed{}, Fixed{}}));
  // A blow at b's corner: the pair tumbles at a few rad/s while b slides out.
  t.world.apply_impulse(b, {0.5_fx, 1.0_fx, 0.3_fx}, t.body(b).pose.position + Vec3{0.2_fx, 0.1_fx, 0.15_fx});
  const auto energy = [&] {
    double sum = 0;
    for (const BodyId id : {a, b}) {
      const Body& body = t.body(id);
      const double m = 1 / to_double(body.inverse_mass);
      const Vec3 w = body.angular_velocity;
      const Vec3 local = rotate_inverse(body.pose.orientation, w);
      sum += 0.5 * m * to_double(dot(body.linear_velocity, body.linear_velocity)) +
             0.5 * to_double(dot(local, body.inertia_local * local));
    }
    return sum;
  };
  t.world.step();
  const double start_energy = energy();
  double worst_off = 0, worst_turn = 0, most_spin = 0;
  for (int step = 0; step < 120; ++step) {
    t.world.step();
    worst_off = std::max(worst_off, off_axis(t, slider));
    worst_turn = std::max(worst_turn, turned_degrees(t.body(a).pose.orientation, t.body(b).pose.orientation));
    most_spin = std::max(most_spin, to_double(length(t.body(a).angular_velocity)));
  }
  INFO("off the axis " << worst_off * 1000 << " mm, turned " << worst_turn << " degrees, spin " << most_spin
                       << " rad/s, translation " << translation(t, slider) << " m, energy " << start_energy << " -> "
                       << energy() << " J");
  CHECK(most_spin > 1.0);
  CHECK(worst_off < 0.001);
  CHECK(worst_turn < 0.1);
  CHECK(translation(t, slider) > 0.1);
  CHECK(energy() < start_energy * 1.01);
  CHECK(energy() > start_energy * 0.9);
}

TEST_CASE("a slider struck along its axis stops at its limit, without sticking or bouncing", "[joint][slider]") {
  Settings settings;
  settings.gravity = {};
  TestWorld t(settings);
  const BodyId anchor = t.add_anchor({});
  const BodyId block = add_block(t, {}, 2.0_fx);
  JointDef def = joint_def(JointType::slider, anchor, block, {}, {Fixed::one(), Fixed{}, Fixed{}});
  def.limited = true;
  def.lower_translation = -0.25_fx;
  def.upper_translation = 0.5_fx;
  const JointId slider = make_joint(t, def);
  t.world.apply_impulse(block, {8.0_fx, Fixed{}, Fixed{}}, t.body(block).pose.position);  // 4 m/s
  double farthest = 0;
  for (int step = 0; step < 60; ++step) {
    t.world.step();
    farthest = std::max(farthest, translation(t, slider));
  }
  INFO("farthest " << farthest << " m");
  CHECK(farthest < 0.5 + 0.01);
  CHECK(farthest > 0.5 - 0.01);
  // At rest against the limit: restitution 0, no bounce.
  CHECK(std::abs(to_double(t.body(block).linear_velocity.x)) < 0.001);
  CHECK(std::abs(translation(t, slider) - 0.5) < 0.005);
  // Struck back, it leaves the limit at once at the blow's speed.
  t.world.apply_impulse(block, {-2.0_fx, Fixed{}, Fixed{}}, t.body(block).pose.position);  // -1 m/s
  t.simulate_steps(6);
  CHECK(std::abs(to_double(t.body(block).linear_velocity.x) + 1.0) < 0.01);
  CHECK(translation(t, slider) < 0.5 - 0.09);
  // And stops at the lower limit.
  double nearest = 0;
  for (int step = 0; step < 60; ++step) {
    t.world.step();
    nearest = std::min(nearest, translation(t, slider));
  }
  CHECK(nearest > -0.25 - 0.01);
  CHECK(std::abs(translation(t, slider) + 0.25) < 0.005);
}

TEST_CASE("a slider on an axis tilted 30 degrees accelerates at g sin 30 degrees", "[joint][slider]") {
  TestWorld t;
  const BodyId anchor = t.add_anchor({Fixed{}, 5.0_fx, Fixed{}});
  const BodyId block = add_block(t, {Fixed{}, 5.0_fx, Fixed{}}, 3.0_fx);
  const Vec3 axis{"0.86602540378"_fx, -0.5_fx, Fixed{}};  // down the slope
  const JointId slider = make_joint(t, joint_def(JointType::slider, anchor, block, {Fixed{}, 5.0_fx, Fixed{}}, axis));
  t.simulate_steps(60);
  const double v1 = along(t.body(block).linear_velocity, axis);
  t.simulate_steps(60);
  const double v2 = along(t.body(block).linear_velocity, axis);
  const double g = -to_double(t.world.settings().gravity.y);
  const double acceleration = v2 - v1;  // over 1 s
  INFO("acceleration " << acceleration << " m/s^2, g sin 30 = " << g / 2);
  CHECK(std::abs(acceleration - g / 2) < 0.01 * g / 2);
  CHECK(std::abs(v1 - g / 2) < 0.01 * g / 2);
  CHECK(off_axis(t, slider) < 0.001);
}

TEST_CASE("a hinge motor spins a wheel up to its speed, holds it under a load within its torque, slips beyond",
          "[joint][motor]") {
  TestWorld t;
  const BodyId anchor = t.add_anchor({Fixed{}, 2.0_fx, Fixed{}});
  BodyDef wheel_def;
  wheel_def.pose.position = {Fixed{}, 2.0_fx, Fixed{}};
  wheel_def.shapes.push_back({ShapeType::sphere, {}, 0.5_fx, {}, {}});
  wheel_def.mass = 1.0_fx;  // I = 2/5 m r^2 = 0.1 kg m^2
  const BodyId wheel = t.world.create_body(wheel_def).value();
  JointDef def =
      joint_def(JointType::hinge, anchor, wheel, {Fixed{}, 2.0_fx, Fixed{}}, {Fixed{}, Fixed{}, Fixed::one()});
  def.motor_speed = 5.0_fx;  // rad/s
  def.motor_max = 10.0_fx;   // N m
  const JointId hinge = make_joint(t, def);
  const double bound = 10.0 * to_double(t.world.settings().dt);
  double largest_impulse = 0;
  const auto run = [&](int steps, double load) {
    for (int i = 0; i < steps; ++i) {
      if (load != 0) apply_torque_z(t, wheel, -load);
      t.world.step();
      largest_impulse = std::max(largest_impulse, std::abs(to_double(joint_of(t, hinge).motor_impulse)));
    }
  };
  run(60, 0);
  const double free_speed = to_double(t.body(wheel).angular_velocity.z);
  INFO("unloaded " << free_speed << " rad/s");
  CHECK(std::abs(free_speed - 5.0) < 0.05);
  run(60, 6.0);  // 6 N m against it: within the motor's 10
  const double loaded_speed = to_double(t.body(wheel).angular_velocity.z);
  INFO("under 6 N m " << loaded_speed << " rad/s");
  CHECK(std::abs(loaded_speed - 5.0) < 0.05);
  // 15 N m: the motor gives its 10 and the wheel slows at (15 - 10) / I.
  run(6, 15.0);
  const double before = to_double(t.body(wheel).angular_velocity.z);
  run(12, 15.0);
  const double after = to_double(t.body(wheel).angular_velocity.z);
  const double deceleration = (before - after) / (12 * to_double(t.world.settings().dt));
  INFO("under 15 N m it slows at " << deceleration << " rad/s^2 (50 expected)");
  CHECK(after < before);
  CHECK(std::abs(deceleration - 50.0) < 0.02 * 50.0);
  INFO("largest motor impulse " << largest_impulse << " N m s, bound " << bound);
  CHECK(largest_impulse <= bound + 1e-9);
  // Changed at run time: the other way, and off.
  REQUIRE(t.world.set_joint_motor(hinge, -3.0_fx, 10.0_fx).ok());
  run(60, 0);
  CHECK(std::abs(to_double(t.body(wheel).angular_velocity.z) + 3.0) < 0.03);
  REQUIRE(t.world.set_joint_motor(hinge, Fixed{}, Fixed{}).ok());
  CHECK(joint_of(t, hinge).motor_impulse == Fixed{});
  t.world.apply_impulse(wheel, {Fixed{}, 0.1_fx, Fixed{}}, t.body(wheel).pose.position + Vec3{Fixed::one(), {}, {}});
  const double spun = to_double(t.body(wheel).angular_velocity.z);
  run(30, 0);
  CHECK(to_double(t.body(wheel).angular_velocity.z) == Approx(spun).margin(1e-4));  // coasts: no motor
}

TEST_CASE("a slider motor lifts a load at its speed and stalls when the load outweighs its force", "[joint][motor]") {
  TestWorld t;
  const BodyId anchor = t.add_anchor({});
  const Vec3 up{Fixed{}, Fixed::one(), Fixed{}};
  const auto lift = [&](Fixed mass, Fixed x) {
    const BodyId load = add_block(t, {x, Fixed{}, Fixed{}}, mass);  // apart: they do not touch
    JointDef def = joint_def(JointType::slider, anchor, load, {x, Fixed{}, Fixed{}}, up);
    def.motor_speed = 0.5_fx;  // m/s
    def.motor_max = 50.0_fx;   // N
    const JointId slider = make_joint(t, def);
    return std::pair{load, slider};
  };
  const auto [light, light_slider] = lift(2.0_fx, -1.0_fx);  // 19.6 N: within 50
  const auto [heavy, heavy_slider] = lift(10.0_fx, 1.0_fx);  // 98.1 N: beyond
  const double dt = to_double(t.world.settings().dt);
  double largest_impulse = 0;
  double heavy_v1 = 0;
  for (int step = 1; step <= 60; ++step) {
    t.world.step();
    largest_impulse = std::max({largest_impulse, std::abs(to_double(joint_of(t, light_slider).motor_impulse)),
                                std::abs(to_double(joint_of(t, heavy_slider).motor_impulse))});
    if (step == 30) heavy_v1 = to_double(t.body(heavy).linear_velocity.y);
  }
  const double light_speed = to_double(t.body(light).linear_velocity.y);
  INFO("the 2 kg load rises at " << light_speed << " m/s");
  CHECK(std::abs(light_speed - 0.5) < 0.005);
  CHECK(std::abs(translation(t, light_slider) - 0.5) < 0.05);  // 1 s at 0.5 m/s, less the spin-up
  const double heavy_v2 = to_double(t.body(heavy).linear_velocity.y);
  const double heavy_acceleration = (heavy_v2 - heavy_v1) / (30 * dt);
  const double expected = -(98.1 - 50.0) / 10.0;
  INFO("the 10 kg load: " << heavy_v2 << " m/s, accelerating at " << heavy_acceleration << " (" << expected << ")");
  CHECK(heavy_v2 < 0);
  CHECK(std::abs(heavy_acceleration - expected) < 0.02 * std::abs(expected));
  CHECK(largest_impulse <= 50.0 * dt + 1e-9);
}

TEST_CASE("motors and slider settings out of range are refused", "[joint][slider][motor]") {
  TestWorld t;
  const BodyId anchor = t.add_anchor({});
  const BodyId block = add_block(t, {}, 1.0_fx);
  JointDef def = joint_def(JointType::slider, anchor, block, {}, {Fixed::one(), Fixed{}, Fixed{}});
  def.limited = true;
  def.lower_translation = 0.1_fx;
  CHECK_FALSE(t.world.create_joint(def).ok());
  def.lower_translation = Fixed{};
  def.motor_max = -1.0_fx;
  CHECK_FALSE(t.world.create_joint(def).ok());
  def.motor_max = 1.0_fx;
  def.motor_speed = 1000.0_fx;
  CHECK_FALSE(t.world.create_joint(def).ok());
  JointDef point = def;
  point.type = JointType::point;
  point.limited = false;
  point.motor_speed = 1.0_fx;
  CHECK(t.world.create_joint(point).error().message() == "motor: only hinges and sliders have one");
  def.motor_speed = 1.0_fx;
  const Result<JointId> made = t.world.create_joint(def);
  REQUIRE(made.ok());
  const Result<void> refused = t.world.set_joint_motor(made.value(), 1.0_fx, -1.0_fx);
  REQUIRE(!refused.ok());
  CHECK(refused.error().message() == "motor: max_torque or max_force outside 0..1000000");
  CHECK(joint_of(t, made.value()).motor_max == 1.0_fx);
}
