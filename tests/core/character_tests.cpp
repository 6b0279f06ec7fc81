// The character controller (core/character.h) in motion: walking, steps,
// slopes, jumps, walls, platforms that move and turn, pushes, against the
// analytic answers.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>

#include "core/character.h"
#include "tests/core/test_world.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::TestWorld;
using bitstep::test::to_double;

namespace {

// A character 1.8 m tall (radius 0.3, half height 0.6) standing on y = 0.
CharacterId add_character(TestWorld& t, Vec3 feet, CharacterDef def = {}) {
  def.position = {feet.x, feet.y + def.radius + def.half_height + 0.01_fx, feet.z};
  return t.world.create_character(def).value();
}

const Character& character(const TestWorld& t, CharacterId id) { return t.world.characters()[id.index]; }

void walk(TestWorld& t, CharacterId id, Vec3 velocity, int steps, bool jump = false) {
  t.world.set_character_controls(id, {velocity, jump});
  for (int i = 0; i < steps; ++i) t.world.step();
}

double feet_y(const TestWorld& t, CharacterId id) {
  const Character& c = character(t, id);
  return to_double(c.position.y - c.def.radius - c.def.half_height);
}

// A static box from `low` to `high`.
void add_block(TestWorld& t, Vec3 low, Vec3 high) {
  BodyDef def;
  def.type = BodyType::static_body;
  def.pose.position = (low + high) * 0.5_fx;
  def.shapes.push_back({ShapeType::box, (high - low) * 0.5_fx, {}, {}, {}});
  t.world.create_body(def);
}

struct RampAxes {
  Vec3 along, up;  // down the ramp's length, out of its face
};

// A ramp rising along +x from x = 2 at `degrees`: a 10 x 1 x 6 m box turned
// about z, its top face through (2, 0, 0).
RampAxes add_ramp(TestWorld& t, Fixed degrees) {
  const Quat tilt = test::about_degrees({Fixed{}, Fixed{}, Fixed::one()}, degrees);
  const RampAxes axes{rotate(tilt, {Fixed::one(), Fixed{}, Fixed{}}), rotate(tilt, {Fixed{}, Fixed::one(), Fixed{}})};
  BodyDef ramp;
  ramp.type = BodyType::static_body;
  ramp.pose = {Vec3{2.0_fx, Fixed{}, Fixed{}} + axes.along * 5.0_fx - axes.up * 0.5_fx, tilt};
  ramp.shapes.push_back({ShapeType::box, {5.0_fx, 0.5_fx, 3.0_fx}, {}, {}, {}});
  t.world.create_body(ramp);
  return axes;
}

}  // namespace

TEST_CASE("Character: walks on flat ground at the asked speed and stays on it", "[character][motion]") {
  TestWorld t;
  t.add_ground();
  const CharacterId id = add_character(t, {});
  walk(t, id, {2.0_fx, Fixed{}, -1.0_fx}, 120);
  const Character& c = character(t, id);
  INFO("at " << to_double(c.position.x) << ", " << to_double(c.position.z) << ", feet " << feet_y(t, id));
  // Standing from its first step (created on the ground), it walks all 2 s.
  CHECK(std::abs(to_double(c.position.x) - 4.0) < 0.001);
  CHECK(std::abs(to_double(c.position.z) + 2.0) < 0.001);
  CHECK(std::abs(feet_y(t, id) - 0.01) < 0.011);
  CHECK(c.ground == GroundState::on_ground);
  CHECK(c.velocity.y == Fixed{});
}

TEST_CASE("Character: climbs steps up to its step height, not higher, and walks down them", "[character][motion]") {
  for (const Fixed rise : {0.2_fx, 0.25_fx, 0.4_fx}) {
    TestWorld t;
    t.add_ground();
    // Five steps 0.5 m deep from x = 1, each `rise` higher, then a landing.
    for (int k = 0; k < 5; ++k) {
      const Fixed x0 = Fixed::one() + 0.5_fx * Fixed::from_int(k);
      add_block(t, {x0, Fixed{}, -2.0_fx}, {x0 + 0.5_fx, rise * Fixed::from_int(k + 1), 2.0_fx});
    }
    add_block(t, {3.5_fx, Fixed{}, -2.0_fx}, {8.0_fx, rise * Fixed::from_int(5), 2.0_fx});
    CharacterDef def;
    def.step_height = 0.3_fx;
    const CharacterId id = add_character(t, {}, def);
    walk(t, id, {1.5_fx, Fixed{}, Fixed{}}, 180);
    const double top = 5 * to_double(rise);
    INFO("rise " << to_double(rise) << ": at x " << to_double(character(t, id).position.x) << ", feet at "
                 << feet_y(t, id) << " (top " << top << ")");
    if (rise <= def.step_height) {
      // Stairs do not slow the walk: 1.5 m/s for 3 s is 4.5 m (a step's
      // edge slid over under the round bottom once cost 4%).
      CHECK(to_double(character(t, id).position.x) > 4.5 * 0.995);
      CHECK(std::abs(feet_y(t, id) - top) < 0.03);
      CHECK(character(t, id).ground == GroundState::on_ground);
      // Back down: it follows the steps, never more than a step in the air.
      t.world.set_character_controls(id, {{-1.5_fx, Fixed{}, Fixed{}}, false});
      int airborne = 0;
      for (int i = 0; i < 180; ++i) {
        t.world.step();
        if (character(t, id).ground == GroundState::in_air) ++airborne;
      }
      INFO("down: feet at " << feet_y(t, id) << ", " << airborne << " steps in the air");
      CHECK(std::abs(feet_y(t, id)) < 0.03);
      CHECK(airborne <= 2);
    } else {
      // Stopped at the first step's face (x = 1 less its radius and skin).
      CHECK(to_double(character(t, id).position.x) < 1.0 - 0.3 + 0.001);
      CHECK(to_double(character(t, id).position.x) > 1.0 - 0.3 - 0.02);
      CHECK(std::abs(feet_y(t, id)) < 0.03);
    }
  }
}

TEST_CASE("Character: walks up a slope below its limit and stops below a steeper one", "[character][motion]") {
  for (const Fixed degrees : {30.0_fx, 60.0_fx}) {
    TestWorld t;
    t.add_ground();
    add_ramp(t, degrees);
    const CharacterId id = add_character(t, {});
    walk(t, id, {2.0_fx, Fixed{}, Fixed{}}, 150);
    const Character& c = character(t, id);
    INFO(to_double(degrees) << " degrees: at x " << to_double(c.position.x) << ", feet " << feet_y(t, id) << ", ground "
                            << ground_state_names[static_cast<size_t>(c.ground)]);
    if (degrees < 45.0_fx) {
      // 2.5 s at 2 m/s: 2 m to the ramp, then up it (its level speed less there).
      CHECK(feet_y(t, id) > 1.0);
      CHECK(c.ground == GroundState::on_ground);
    } else {
      CHECK(feet_y(t, id) < 0.2);
      CHECK(to_double(c.position.x) < 2.0);
      CHECK(c.ground == GroundState::on_ground);
    }
  }
}

TEST_CASE("Character: jumps as high as v^2 / 2g and lands on its feet", "[character][motion]") {
  TestWorld t;
  t.add_ground();
  const CharacterId id = add_character(t, {});
  const double start = feet_y(t, id);
  t.world.step();  // finds the ground
  REQUIRE(character(t, id).ground == GroundState::on_ground);
  t.world.set_character_controls(id, {{Fixed{}, Fixed{}, Fixed{}}, true});
  t.world.step();
  t.world.set_character_controls(id, {});
  double peak = 0;
  int airborne = 1;
  while (character(t, id).ground != GroundState::on_ground && airborne < 200) {
    t.world.step();
    peak = std::max(peak, feet_y(t, id) - start);
    ++airborne;
  }
  // 5 m/s: v^2 / 2g = 1.2742 m. The jump step moves at 5 m/s, then each
  // step first adds g dt: the feet rise dt sum_k (v - k g dt), which peaks
  // at 1.3160 m (k = 0..30), 3% above the continuous answer; 2 v / g =
  // 1.019 s (61 steps) up and down.
  INFO("peak " << peak << " m, " << airborne << " steps off the ground");
  CHECK(std::abs(peak - 1.3160) < 0.005);
  CHECK(std::abs(peak - 1.2742) < 0.05);
  CHECK(std::abs(airborne - 61) <= 2);
  CHECK(std::abs(feet_y(t, id) - start) < 0.011);
}

TEST_CASE("Character: slides along a wall with the part of its velocity along it", "[character][motion]") {
  TestWorld t;
  t.add_ground();
  add_block(t, {1.0_fx, Fixed{}, -10.0_fx}, {1.5_fx, 3.0_fx, 10.0_fx});
  const CharacterId id = add_character(t, {});
  // 2 m/s at 45 degrees into the wall (x = 1): along it at 1.414 m/s.
  walk(t, id, {1.41421_fx, Fixed{}, 1.41421_fx}, 120);
  const Character& c = character(t, id);
  INFO("at " << to_double(c.position.x) << ", " << to_double(c.position.z));
  CHECK(to_double(c.position.x) < 1.0 - 0.3);
  CHECK(to_double(c.position.x) > 1.0 - 0.3 - 0.02);
  // 0.7 m to the wall at 1.41 m/s across (0.5 s), then 1.5 s along: z ~ 2.83.
  CHECK(std::abs(to_double(c.position.z) - 2.828) < 0.05);
}

TEST_CASE("Character: stands on a platform that moves and turns, and turns with it", "[character][motion]") {
  TestWorld t;
  t.add_ground();
  BodyDef platform;
  platform.type = BodyType::kinematic;
  platform.pose.position = {Fixed{}, 1.0_fx, Fixed{}};
  platform.shapes.push_back({ShapeType::box, {3.0_fx, 0.2_fx, 3.0_fx}, {}, {}, {}});
  platform.linear_velocity = {1.0_fx, Fixed{}, 0.5_fx};
  platform.angular_velocity = {Fixed{}, 0.5_fx, Fixed{}};
  const BodyId deck = t.world.create_body(platform).value();
  const CharacterId id = add_character(t, {1.5_fx, 1.2_fx, Fixed{}});
  t.world.step();
  REQUIRE(character(t, id).ground == GroundState::on_ground);
  const auto in_deck = [&] {
    const Pose& p = t.world.body(deck).pose;
    return rotate_inverse(p.orientation, character(t, id).position - p.position);
  };
  const Vec3 start = in_deck();
  const Vec3 facing_in_deck = rotate_inverse(t.world.body(deck).pose.orientation, character(t, id).facing);
  for (int i = 0; i < 240; ++i) t.world.step();  // 4 s: 2 rad turned, 4.5 m carried
  const Vec3 end = in_deck();
  const Vec3 facing_end = rotate_inverse(t.world.body(deck).pose.orientation, character(t, id).facing);
  INFO("on the deck from (" << to_double(start.x) << ", " << to_double(start.z) << ") to (" << to_double(end.x) << ", "
                            << to_double(end.z) << ")");
  CHECK(to_double(length(end - start)) < 0.01);
  CHECK(to_double(length(facing_end - facing_in_deck)) < 0.001);
  CHECK(character(t, id).ground == GroundState::on_ground);
  CHECK(character(t, id).ground_body == deck);
}

TEST_CASE("Character: pushes a crate with a bounded force", "[character][motion]") {
  TestWorld t;
  t.add_ground(Material{0.3_fx, 0.3_fx, Fixed{}, Fixed{}});
  BodyDef crate;
  crate.pose.position = {1.5_fx, 0.5_fx, Fixed{}};
  crate.shapes.push_back({ShapeType::box, {0.5_fx, 0.5_fx, 0.5_fx}, {}, {}, {}});
  crate.mass = 50.0_fx;
  crate.material = {0.3_fx, 0.3_fx, Fixed{}, Fixed{}};
  const BodyId box = t.world.create_body(crate).value();
  CharacterDef def;
  def.max_push_force = 300.0_fx;
  const CharacterId id = add_character(t, {}, def);
  t.world.set_character_controls(id, {{2.0_fx, Fixed{}, Fixed{}}, false});
  double fastest_gain = 0, last = 0;
  for (int i = 0; i < 180; ++i) {
    t.world.step();
    const double v = to_double(t.world.body(box).linear_velocity.x);
    fastest_gain = std::max(fastest_gain, v - last);
    last = v;
  }
  // At most 300 N on 50 kg: 6 m/s^2, 0.1 m/s a step (friction takes 2.94 m/s^2 of it).
  const double moved = to_double(t.world.body(box).pose.position.x) - 1.5;
  INFO("crate moved " << moved << " m, fastest gain a step " << fastest_gain << " m/s");
  CHECK(fastest_gain <= 300.0 / 50 / 60 + 1e-6);
  CHECK(moved > 1.0);
  // The character follows it, never inside it.
  CHECK(to_double(character(t, id).position.x) < to_double(t.world.body(box).pose.position.x) - 0.5 - 0.3 + 0.001);
}

TEST_CASE("Character: on a slope steeper than its limit it slides down, and never tunnels a thin wall",
          "[character][motion]") {
  TestWorld t;
  t.add_ground();
  const auto [along, up] = add_ramp(t, 60.0_fx);
  // Dropped onto the 60-degree face 2 m up it.
  const Vec3 on_face = Vec3{2.0_fx, Fixed{}, Fixed{}} + along * 2.5_fx + up * 0.95_fx;
  CharacterDef def;
  def.position = on_face;
  const CharacterId id = t.world.create_character(def).value();
  bool steep = false;
  for (int i = 0; i < 120; ++i) {
    t.world.step();
    steep = steep || character(t, id).ground == GroundState::on_steep_slope;
  }
  INFO("feet at " << feet_y(t, id) << ", x " << to_double(character(t, id).position.x));
  CHECK(steep);
  CHECK(feet_y(t, id) < 0.05);  // slid down to the floor
  CHECK(character(t, id).ground == GroundState::on_ground);

  // 5 cm wall, asked 100 m/s: stops at its face.
  TestWorld w;
  w.add_ground();
  add_block(w, {3.0_fx, Fixed{}, -5.0_fx}, {3.05_fx, 3.0_fx, 5.0_fx});
  const CharacterId runner = add_character(w, {});
  walk(w, runner, {100.0_fx, Fixed{}, Fixed{}}, 60);
  CHECK(to_double(character(w, runner).position.x) < 3.0 - 0.3);
}
