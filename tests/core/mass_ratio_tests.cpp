// Mass ratios: a light box caught between the ground and heavy
// ones is not pushed through and does not sink, under both pipelines (the
// shock step holds the light box up as immovable for the bodies above it).
#include <catch2/catch.hpp>

#include <algorithm>
#include <cmath>
#include <vector>

#include "tests/core/test_world.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::TestWorld;
using bitstep::test::to_double;

namespace {

BodyId add_cube(TestWorld& t, Vec3 position, Fixed mass) {
  BodyDef def;
  def.pose.position = position;
  def.mass = mass;
  def.shapes.push_back({ShapeType::box, {0.5_fx, 0.5_fx, 0.5_fx}, {}, {}, {}});
  return t.world.create_body(def).value();
}

// A 1 kg unit cube on the ground under `heavy` cubes of `heavy_mass` kg.
// Over 2 s: every gap between neighbours (and the light cube's height)
// stays within slop + 2 mm of touching, and the top cube moves less than
// 0.1 mm in the second second (no sinking).
void check_light_under_heavy(Pipeline pipeline, int heavy, Fixed heavy_mass) {
  Settings settings;
  settings.pipeline = pipeline;
  TestWorld t(settings);
  t.add_ground();
  std::vector<BodyId> column{add_cube(t, {Fixed{}, 0.5_fx, Fixed{}}, Fixed::one())};
  for (int i = 1; i <= heavy; ++i) column.push_back(add_cube(t, {Fixed{}, Fixed::from_int(i) + 0.5_fx, Fixed{}}, heavy_mass));
  const double allowed = to_double(settings.penetration_slop) + 0.002;
  double deepest = 0;
  double top_at_1s = 0;
  for (int step = 1; step <= 120; ++step) {
    t.world.step();
    deepest = std::max(deepest, 0.5 - to_double(t.body(column[0]).pose.position.y));
    for (size_t i = 1; i < column.size(); ++i) {
      const double gap = to_double(t.body(column[i]).pose.position.y - t.body(column[i - 1]).pose.position.y);
      deepest = std::max(deepest, 1.0 - gap);
    }
    if (step == 60) top_at_1s = to_double(t.body(column.back()).pose.position.y);
  }
  const double sink = top_at_1s - to_double(t.body(column.back()).pose.position.y);
  INFO("deepest overlap " << deepest * 1000 << " mm, top sank " << sink * 1000 << " mm in the second second");
  CHECK(deepest < allowed);
  CHECK(std::abs(sink) < 0.0001);
  WARN((pipeline == Pipeline::standard ? "standard" : "guendelman")
       << ": 1 kg under " << heavy << " x " << to_double(heavy_mass) << " kg: deepest " << deepest * 1000
       << " mm, sank " << sink * 1000 << " mm");
}

}  // namespace

TEST_CASE("a 1 kg box under a 1,000 kg box does not sink into the ground or the box", "[physics][mass-ratio]") {
  const Pipeline pipeline = GENERATE(Pipeline::standard, Pipeline::guendelman);
  check_light_under_heavy(pipeline, 1, 1000.0_fx);
}

TEST_CASE("a 1 kg box under a stack of ten 100 kg boxes does not sink", "[physics][mass-ratio]") {
  const Pipeline pipeline = GENERATE(Pipeline::standard, Pipeline::guendelman);
  check_light_under_heavy(pipeline, 10, 100.0_fx);
}

namespace {

// JigLib's car-and-wall case: a 1 kg unit cube on the ground
// against a static wall (its face at x = 0), a 2,000 kg 2 m box sliding at
// 5 m/s into it from 1 m away. Over 2 s: the cube never goes into the wall
// by more than slop + 5 mm, the heavy box never into the cube by more, and
// the heavy box ends at rest against the cube.
void check_pinned_against_wall(Pipeline pipeline, bool shock) {
  Settings settings;
  settings.pipeline = pipeline;
  settings.shock_propagation = shock;
  TestWorld t(settings);
  t.add_ground();
  BodyDef wall;
  wall.type = BodyType::static_body;
  wall.pose.position = {-0.5_fx, 3.0_fx, Fixed{}};
  wall.shapes.push_back({ShapeType::box, {0.5_fx, 3.0_fx, 5.0_fx}, {}, {}, {}});
  t.world.create_body(wall);
  const BodyId light = add_cube(t, {0.5_fx, 0.5_fx, Fixed{}}, Fixed::one());
  BodyDef car;
  car.pose.position = {3.0_fx, Fixed::one(), Fixed{}};
  car.mass = 2000.0_fx;
  car.linear_velocity = {-5.0_fx, Fixed{}, Fixed{}};
  car.shapes.push_back({ShapeType::box, {Fixed::one(), Fixed::one(), Fixed::one()}, {}, {}, {}});
  const BodyId heavy = t.world.create_body(car).value();
  const double allowed = to_double(settings.penetration_slop) + 0.005;
  double into_wall = 0, into_cube = 0;
  for (int step = 1; step <= 120; ++step) {
    t.world.step();
    const double cube_x = to_double(t.body(light).pose.position.x);
    into_wall = std::max(into_wall, 0.5 - cube_x);
    into_cube = std::max(into_cube, (cube_x + 1.5) - to_double(t.body(heavy).pose.position.x));
  }
  const double speed = to_double(length(t.body(heavy).linear_velocity));
  INFO("cube into the wall " << into_wall * 1000 << " mm, car into the cube " << into_cube * 1000
                             << " mm, car speed at 2 s " << speed << " m/s");
  CHECK(into_wall < allowed);
  CHECK(into_cube < allowed);
  CHECK(speed < 0.01);
  WARN((pipeline == Pipeline::standard ? "standard" : "guendelman")
       << (shock ? " + shock" : "") << ": car and wall: cube into wall " << into_wall * 1000 << " mm, car into cube "
       << into_cube * 1000 << " mm, car speed " << speed);
}

}  // namespace

TEST_CASE("a 1 kg box between a wall and a 2,000 kg box driven into it at 5 m/s is not pushed through",
          "[physics][mass-ratio]") {
  const Pipeline pipeline = GENERATE(Pipeline::standard, Pipeline::guendelman);
  check_pinned_against_wall(pipeline, true);
}
