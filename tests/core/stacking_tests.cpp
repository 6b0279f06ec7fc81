// Stability of resting stacks. Long runs: tagged [slow], run in Release.
// At 60 Hz and 10 iterations a 20-cube column topples Jolt, Bullet and qu3e
// within 7 s and a 50-cube column all three even at 80 iterations; bitstep's
// shock step (solver.cpp, shock.cpp) holds both.
#include <catch2/catch.hpp>

#include <cmath>

#include "tests/core/test_world.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::TestWorld;

namespace {

using bitstep::test::to_double;

struct Drift {
  double horizontal = 0;   // m, largest horizontal displacement of any box
  double penetration = 0;  // m, deepest contact seen
};

// Runs `steps` and tracks the boxes' horizontal drift from their start and
// the deepest contact.
Drift run_and_measure(TestWorld& t, const std::vector<BodyId>& boxes, int steps) {
  std::vector<Vec3> start;
  for (BodyId id : boxes) start.push_back(t.body(id).pose.position);
  Drift d;
  for (int i = 0; i < steps; ++i) {
    t.world.step();
    d.penetration = std::max(d.penetration, to_double(t.world.stats().max_penetration));
  }
  for (size_t i = 0; i < boxes.size(); ++i) {
    const Vec3 p = t.body(boxes[i]).pose.position;
    const double dx = to_double(p.x - start[i].x), dz = to_double(p.z - start[i].z);
    d.horizontal = std::max(d.horizontal, std::sqrt(dx * dx + dz * dz));
  }
  return d;
}

std::vector<BodyId> add_stack(TestWorld& t, int count) {
  std::vector<BodyId> boxes;
  for (int i = 0; i < count; ++i) {
    const Fixed y = Fixed::from_int(i) + 0.5_fx;  // unit cubes exactly touching
    boxes.push_back(t.add_box({Fixed{}, y, Fixed{}}, {0.5_fx, 0.5_fx, 0.5_fx}));
  }
  return boxes;
}

// A column of `count` unit cubes stands `steps` steps: every box within
// `drift` (m) of where it started, every contact within the slop plus
// `extra_depth` (m), the top still at its height.
void check_column_stands(int count, int steps, double drift, double extra_depth) {
  TestWorld t;
  t.add_ground();
  const std::vector<BodyId> boxes = add_stack(t, count);
  const Drift d = run_and_measure(t, boxes, steps);
  const double top_y = to_double(t.body(boxes.back()).pose.position.y);
  INFO(count << " cubes: drift " << d.horizontal << " m, penetration " << d.penetration << " m, top at " << top_y
             << " m");
  CHECK(d.horizontal < drift);
  const double allowed_depth = to_double(t.world.settings().penetration_slop) + extra_depth;
  CHECK(d.penetration < allowed_depth);
  CHECK(top_y > count - 0.5 - count * allowed_depth);
}

}  // namespace

TEST_CASE("a cube resting on the ground stays put", "[physics][stacking]") {
  TestWorld t;
  t.add_ground();
  const std::vector<BodyId> box = add_stack(t, 1);
  const Drift d = run_and_measure(t, box, 120);
  INFO("drift " << d.horizontal << " m, penetration " << d.penetration << " m");
  CHECK(d.horizontal < 1e-4);
  CHECK(d.penetration < to_double(t.world.settings().penetration_slop) + 0.001);
  CHECK(std::abs(to_double(t.body(box[0]).pose.position.y) - 0.5) < 0.01);
}

TEST_CASE("a 20-cube stack stands 10 s at 60 Hz and 10 iterations", "[physics][stacking][slow]") {
  check_column_stands(20, 600, 0.01, 0.001);
}

TEST_CASE("a 50-cube stack stands 30 s at 60 Hz and 10 iterations", "[physics][stacking][slow]") {
  check_column_stands(50, 1800, 0.02, 0.002);
}

TEST_CASE("the shock step does not make a stack rigid: remove a middle box and the ones above fall",
          "[physics][stacking]") {
  TestWorld t;
  t.add_ground();
  const std::vector<BodyId> boxes = add_stack(t, 10);
  t.simulate_steps(60);
  const double top_before = to_double(t.body(boxes[9]).pose.position.y);
  REQUIRE(t.world.remove_body(boxes[4]));
  // Free fall for 1 m takes sqrt(2 / 9.81) = 0.45 s; after 1 s the boxes
  // above the gap rest one box lower (within the slop of each of the nine
  // contacts below them), and the ones below the gap stay.
  t.simulate_steps(60);
  const double top_after = to_double(t.body(boxes[9]).pose.position.y);
  const double slop = to_double(t.world.settings().penetration_slop);
  INFO("top box from " << top_before << " m to " << top_after << " m");
  CHECK(std::abs(top_after - (top_before - 1.0)) < 9 * slop);
  CHECK(to_double(t.body(boxes[5]).pose.position.y) < 4.5 + 5 * slop);
  CHECK(std::abs(to_double(t.body(boxes[3]).pose.position.y) - 3.5) < 4 * slop);
  CHECK(to_double(length(t.body(boxes[9]).linear_velocity)) < 0.05);
}
