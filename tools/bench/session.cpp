// `bitstep bench session`: the cost of running a game through a Session.
//
// Method. Each world is built from a scene (the shipped ones, and pyramids
// of unit cubes with 10 to 140 along the base: 55 to 9,870 bodies), stepped
// 60 times (every contact found), then timed over T ticks three ways with
// std::chrono::steady_clock, best of the samples: the world's step alone; a
// one-player lockstep session (a checksum, the state hash, every tick); a
// one-player rollback session (the same, and the tick's rollback state
// saved into its ring). The session's overhead is the difference per tick.
// A lockstep game sustains a world whose tick fits in the frame (16.7 ms at
// 60 Hz, 50 ms at 20 Hz); a rollback game must also afford the worst case
// of a rollback every frame: restoring a state and simulating its 8
// predicted ticks again, so 9 ticks and a restore per frame.
#include "tools/bench/session.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <stdexcept>
#include <cstring>
#include <string>
#include <vector>

#include "replay/rollback_state.h"
#include "replay/session.h"
#include "tools/exit_codes.h"

namespace bitstep {

namespace {

using Clock = std::chrono::steady_clock;

struct Costs {
  size_t bodies = 0;
  double step_ms = 0, lockstep_ms = 0, rollback_ms = 0, restore_ms = 0;
};

double best_ms_per_tick(int samples, int ticks, const auto& tick) {
  double best = 1e300;
  for (int s = 0; s < samples; ++s) {
    const auto start = Clock::now();
    for (int t = 0; t < ticks; ++t) tick();
    best = std::min(best, std::chrono::duration<double, std::milli>(Clock::now() - start).count() / ticks);
  }
  return best;
}

Simulation settled(const std::string& scene_json, const std::string& name) {
  std::string error;
  auto sim = Simulation::from_text(scene_json, name, error);
  if (!sim) throw std::runtime_error(error);
  for (int i = 0; i < 60; ++i) sim->step();
  return std::move(*sim);
}

Costs measure(const std::string& scene_json, const std::string& name, int samples, int ticks) {
  Costs c;
  {
    Simulation sim = settled(scene_json, name);
    c.bodies = sim.world().bodies().size();
    c.step_ms = best_ms_per_tick(samples, ticks, [&] { sim.step(); });
    // Restoring a rollback state (in place), as a rollback does once a frame.
    RollbackStates states;
    std::vector<uint8_t> state;
    states.save(sim.world(), state);
    c.restore_ms = best_ms_per_tick(samples, ticks, [&] { (void)states.restore(state, sim.world()); });
  }
  for (const SessionMode mode : {SessionMode::lockstep, SessionMode::rollback}) {
    SessionConfig config;
    config.players = 1;
    config.mode = mode;
    Session session(settled(scene_json, name), config, [](Simulation&, int, const PlayerInput&) {});
    const double ms = best_ms_per_tick(samples, ticks, [&] {
      session.add_local_input({});
      session.advance();
      (void)session.take_outgoing();
    });
    (mode == SessionMode::lockstep ? c.lockstep_ms : c.rollback_ms) = ms;
  }
  return c;
}

std::string pyramid_scene(int base) {
  return fmt::format(R"({{"format": "bitstep-scene", "version": 1, "bodies": [{{"name": "ground", "type": "static",
      "shapes": [{{"type": "plane"}}]}}], "generators": [{{"type": "pyramid", "name": "p", "base": {}}}]}})",
                     base);
}

}  // namespace

int run_bench_session(int argc, char** argv) {
  bool quick = false;
  std::string scenes = "scenes";
  for (int i = 0; i < argc; ++i) {
    if (std::strcmp(argv[i], "--quick") == 0) {
      quick = true;
    } else if (std::strcmp(argv[i], "--scenes") == 0 && i + 1 < argc) {
      scenes = argv[++i];
    } else {
      fmt::print(stderr, "bitstep bench session: unknown option '{}'\n", argv[i]);
      return exit_code::usage;
    }
  }
  const int samples = quick ? 2 : 5, ticks = quick ? 10 : 30;
  try {
    fmt::print("| scene | bodies | step (ms) | lockstep session (ms/tick) | rollback session (ms/tick) | "
               "overhead lockstep / rollback (us) | restore a state (us) |\n|---|---:|---:|---:|---:|---:|---:|\n");
    for (const char* name : {"stack20.json", "pyramid20.json", "thrown.json", "playground.json"}) {
      std::string text, reason;
      if (!read_text_file(scenes + "/" + name, text, reason)) throw std::runtime_error(scenes + "/" + name + ": " + reason);
      const Costs c = measure(text, name, samples, ticks);
      fmt::print("| {} | {} | {:.3f} | {:.3f} | {:.3f} | {:.0f} / {:.0f} | {:.0f} |\n", name, c.bodies, c.step_ms,
                 c.lockstep_ms, c.rollback_ms, 1000 * (c.lockstep_ms - c.step_ms), 1000 * (c.rollback_ms - c.step_ms),
                 1000 * c.restore_ms);
    }
    // Pyramids of growing size: the largest each mode sustains.
    std::vector<Costs> ladder;
    fmt::print("\n| pyramid base | bodies | step (ms) | lockstep tick (ms) | rollback tick (ms) | worst rollback frame (ms) |\n"
               "|---:|---:|---:|---:|---:|---:|\n");
    for (const int base : quick ? std::vector<int>{10, 40, 80} : std::vector<int>{10, 20, 40, 60, 80, 100, 140}) {
      const Costs c = measure(pyramid_scene(base), "pyramid", samples, ticks);
      ladder.push_back(c);
      fmt::print("| {} | {} | {:.3f} | {:.3f} | {:.3f} | {:.2f} |\n", base, c.bodies, c.step_ms, c.lockstep_ms,
                 c.rollback_ms, c.restore_ms + 9 * c.rollback_ms);
    }
    fmt::print("\n| mode | at 60 Hz (16.7 ms) | at 20 Hz (50 ms) |\n|---|---:|---:|\n");
    const auto largest = [&](auto&& frame_ms, double budget) {
      size_t best = 0;
      for (const Costs& c : ladder) {
        if (frame_ms(c) <= budget) best = std::max(best, c.bodies);
      }
      return best == 0 ? std::string("none measured") : fmt::format("{} bodies", best);
    };
    const auto lockstep = [](const Costs& c) { return c.lockstep_ms; };
    const auto rollback = [](const Costs& c) { return c.restore_ms + 9 * c.rollback_ms; };
    fmt::print("| lockstep (a tick per frame) | {} | {} |\n", largest(lockstep, 1000.0 / 60), largest(lockstep, 50.0));
    fmt::print("| rollback (restore + 9 ticks per frame, worst case) | {} | {} |\n", largest(rollback, 1000.0 / 60),
               largest(rollback, 50.0));
  } catch (const std::exception& e) {
    fmt::print(stderr, "bitstep bench session: {}\n", e.what());
    return exit_code::bad_input;  // a scene refused
  }
  return 0;
}

}  // namespace bitstep
