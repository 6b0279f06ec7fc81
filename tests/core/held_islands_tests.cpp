// Held islands (core/held_islands.h): an island the contacts hold at rest
// runs Settings::held_velocity_iterations velocity passes, every other
// island the world's. The islands in motion must compute exactly what they
// computed with every island at the world's passes, step after step; the
// held ones must still stand.
#include <catch2/catch.hpp>

#include "tests/core/test_world.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::TestWorld;
using bitstep::test::to_double;

namespace {

struct Scene {
  TestWorld t;
  std::vector<BodyId> stack;        // a column of five boxes at rest on the ground
  BodyId slider, tumbler, dropped;  // in motion: on a ramp, tipping over, falling onto a box
  std::vector<BodyId> moving;

  explicit Scene(const Settings& settings) : t(settings) {
    t.add_ground();
    for (int i = 0; i < 5; ++i) {
      stack.push_back(t.add_box({Fixed{}, Fixed::from_ratio(2 * i + 1, 4), Fixed{}}, {0.25_fx, 0.25_fx, 0.25_fx}));
    }
    // A box sliding down a 30 degree ramp (mu 0.2: it never stops on it).
    Material slippery;
    slippery.static_friction = slippery.dynamic_friction = 0.2_fx;
    const Quat tilt = from_axis_angle({Fixed{}, Fixed{}, Fixed::one()}, -0.5235987756_fx);
    TestWorld& w = t;
    const BodyDef ramp_def = [&] {
      BodyDef def;
      def.type = BodyType::static_body;
      def.pose = {{Fixed{}, 5.0_fx, 20.0_fx}, tilt};
      def.shapes.push_back({ShapeType::box, {10.0_fx, 0.5_fx, 3.0_fx}, {}, {}, {}});
      def.material = slippery;
      return def;
    }();
    w.world.create_body(ramp_def);
    const Vec3 up_slope = rotate(tilt, {-8.0_fx, 0.75_fx, Fixed{}});
    BodyDef box;
    box.pose = {ramp_def.pose.position + up_slope, tilt};
    box.shapes.push_back({ShapeType::box, {0.25_fx, 0.25_fx, 0.25_fx}, {}, {}, {}});
    box.material = slippery;
    slider = w.world.create_body(box).value();
    // A tall plank standing on an edge's worth of its face, tipping over.
    BodyDef plank;
    plank.pose = {{-20.0_fx, 1.02_fx, Fixed{}}, from_axis_angle({Fixed{}, Fixed{}, Fixed::one()}, 0.2_fx)};
    plank.shapes.push_back({ShapeType::box, {0.1_fx, 1.0_fx, 0.5_fx}, {}, {}, {}});
    tumbler = w.world.create_body(plank).value();
    // A box dropped from 2 m onto a box on the ground (impacts, then a pile).
    t.add_box({20.0_fx, 0.25_fx, Fixed{}}, {0.25_fx, 0.25_fx, 0.25_fx});
    dropped = t.add_box({20.1_fx, 2.75_fx, 0.05_fx}, {0.25_fx, 0.25_fx, 0.25_fx});
    moving = {slider, tumbler, dropped};
  }
};

Settings with_held_passes(int passes) {
  Settings settings;
  settings.held_velocity_iterations = passes;
  return settings;
}

}  // namespace

TEST_CASE("islands in motion keep their bits when held islands run fewer passes", "[held]") {
  // 10 held passes: every island at the world's 10, as before the rule.
  Scene held(with_held_passes(4)), every(with_held_passes(10));
  // The falling box and the tipping plank until they come down (steps
  // 1-45), the slider all the way down its ramp (its island moves
  // throughout: the comparison is exact at every step).
  for (int step = 0; step < 120; ++step) {
    held.t.world.step();
    every.t.world.step();
    for (const BodyId id : held.moving) {
      if (step >= 45 && id != held.slider) continue;
      const Body& a = held.t.body(id);
      const Body& b = every.t.body(id);
      INFO("step " << step + 1 << ", body " << id.index);
      REQUIRE(a.pose.position == b.pose.position);
      REQUIRE(a.pose.orientation == b.pose.orientation);
      REQUIRE(a.linear_velocity == b.linear_velocity);
      REQUIRE(a.angular_velocity == b.angular_velocity);
    }
  }
  CHECK(to_double(length(held.t.body(held.slider).linear_velocity)) > 1.0);
  // The rule was at work on the column (and only there): its rows ran the
  // held passes, and 10 held passes are the world's (nothing held).
  CHECK(held.t.world.held_manifold_rows() >= 5 * 100);
  CHECK(every.t.world.held_manifold_rows() == 0);
  // The column stands as it did at 10 passes: no box moved a micrometre.
  for (size_t i = 0; i < held.stack.size(); ++i) {
    const Vec3 start{Fixed{}, Fixed::from_ratio(2 * static_cast<int>(i) + 1, 4), Fixed{}};
    INFO("box " << i);
    CHECK(to_double(length(held.t.body(held.stack[i]).pose.position - start)) < 1e-6);
    CHECK(to_double(length(every.t.body(every.stack[i]).pose.position - start)) < 1e-6);
  }
}

TEST_CASE("held islands: no rule without the shock step, or at the world's passes", "[held]") {
  Settings no_shock = with_held_passes(4);
  no_shock.shock_propagation = false;
  Settings fewer_world_passes = with_held_passes(4);
  fewer_world_passes.velocity_iterations = 3;  // held passes beyond the world's: the world's
  for (const Settings& settings : {no_shock, fewer_world_passes}) {
    Scene scene(settings);
    scene.t.simulate_steps(60);
    CHECK(scene.t.world.held_manifold_rows() == 0);
  }
}
