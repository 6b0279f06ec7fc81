#include <catch2/catch.hpp>

#include "fixed/decimal.h"
#include "tests/core/test_world.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::TestWorld;

namespace {
using bitstep::test::to_double;
}  // namespace

TEST_CASE("free fall equals the integrator's own recurrence exactly", "[world][integration]") {
  TestWorld t;
  const BodyId ball = t.add_sphere({Fixed{}, 100.0_fx, Fixed{}}, 0.5_fx);
  const Settings& s = t.world.settings();
  // In free flight: v += g dt, then x += dt (v_start + v) / 2 (one rounding
  // for the mean, one for mul_add).
  Fixed v, y = 100.0_fx;
  for (int step = 0; step < 120; ++step) {
    t.world.step();
    const Fixed start = v;
    v += s.gravity.y * s.dt;
    y = mul_add((start + v) / 2.0_fx, s.dt, y);
    REQUIRE(t.body(ball).linear_velocity.y == v);
    REQUIRE(t.body(ball).pose.position.y == y);
  }
  // The recurrence is the exact parabola y0 - g t^2 / 2 (plain semi-implicit
  // Euler would lag it by g dt t / 2 = 0.1635 m here): only rounding remains.
  const double t_end = 2.0, g = 9.81;
  const double continuous = 100.0 - g * t_end * t_end / 2.0;
  CHECK(to_double(y) == Approx(continuous).margin(1e-6));
  CHECK(to_double(v) == Approx(-g * t_end).margin(1e-6));
}

TEST_CASE("bodies outside the world envelope are refused and the world is unchanged", "[world][envelope]") {
  TestWorld t;
  BodyDef def;
  def.shapes.push_back({ShapeType::box, {60.0_fx, 1.0_fx, 1.0_fx}, {}, {}, {}});
  const Result<BodyId> too_big = t.world.create_body(def);
  CHECK_FALSE(too_big.ok());
  CHECK(too_big.error().place == "shapes[0].half_extents");
  def.shapes[0].half_extents = {1.0_fx, 1.0_fx, 1.0_fx};
  def.pose.position = {20000.0_fx, Fixed{}, Fixed{}};
  CHECK(t.world.create_body(def).error().place == "position");
  def.pose.position = {};
  def.density = 200000.0_fx;  // 8 m^3 x 2e5 kg/m^3 = 1.6e6 kg
  CHECK(t.world.create_body(def).error().place == "density");
  CHECK(t.world.bodies().empty());
}

TEST_CASE("a body's mass and inertia follow from its shapes and density", "[world][mass]") {
  TestWorld t;
  const BodyId cube = t.add_box({}, {0.5_fx, 0.5_fx, 0.5_fx});
  // 1 m^3 of 1000 kg/m^3: 1000 kg; I = m (h^2 + h^2) / 3 = 166.67 kg m^2.
  CHECK(t.body(cube).inverse_mass == Fixed::one() / 1000.0_fx);
  CHECK(to_double(t.body(cube).inertia_local.rows[0].x) == Approx(1000.0 / 6.0).epsilon(1e-9));
  CHECK(t.body(cube).inertia_local.rows[0].y == Fixed{});
}

TEST_CASE("a compound body moves its frame to the centre of mass", "[world][mass]") {
  TestWorld t;
  BodyDef def;
  // Two equal cubes at x = 0 and x = 2: the centre of mass is at x = 1.
  def.shapes.push_back({ShapeType::box, {0.5_fx, 0.5_fx, 0.5_fx}, {}, {}, {}});
  def.shapes.push_back({ShapeType::box, {0.5_fx, 0.5_fx, 0.5_fx}, {}, {}, {{2.0_fx, Fixed{}, Fixed{}}, {}}});
  const BodyId id = t.world.create_body(def).value();
  CHECK(t.body(id).pose.position.x == 1.0_fx);
  CHECK(t.body(id).shapes[0].local.position.x == -1.0_fx);
  CHECK(t.body(id).shapes[1].local.position.x == 1.0_fx);
  // Parallel axis: I_yy = 2 (1000/6 + 1000 * 1^2) kg m^2.
  CHECK(to_double(t.body(id).inertia_local.rows[1].y) == Approx(2.0 * (1000.0 / 6.0 + 1000.0)).epsilon(1e-9));
}

TEST_CASE("removed bodies free their slot and stale handles stay dead", "[world][handles]") {
  TestWorld t;
  const BodyId a = t.add_box({}, {0.5_fx, 0.5_fx, 0.5_fx});
  CHECK(t.world.remove_body(a));
  CHECK_FALSE(t.world.is_alive(a));
  const BodyId b = t.add_box({}, {0.5_fx, 0.5_fx, 0.5_fx});
  CHECK(b.index == a.index);
  CHECK(b.generation == a.generation + 1);
  CHECK_FALSE(t.world.remove_body(a));
  CHECK(t.world.is_alive(b));
}
