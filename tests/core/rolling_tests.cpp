// Rolling resistance against the analytic answers. A ball of radius r
// rolling without slip, with the pair's coefficient c, feels a resisting
// torque c r N about its contact. About the contact point:
//   (I + m r^2) dw/dt = -c r m g cos(theta) + m g r sin(theta)
// so on flat ground it slows at a = c g / (1 + I / (m r^2)) = 5/7 c g, on a
// slope of angle theta it holds while tan(theta) <= c and otherwise rolls
// down at 5/7 g (sin(theta) - c cos(theta)). With c = 0 it rolls for ever.
#include <catch2/catch.hpp>

#include <cmath>

#include "tests/core/test_world.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::TestWorld;
using bitstep::test::to_double;

namespace {

constexpr double g = 9.81;

Material rolling(Fixed c) {
  Material m;
  m.rolling_resistance = c;
  return m;
}

Settings with_pipeline(Pipeline pipeline) {
  Settings settings;
  settings.pipeline = pipeline;
  return settings;
}

// A ball (r 0.25 m) on the ground, rolling along +x at `speed` m/s without
// slip: w = -v / r about z.
struct RollingBall {
  TestWorld t;
  BodyId ball;
  RollingBall(Fixed c, Fixed speed, Pipeline pipeline) : t(with_pipeline(pipeline)) {
    t.add_ground(rolling(c));
    BodyDef def;
    def.pose.position = {Fixed{}, 0.25_fx, Fixed{}};
    def.shapes.push_back({ShapeType::sphere, {}, 0.25_fx, {}, {}});
    def.material = rolling(c);
    def.linear_velocity = {speed, Fixed{}, Fixed{}};
    def.angular_velocity = {Fixed{}, Fixed{}, -speed / 0.25_fx};
    ball = t.world.create_body(def).value();
  }
  double speed() const { return to_double(t.body(ball).linear_velocity.x); }
};

// A ball (r 0.25 m) released at rest on a ramp tilted by `radians` about z.
struct BallOnRamp {
  TestWorld t;
  BodyId ball;
  Vec3 down_slope;
  BallOnRamp(Fixed c, Fixed radians, Pipeline pipeline) : t(with_pipeline(pipeline)) {
    const Quat tilt = from_axis_angle({Fixed{}, Fixed{}, Fixed::one()}, radians);
    t.add_ramp(tilt, rolling(c));
    const Vec3 normal = rotate(tilt, {Fixed{}, Fixed::one(), Fixed{}});
    down_slope = -rotate(tilt, {Fixed::one(), Fixed{}, Fixed{}});
    ball = t.add_sphere(normal * 0.75_fx, 0.25_fx, rolling(c));  // ramp half-thickness + radius
  }
  double along() const { return to_double(dot(t.body(ball).pose.position, down_slope)); }
  double speed() const { return to_double(dot(t.body(ball).linear_velocity, down_slope)); }
};

const char* name_of(Pipeline pipeline) { return pipeline == Pipeline::standard ? "standard" : "guendelman"; }

}  // namespace

TEST_CASE("a rolling ball slows at 5/7 c g", "[physics][rolling]") {
  for (Pipeline pipeline : {Pipeline::standard, Pipeline::guendelman}) {
    RollingBall roll(0.01_fx, 2.0_fx, pipeline);
    roll.t.simulate_steps(60);
    const double v1 = roll.speed();
    roll.t.simulate_steps(120);
    const double v3 = roll.speed();
    const double measured = (v1 - v3) / 2.0, expected = 5.0 / 7.0 * 0.01 * g;
    INFO(name_of(pipeline) << ": slows at " << measured << " m/s^2, expected " << expected);
    CHECK(std::abs(measured - expected) < 0.02 * expected);
  }
}

TEST_CASE("without rolling resistance a ball rolls on undiminished", "[physics][rolling]") {
  for (Pipeline pipeline : {Pipeline::standard, Pipeline::guendelman}) {
    RollingBall roll(Fixed{}, 2.0_fx, pipeline);
    roll.t.simulate_steps(300);
    INFO(name_of(pipeline) << ": " << roll.speed() << " m/s after 5 s");
    CHECK(std::abs(roll.speed() - 2.0) < 1e-6);
  }
}

TEST_CASE("a ball holds on a slope below its rolling-resistance angle and rolls above it",
          "[physics][rolling]") {
  for (Pipeline pipeline : {Pipeline::standard, Pipeline::guendelman}) {
    INFO(name_of(pipeline));
    // c 0.02: tan(theta) 0.01 holds, the ball moves under 0.1 mm in 5 s.
    BallOnRamp holds(0.02_fx, 0.01_fx, pipeline);
    holds.t.simulate_steps(60);
    const double start = holds.along();
    holds.t.simulate_steps(300);
    INFO("held: moved " << holds.along() - start << " m");
    CHECK(std::abs(holds.along() - start) < 0.0001);
    // tan(theta) 0.05 rolls at 5/7 g (sin - c cos).
    BallOnRamp rolls(0.02_fx, 0.05_fx, pipeline);
    rolls.t.simulate_steps(60);
    const double v1 = rolls.speed();
    rolls.t.simulate_steps(60);
    const double measured = rolls.speed() - v1;
    const double expected = 5.0 / 7.0 * g * (std::sin(0.05) - 0.02 * std::cos(0.05));
    INFO("rolls at " << measured << " m/s^2, expected " << expected);
    CHECK(std::abs(measured - expected) < 0.02 * expected);
  }
}
