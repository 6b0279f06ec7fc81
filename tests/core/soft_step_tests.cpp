// The soft step (core/soft_step.h): Catto's coefficients, and motion
// against the analytic answers: a ball dropped onto the ground comes to
// rest at the contact spring's sag g / w^2, a sliding box stops at
// v0^2 / (2 mu g), a bouncing ball rises to e^2 h.
#include <catch2/catch.hpp>

#include <cmath>

#include "core/soft_step.h"
#include "tests/core/test_world.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::TestWorld;
using bitstep::test::to_double;

namespace {

constexpr double g = 9.81;

// Four substeps of 1/240 s: the contact at a quarter of that rate, 60 Hz.
Settings soft_settings() {
  Settings settings;
  settings.soft_substeps = 4;
  settings.contact_hertz = 60.0_fx;
  return settings;
}

double omega() { return 2 * M_PI * 60.0; }

}  // namespace

TEST_CASE("soft step: the softness coefficients are Catto's", "[soft]") {
  const double hertz = 30, zeta = 10, h = 1.0 / 240;
  const Softness s = make_softness(30.0_fx, 10.0_fx, Fixed::one() / 240.0_fx);
  const double w = 2 * M_PI * hertz, a1 = 2 * zeta + h * w, a2 = h * w * a1, a3 = 1 / (1 + a2);
  CHECK(to_double(s.bias_rate) == Approx(w / a1).epsilon(1e-7));
  CHECK(to_double(s.mass_scale) == Approx(a2 * a3).epsilon(1e-7));
  CHECK(to_double(s.impulse_scale) == Approx(a3).epsilon(1e-7));
  // 0 Hz: a rigid row (no bias, the whole mass, nothing of the impulse).
  const Softness rigid = make_softness(Fixed{}, 10.0_fx, Fixed::one() / 240.0_fx);
  CHECK(rigid.mass_scale == Fixed{});
  CHECK(rigid.impulse_scale == Fixed::one());
}

TEST_CASE("soft step: a dropped ball lands and rests at the spring's sag", "[soft]") {
  TestWorld t(soft_settings());
  t.add_ground();
  const BodyId ball = t.add_sphere({Fixed{}, 1.5_fx, Fixed{}}, 0.5_fx);  // 1 m above the ground
  double deepest = 0;
  for (int step = 0; step < 180; ++step) {
    t.world.step();
    deepest = std::max(deepest, 0.5 - to_double(t.body(ball).pose.position.y));
  }
  // The ball's contact has its mass alone (the normal passes through its
  // centre): the spring m w^2 holds m g at a sag of g / w^2 (0.069 mm).
  const double sag = g / (omega() * omega());
  CHECK(0.5 - to_double(t.body(ball).pose.position.y) == Approx(sag).epsilon(0.001));
  CHECK(std::abs(to_double(t.body(ball).linear_velocity.y)) < 1e-5);
  // It landed at 4.4 m/s: the speculative contact met it at the surface.
  CHECK(deepest < 2 * sag);
}

TEST_CASE("soft step: a box sliding at 5 m/s stops at v0^2 / (2 mu g)", "[soft]") {
  TestWorld t(soft_settings());
  t.add_ground();
  const BodyId box = t.add_box({Fixed{}, 0.25_fx, Fixed{}}, {0.25_fx, 0.25_fx, 0.25_fx});
  t.simulate_steps(30);  // settle onto its spring
  t.world.set_velocity(box, {5.0_fx, Fixed{}, Fixed{}}, Vec3{});
  const double x0 = to_double(t.body(box).pose.position.x);
  t.simulate_steps(120);
  const double exact = 25.0 / (2 * 0.5 * g);
  CHECK(to_double(t.body(box).pose.position.x) - x0 == Approx(exact).epsilon(0.02));
  CHECK(to_double(length(t.body(box).linear_velocity)) < 1e-4);
}

TEST_CASE("soft step: a ball with restitution 0.5 rises to e^2 h", "[soft]") {
  TestWorld t(soft_settings());
  t.add_ground();
  Material bouncy;
  bouncy.restitution = 0.5_fx;
  const BodyId ball = t.add_sphere({Fixed{}, 1.5_fx, Fixed{}}, 0.5_fx, bouncy);
  bool landed = false;
  double peak = 0;
  for (int step = 0; step < 60; ++step) {
    t.world.step();
    const double height = to_double(t.body(ball).pose.position.y) - 0.5;
    if (t.body(ball).linear_velocity.y > Fixed{}) landed = true;
    if (landed) peak = std::max(peak, height);
  }
  REQUIRE(landed);
  CHECK(peak == Approx(0.25).epsilon(0.08));
}
