// Shipped scenes run in the world, with their stability asserted in numbers.
// Long runs: tagged [slow], Release only. pyramid20 (1.2 cm drift in 20 s)
// and stack20 do not meet issue 3's bars yet and are not asserted here.
#include <catch2/catch.hpp>

#include <cmath>
#include <string>
#include <variant>

#include "core/world.h"
#include "replay/scene.h"
#include "tests/test_support.h"

using namespace bitstep;

namespace {

using bitstep::test::to_double;

World load_world(const std::string& name) {
  auto loaded = load_scene_file(std::string(BITSTEP_SOURCE_DIR) + "/scenes/" + name);
  REQUIRE(std::holds_alternative<Scene>(loaded));
  const Scene& scene = std::get<Scene>(loaded);
  World world(scene.settings);
  for (const SceneBody& body : scene.bodies) REQUIRE(world.create_body(body.def).ok());
  return world;
}

struct Motion {
  double largest_move = 0;  // m, of any dynamic body from its start
  double largest_drift = 0; // m, the horizontal part
  double deepest = 0;       // m, deepest contact over the run
};

Motion run(World& world, int steps) {
  std::vector<Vec3> start;
  for (const Body& b : world.bodies()) start.push_back(b.pose.position);
  Motion m;
  for (int i = 0; i < steps; ++i) {
    world.step();
    m.deepest = std::max(m.deepest, to_double(world.stats().max_penetration));
  }
  for (size_t i = 0; i < start.size(); ++i) {
    if (world.bodies()[i].type != BodyType::dynamic) continue;
    const Vec3 d = world.bodies()[i].pose.position - start[i];
    m.largest_move = std::max(m.largest_move, std::sqrt(to_double(length_sq(d))));
    m.largest_drift = std::max(m.largest_drift, std::hypot(to_double(d.x), to_double(d.z)));
  }
  return m;
}

}  // namespace

// "Stands": no box drifts sideways by 1 cm. Vertically the rows settle into
// their contacts (each interface may sink up to the penetration slop).
TEST_CASE("pyramid20 stands 20 s at 10 iterations: no box drifts 1 cm", "[scene-run][slow]") {
  World world = load_world("pyramid20.json");
  const Motion m = run(world, 1200);
  INFO("largest drift " << m.largest_drift << " m, largest move " << m.largest_move << " m, deepest contact "
                        << m.deepest << " m");
  const double slop = to_double(world.settings().penetration_slop);
  WARN("pyramid20: drift " << m.largest_drift << " m, move " << m.largest_move << " m, deepest " << m.deepest);
  CHECK(m.largest_drift < 0.01);
  CHECK(m.largest_move < 20 * slop);
  CHECK(m.deepest < slop + 0.001);
}

TEST_CASE("tables: five stacked compound tables stand 20 s with drift under 1 cm", "[scene-run][slow]") {
  World world = load_world("tables.json");
  const Motion m = run(world, 1200);
  INFO("largest drift " << m.largest_drift << " m, largest move " << m.largest_move << " m");
  CHECK(m.largest_drift < 0.01);
}

// In the checked build any overflow, saturation or division by zero aborts
// the run; in every build the bodies must stay inside the world envelope.
// wall128 (8,256 boxes) runs 10 steps in unoptimised builds, 120 otherwise.
TEST_CASE("every shipped scene runs 2 s inside the envelope without an overflow", "[scene-run]") {
  for (const char* name : {"bounce.json", "stack20.json", "stack50.json", "pyramid20.json", "wall128.json", "jenga.json",
                           "dominoes.json", "tables.json", "thrown.json", "incline.json", "slide_stop.json",
                           "spheres.json", "playground.json"}) {
    INFO(name);
    World world = load_world(name);
#if defined(NDEBUG)
    const int steps = 120;
#else
    const int steps = world.bodies().size() > 1000 ? 10 : 120;
#endif
    for (int i = 0; i < steps; ++i) world.step();
    for (const Body& body : world.bodies()) {
      const Vec3 p = body.pose.position;
      REQUIRE(max(abs(p.x), max(abs(p.y), abs(p.z))) <= envelope::max_position);
    }
  }
}
