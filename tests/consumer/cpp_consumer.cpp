// A game's loop around bitstep: a scene, a fixed 60 Hz tick, an input that
// every peer applies before the same tick, the poses to draw between ticks,
// and the state hash of the replays. Run on scenes/pyramid20.json it ends with the
// hash of scenes/pyramid20.short.replay.json (tools/test.sh checks).
#include <cinttypes>
#include <cstdio>
#include <optional>
#include <string>

#include "replay/render_pose.h"
#include "replay/simulation.h"

int main(int argc, char** argv) {
  if (argc != 2) {
    std::fprintf(stderr, "usage: cpp_consumer SCENE.json\n");
    return 2;
  }
  bitstep::Result<bitstep::Simulation> sim = bitstep::Simulation::from_file(argv[1]);
  if (!sim.ok()) {
    std::fprintf(stderr, "%s\n", sim.error().message().c_str());  // "<file>: <JSON path>: <reason>"
    return 1;
  }
  const char* ball_json = R"({"name": "ball", "position": [-8, 3, 0], "velocity": [15, 3, 0],
      "shapes": [{"type": "sphere", "radius": 0.5}], "density": 3000})";
  bitstep::RenderPose previous{}, current{};
  for (int tick = 1; tick <= 20; ++tick) {
    if (tick == 10) {  // an input, before tick 10
      if (const bitstep::Result<bitstep::BodyId> ball = sim->add_body(ball_json); !ball.ok()) {
        std::fprintf(stderr, "%s\n", ball.error().message().c_str());
        return 1;
      }
    }
    sim->step();
    if (const std::optional<bitstep::BodyId> ball = sim->find_body("ball")) {
      previous = tick == 10 ? bitstep::render_pose(*sim->pose(*ball)) : current;
      current = bitstep::render_pose(*sim->pose(*ball));
      // A 144 Hz display draws frames between ticks: here a third of the way.
      const bitstep::RenderPose drawn = bitstep::interpolate(previous, current, 1.0f / 3);
      std::printf("tick %d ball drawn at x %.3f y %.3f\n", tick, static_cast<double>(drawn.position[0]),
                  static_cast<double>(drawn.position[1]));
    }
  }
  std::printf("tick %" PRIu64 " hash %016" PRIx64 "\n", sim->tick(), sim->hash());
  return 0;
}
