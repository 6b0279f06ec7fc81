// Scenes that start in motion: a body released above a support
// falls and rests on it, not above it, in both pipelines, sleep on or off;
// a fast body meets a thin wall and neither stops short of it nor passes.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "core/manifold.h"
#include "tests/core/test_world.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::TestWorld;
using bitstep::test::to_double;

namespace {

Settings settings_for(Pipeline pipeline, SleepMethod sleep) {
  Settings settings;
  settings.pipeline = pipeline;
  settings.sleep_method = sleep;
  return settings;
}

const char* name_of(Pipeline p) { return p == Pipeline::guendelman ? "guendelman" : "standard"; }
const char* name_of(SleepMethod s) { return s == SleepMethod::off ? "sleep off" : "sleep motion"; }

}  // namespace

// A 0.5 m cube released 0.1 mm .. 5 cm above the ground, or above a 1 m cube
// resting on it: after 3 s its bottom face lies on the support, within
// touch_tolerance above it and no deeper than the slop into it. Before
// touching meant touching (2026-11-23) it hovered at 0.1, 1 and 3 mm (the
// shock step glued contacts within the 5 mm slop) and, under guendelman,
// up to 7 mm (g dt^2 read as overlap).
TEST_CASE("a box released above a support falls and rests on it, not above it", "[motion]") {
  const double tolerance = to_double(touch_tolerance);
  for (Pipeline pipeline : {Pipeline::standard, Pipeline::guendelman}) {
    for (SleepMethod sleep : {SleepMethod::off, SleepMethod::motion}) {
      for (bool onto_box : {false, true}) {
        for (Fixed height : {0.0001_fx, 0.001_fx, 0.003_fx, 0.01_fx, 0.05_fx}) {
          const Settings settings = settings_for(pipeline, sleep);
          TestWorld t(settings);
          t.add_ground();
          Fixed support_top;
          if (onto_box) {
            t.add_box({Fixed{}, 0.5_fx, Fixed{}}, {0.5_fx, 0.5_fx, 0.5_fx});
            support_top = 1.0_fx;
          }
          const BodyId box = t.add_box({Fixed{}, support_top + 0.25_fx + height, Fixed{}}, {0.25_fx, 0.25_fx, 0.25_fx});
          t.simulate(3.0_fx);
          const double gap = to_double(t.body(box).pose.position.y - 0.25_fx - support_top);
          INFO(name_of(pipeline) << ", " << name_of(sleep) << (onto_box ? ", onto a box" : ", onto the ground")
                                 << ", released " << to_double(height) * 1000 << " mm up: rests " << gap * 1000
                                 << " mm above its support");
          CHECK(gap <= tolerance);
          CHECK(gap >= -to_double(settings.penetration_slop));
          // What run reports as penetration is a real overlap: none here.
          CHECK(to_double(t.world.stats().max_penetration) <= to_double(settings.penetration_slop));
          if (sleep != SleepMethod::off) CHECK(t.body(box).asleep);
        }
      }
    }
  }
}

// A body of the envelope's smallest size (0.01 m half-size, 0.1 kg) thrown
// at 20, 100 and 500 m/s (the envelope's top speed) at a static wall of the
// smallest thickness (0.02 m), no gravity: it never crosses the wall's front
// face and it reaches it. Before the guendelman pipeline found contacts at
// real depths (2026-11-23) it stopped the body 0.3-3.3 m short, or at
// 500 m/s let it pass through.
TEST_CASE("a fast small body meets a thin wall: it neither passes through nor stops short", "[motion]") {
  for (Pipeline pipeline : {Pipeline::standard, Pipeline::guendelman}) {
    for (ShapeType type : {ShapeType::box, ShapeType::sphere, ShapeType::capsule, ShapeType::hull}) {
      for (Fixed speed : {20.0_fx, 100.0_fx, 500.0_fx}) {
        Settings settings = settings_for(pipeline, SleepMethod::off);
        settings.gravity = Vec3{};
        TestWorld t(settings);
        BodyDef wall;
        wall.type = BodyType::static_body;
        wall.pose.position = {10.0_fx, Fixed{}, Fixed{}};
        // The hull meets a hull wall: the generic path on both sides.
        const Vec3 wall_half{0.01_fx, 5.0_fx, 5.0_fx};
        wall.shapes.push_back(type == ShapeType::hull ? test::box_hull(wall_half)
                                                      : Shape{ShapeType::box, wall_half, {}, {}, {}});
        t.world.create_body(wall);
        BodyDef body;
        const Vec3 half{0.01_fx, 0.01_fx, 0.01_fx};
        body.shapes.push_back(type == ShapeType::hull ? test::box_hull(half) : Shape{type, half, 0.01_fx, 0.01_fx, {}});
        body.mass = 0.1_fx;
        body.linear_velocity = {speed, Fixed{}, Fixed{}};
        const BodyId id = t.world.create_body(body).value();
        REQUIRE(id.valid());
        const double front = 9.99 - 0.01;  // the wall's front face less the body's half-size
        double farthest = -1e9;
        for (int step = 0; step < 120; ++step) {
          t.world.step();
          farthest = std::max(farthest, to_double(t.body(id).pose.position.x));
        }
        INFO(name_of(pipeline) << ", shape " << static_cast<int>(type) << " at " << to_double(speed)
                               << " m/s: farthest " << farthest << ", front " << front);
        CHECK(farthest <= front + 0.0001);
        CHECK(farthest >= front - 0.0001);
        CHECK(std::abs(to_double(t.body(id).linear_velocity.x)) < 0.001);
      }
    }
  }
}

// Thrown with gravity onto the ground at a grazing angle, then sliding into a
// thin wall standing on it: the same, with the landing and friction in it.
TEST_CASE("a cube thrown down at 100 m/s lands on the ground and stops at a thin wall", "[motion]") {
  for (Pipeline pipeline : {Pipeline::standard, Pipeline::guendelman}) {
    TestWorld t(settings_for(pipeline, SleepMethod::off));
    t.add_ground();
    BodyDef wall;
    wall.type = BodyType::static_body;
    wall.pose.position = {20.0_fx, 1.0_fx, Fixed{}};
    wall.shapes.push_back({ShapeType::box, {0.01_fx, 1.0_fx, 5.0_fx}, {}, {}, {}});
    t.world.create_body(wall);
    BodyDef body;
    body.pose.position = {Fixed{}, 2.0_fx, Fixed{}};
    body.shapes.push_back({ShapeType::box, {0.05_fx, 0.05_fx, 0.05_fx}, {}, {}, {}});
    body.linear_velocity = {100.0_fx, -20.0_fx, Fixed{}};
    const BodyId id = t.world.create_body(body).value();
    double lowest = 1e9, farthest = -1e9;
    for (int step = 0; step < 180; ++step) {
      t.world.step();
      lowest = std::min(lowest, to_double(t.body(id).pose.position.y));
      farthest = std::max(farthest, to_double(t.body(id).pose.position.x));
    }
    INFO(name_of(pipeline) << ": lowest centre " << lowest << ", farthest " << farthest);
    CHECK(lowest >= 0.05 - to_double(t.world.settings().penetration_slop) - 0.001);
    CHECK(farthest <= 19.99 - 0.05 + 0.0001);
  }
}

// A 2 m plank spinning about its centre 0.9 m above the ground (no gravity):
// its tips sweep down to y = -0.1 at w r, far faster than its centre moves
// (which is not at all). Contacts are kept for the turn too, so the tips
// meet the ground in the step they reach it. Kept for the centre's motion
// only, they went 38 mm (10 rad/s) to 100 mm (30 rad/s) deep.
TEST_CASE("a fast-spinning plank's tips meet the ground instead of sweeping into it", "[motion]") {
  for (Pipeline pipeline : {Pipeline::standard, Pipeline::guendelman}) {
    for (Fixed spin : {10.0_fx, 30.0_fx, 100.0_fx}) {
      Settings settings = settings_for(pipeline, SleepMethod::off);
      settings.gravity = Vec3{};
      TestWorld t(settings);
      t.add_ground();
      BodyDef plank;
      plank.pose.position = {Fixed{}, 0.9_fx, Fixed{}};
      plank.shapes.push_back({ShapeType::box, {1.0_fx, 0.05_fx, 0.25_fx}, {}, {}, {}});
      plank.angular_velocity = {Fixed{}, Fixed{}, spin};
      const BodyId id = t.world.create_body(plank).value();
      double deepest = 0;
      for (int step = 0; step < 60; ++step) {
        t.world.step();
        const Pose pose = t.body(id).pose;
        for (int c = 0; c < 8; ++c) {
          const Vec3 corner{(c & 1) ? 1.0_fx : -1.0_fx, (c & 2) ? 0.05_fx : -0.05_fx, (c & 4) ? 0.25_fx : -0.25_fx};
          deepest = std::max(deepest, -to_double(pose.apply(corner).y));
        }
      }
      INFO(name_of(pipeline) << " at " << to_double(spin) << " rad/s: deepest corner " << deepest << " m");
      CHECK(deepest < 0.0001);
    }
  }
}
