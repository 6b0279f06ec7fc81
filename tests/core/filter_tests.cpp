// Collision filters (core/body.h CollisionFilter): bodies whose layers the
// other does not collide with make no contact and pass through each other,
// while both still rest on what they do collide with.
#include <catch2/catch.hpp>

#include "tests/core/test_world.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::TestWorld;
using bitstep::test::to_double;

namespace {

BodyId add_filtered_box(TestWorld& t, Vec3 position, CollisionFilter filter) {
  BodyDef def;
  def.pose.position = position;
  def.shapes.push_back({ShapeType::box, {0.5_fx, 0.5_fx, 0.5_fx}, {}, {}, {}});
  def.filter = filter;
  return t.world.create_body(def).value();
}

}  // namespace

TEST_CASE("a body that does not collide with the ground's layer falls through it as in free fall", "[filter]") {
  TestWorld t;
  t.add_ground();  // layer 0
  const BodyId ghost = add_filtered_box(t, {Fixed{}, 0.5_fx, Fixed{}}, {0b10, 0b10});  // layer 1, with layer 1 only
  TestWorld free;
  const BodyId alone = add_filtered_box(free, {Fixed{}, 0.5_fx, Fixed{}}, {});
  for (int step = 0; step < 60; ++step) {
    t.world.step();
    free.world.step();
    CHECK(t.world.contacts().empty());
    REQUIRE(t.world.body(ghost).pose.position == free.world.body(alone).pose.position);  // the same bits
  }
  CHECK(to_double(t.world.body(ghost).pose.position.y) < -4.0);
}

TEST_CASE("two bodies on layers the other ignores pass through each other and both rest on the ground",
          "[filter]") {
  TestWorld t;
  t.add_ground();
  const BodyId below = add_filtered_box(t, {Fixed{}, 0.5_fx, Fixed{}}, {0b10, 0b01});  // layer 1: ground only
  const BodyId above = add_filtered_box(t, {0.2_fx, 2.0_fx, Fixed{}}, {0b100, 0b01});  // layer 2: ground only
  t.simulate_steps(180);
  for (const Contact& c : t.world.contacts()) {
    CHECK_FALSE((c.key.body_a == below.index && c.key.body_b == above.index));
  }
  // Both stand on the ground, overlapping each other.
  CHECK(std::abs(to_double(t.world.body(below).pose.position.y) - 0.5) < 1e-3);
  CHECK(std::abs(to_double(t.world.body(above).pose.position.y) - 0.5) < 1e-3);
  // The same boxes without filters: the upper one stands on the lower.
  TestWorld plain;
  plain.add_ground();
  add_filtered_box(plain, {Fixed{}, 0.5_fx, Fixed{}}, {});
  const BodyId stacked = add_filtered_box(plain, {0.2_fx, 2.0_fx, Fixed{}}, {});
  plain.simulate_steps(180);
  CHECK(to_double(plain.world.body(stacked).pose.position.y) > 1.4);
}
