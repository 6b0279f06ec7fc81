// Sensors and events (core/sensor.h): a sensor reports what enters and
// leaves it and pushes nothing; contacts report when they begin and end;
// each step's events come in a defined order and survive a snapshot.
#include <catch2/catch.hpp>

#include <vector>

#include "tests/core/test_world.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::TestWorld;
using bitstep::test::to_double;

namespace {

// A static sensor slab, 0.5 m thick, its middle at `height`.
BodyId add_zone(TestWorld& t, Fixed height, CollisionFilter filter = {}) {
  BodyDef def;
  def.type = BodyType::static_body;
  def.sensor = true;
  def.filter = filter;
  def.pose.position = {Fixed{}, height, Fixed{}};
  def.shapes.push_back({ShapeType::box, {2.0_fx, 0.25_fx, 2.0_fx}, {}, {}, {}});
  return t.world.create_body(def).value();
}

struct Logged {
  uint64_t step;
  WorldEvent event;
};

std::vector<Logged> run_logging(World& world, int steps) {
  world.set_events(true);
  std::vector<Logged> log;
  for (int i = 0; i < steps; ++i) {
    world.step();
    for (const WorldEvent& e : world.events()) log.push_back({world.step_count(), e});
  }
  return log;
}

}  // namespace

TEST_CASE("a box falls through a sensor as if it were not there, which reports it entering and leaving", "[sensor]") {
  TestWorld t;
  t.add_ground();
  const BodyId zone = add_zone(t, 1.25_fx);
  const BodyId box = t.add_box({Fixed{}, 3.0_fx, Fixed{}}, {0.25_fx, 0.25_fx, 0.25_fx});
  TestWorld plain;
  plain.add_ground();
  const BodyId same = plain.add_box({Fixed{}, 3.0_fx, Fixed{}}, {0.25_fx, 0.25_fx, 0.25_fx});
  std::vector<Logged> log;
  t.world.set_events(true);
  for (int i = 0; i < 120; ++i) {
    t.world.step();
    plain.world.step();
    REQUIRE(t.world.body(box).pose == plain.world.body(same).pose);  // the same bits: it pushes nothing
    for (const Contact& c : t.world.contacts()) CHECK((c.key.body_a != zone.index && c.key.body_b != zone.index));
    for (const WorldEvent& e : t.world.events()) log.push_back({t.world.step_count(), e});
  }
  // Enters, leaves, lands: in that order, each once.
  REQUIRE(log.size() == 3u);
  CHECK(log[0].event.kind == EventKind::sensor_begin);
  CHECK(log[1].event.kind == EventKind::sensor_end);
  CHECK(log[2].event.kind == EventKind::contact_begin);
  CHECK(log[0].event.key == ContactKey{zone.index, box.index, 0, 0});
  CHECK(log[1].event.key == ContactKey{zone.index, box.index, 0, 0});
  CHECK(log[2].event.key == ContactKey{0, box.index, 0, 0});
  // It entered when its bottom passed the slab's top (y 1.5): falling from
  // its bottom at 2.75, after sqrt(2 * 1.25 / 9.81) = 0.505 s, step 31.
  CHECK(log[0].step >= 30u);
  CHECK(log[0].step <= 32u);
  CHECK(log[1].step < log[2].step);
}

TEST_CASE("contact events: one begin when a box lands, one end when it is knocked off the ground", "[sensor]") {
  TestWorld t;
  t.add_ground();
  const BodyId box = t.add_box({Fixed{}, 1.0_fx, Fixed{}}, {0.5_fx, 0.5_fx, 0.5_fx});
  std::vector<Logged> log = run_logging(t.world, 60);
  REQUIRE(log.size() == 1u);
  CHECK(log[0].event.kind == EventKind::contact_begin);
  t.world.apply_impulse(box, {Fixed{}, 5000.0_fx, Fixed{}}, t.world.body(box).pose.position);  // 5 m/s up
  log = run_logging(t.world, 30);
  REQUIRE_FALSE(log.empty());
  CHECK(log[0].event.kind == EventKind::contact_end);
  CHECK(log[0].event.key == ContactKey{0, box.index, 0, 0});
}

TEST_CASE("a sensor respects collision filters and does not see other sensors", "[sensor][filter]") {
  TestWorld t;
  const BodyId zone = add_zone(t, 1.25_fx, {1, 0b10});  // sees layer 1 only
  BodyDef ghost;
  ghost.pose.position = {Fixed{}, 1.25_fx, Fixed{}};
  ghost.shapes.push_back({ShapeType::sphere, {}, 0.2_fx, {}, {}});
  t.world.create_body(ghost);        // layer 0: not seen
  ghost.filter = {0b10, UINT32_MAX};  // layer 1: seen
  const BodyId seen = t.world.create_body(ghost).value();
  ghost.sensor = true;               // a sensor on layer 1: sensors do not see sensors
  const BodyId other_sensor = t.world.create_body(ghost).value();
  t.world.step();
  std::vector<uint32_t> seen_by_zone, seen_by_other;
  for (const SensorOverlap& o : t.world.sensor_overlaps()) {
    if (o.key.body_a == zone.index) seen_by_zone.push_back(o.key.body_b);
    if (o.key.body_b == other_sensor.index) seen_by_other.push_back(o.key.body_a);
  }
  CHECK(seen_by_zone == std::vector<uint32_t>{seen.index});
  // The second sensor sees both spheres (its filter lets every layer in).
  CHECK(seen_by_other == std::vector<uint32_t>{seen.index - 1, seen.index});
}

TEST_CASE("a sleeping body stays inside a sensor without an end event", "[sensor][sleep]") {
  Settings settings;
  settings.sleep_method = SleepMethod::motion;
  TestWorld t(settings);
  t.add_ground();
  add_zone(t, 0.25_fx);  // from the ground up to 0.5 m
  t.add_box({Fixed{}, 0.25_fx, Fixed{}}, {0.25_fx, 0.25_fx, 0.25_fx});
  const std::vector<Logged> log = run_logging(t.world, 240);
  CHECK(t.world.stats().awake_bodies == 0);
  REQUIRE(log.size() == 2u);  // the contact and the overlap begin at step 1, and nothing ends
  CHECK(log[0].event.kind == EventKind::contact_begin);
  CHECK(log[1].event.kind == EventKind::sensor_begin);
  CHECK(t.world.sensor_overlaps().size() == 1u);
}
