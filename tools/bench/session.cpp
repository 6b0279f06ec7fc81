// `bitstep bench session`: the cost of running a game through a Session.
//
// Method. Each world is built from a scene (the shipped ones, and pyramids
// of unit cubes with 10 to 140 along the base: 55 to 9,870 bodies), stepped
// 60 times (every contact found), then timed over T ticks three ways with
// std::chrono::steady_clock, best of the samples: the world's step alone; a
// one-player lockstep session and a one-player rollback session (each tick's
// rollback state saved, its checksum from that save). The session's
// overhead is the difference per tick.
// A lockstep game sustains a world whose tick fits in the frame (16.7 ms at
// 60 Hz, 50 ms at 20 Hz); a rollback game must also afford the worst case
// of a rollback every frame: restoring a state and simulating its 8
// predicted ticks again, so 9 ticks and a restore per frame. The pyramids
// are measured standing (best of the samples) and being knocked over: a
// 50 kg ball fired at 15 m/s into the middle of the second row, and every
// tick of the second after it counted (the mean, with the restore taken
// where the ball strikes), since a rollback game must afford the collapse
// as well as the stand; and pushed: the top cube pushed 1 m/s sideways by
// the player's input every second, the mean of two seconds' ticks (a push
// wakes the pile: what a game whose players touch its piles pays).
#include "tools/bench/session.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cstring>
#include <stdexcept>
#include <string>
#include <vector>

#include "replay/rollback_state.h"
#include "replay/session.h"
#include "tools/bench/costs.h"
#include "tools/cli/exit_codes.h"
#include "tools/cli/options.h"

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
  Result<Simulation> sim = Simulation::from_text(scene_json, name);
  if (!sim.ok()) throw std::runtime_error(sim.error().message());
  for (int i = 0; i < 60; ++i) sim->step();
  return std::move(sim).value();
}

// The mean ms per tick over `ticks` ticks from where the simulation is.
double mean_ms_per_tick(int ticks, const auto& tick) {
  const auto start = Clock::now();
  for (int t = 0; t < ticks; ++t) tick();
  return std::chrono::duration<double, std::milli>(Clock::now() - start).count() / ticks;
}

// The ball that knocks a pyramid over, 2 m in front of its second row.
constexpr const char* knocking_ball =
    R"({"name": "ball", "position": [0, 1.5, -2.5], "velocity": [0, 0, 15], "mass": 50,
        "shapes": [{"type": "sphere", "radius": 0.5}]})";

Simulation settled_and_knocked(const std::string& scene_json, const std::string& name) {
  Simulation sim = settled(scene_json, name);
  const Result<BodyId> ball = sim.add_body(knocking_ball);
  if (!ball.ok()) throw std::runtime_error(ball.error().within(name).message());
  return sim;
}

// The same as measure() while the ball knocks the pyramid over: every tick
// of the second after the throw, on fresh worlds.
Costs measure_knocked(const std::string& scene_json, const std::string& name, int ticks) {
  Costs c;
  {
    Simulation sim = settled_and_knocked(scene_json, name);
    c.bodies = sim.world().bodies().size();
    for (int t = 0; t < 8; ++t) sim.step();  // the ball meets the pyramid
    RollbackStates states;
    std::vector<uint8_t> state;
    states.save(sim.world(), state);
    c.restore_ms = best_ms_per_tick(1, ticks, [&] { (void)states.restore(state, sim.world()); });
  }
  {
    Simulation sim = settled_and_knocked(scene_json, name);
    c.step_ms = mean_ms_per_tick(ticks, [&] { sim.step(); });
  }
  for (const SessionMode mode : {SessionMode::lockstep, SessionMode::rollback}) {
    SessionConfig config;
    config.players = 1;
    config.mode = mode;
    Session session(settled_and_knocked(scene_json, name), config, [](Simulation&, int, const PlayerInput&) {});
    const double ms = mean_ms_per_tick(ticks, [&] {
      session.add_local_input({});
      session.advance();
      (void)session.take_outgoing();
    });
    (mode == SessionMode::lockstep ? c.lockstep_ms : c.rollback_ms) = ms;
  }
  return c;
}

// A game whose input pushes the last dynamic body (a pyramid's top cube)
// 1 m/s sideways when it is "push", as a player's move does now and then.
void push_top(Simulation& sim, int, const PlayerInput& input) {
  if (input != "push") return;
  const std::optional<BodyId> top = bench::last_dynamic_body(sim.world());
  if (!top) return;
  const Body& b = sim.world().body(*top);
  (void)sim.apply_impulse(*top, bench::sideways_impulse(b, Fixed::from_int(1)), b.pose.position);
}

// The same as measure() with a push every second (every 60th tick, from
// the first): the mean of `ticks` ticks, the pile woken as a game wakes it.
Costs measure_pushed(const std::string& scene_json, const std::string& name, int ticks) {
  Costs c;
  const auto input_at = [](int t) { return t % 60 == 0 ? PlayerInput("push") : PlayerInput(); };
  {
    Simulation sim = settled(scene_json, name);
    c.bodies = sim.world().bodies().size();
    RollbackStates states;
    std::vector<uint8_t> state;
    states.save(sim.world(), state);
    c.restore_ms = best_ms_per_tick(1, 10, [&] { (void)states.restore(state, sim.world()); });
    int t = 0;
    c.step_ms = mean_ms_per_tick(ticks, [&] {
      push_top(sim, 0, input_at(t++));
      sim.step();
    });
  }
  for (const SessionMode mode : {SessionMode::lockstep, SessionMode::rollback}) {
    SessionConfig config;
    config.players = 1;
    config.mode = mode;
    Session session(settled(scene_json, name), config, push_top);
    int t = 0;
    const double ms = mean_ms_per_tick(ticks, [&] {
      session.add_local_input(input_at(t++));
      session.advance();
      (void)session.take_outgoing();
    });
    (mode == SessionMode::lockstep ? c.lockstep_ms : c.rollback_ms) = ms;
  }
  return c;
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
  CLI::App app("what a session adds to a tick; the largest world lockstep and rollback sustain",
               "bitstep bench session");
  app.add_flag("--quick", quick, "fewer samples and ticks");
  app.add_option("--scenes", scenes, "the scenes' folder (default scenes)")->type_name("DIR");
  if (const std::optional<int> code = cli::parse(app, "bench session", argc, argv)) return *code;
  const int samples = quick ? 2 : 5, ticks = quick ? 10 : 30;
  try {
    fmt::print("| scene | bodies | step (ms) | lockstep session (ms/tick) | rollback session (ms/tick) | "
               "overhead lockstep / rollback (us) | restore a state (us) |\n|---|---:|---:|---:|---:|---:|---:|\n");
    for (const char* name : {"stack20.json", "pyramid20.json", "thrown.json", "playground.json"}) {
      const Result<std::string> text = read_text_file(scenes + "/" + name);
      if (!text.ok()) throw std::runtime_error(text.error().message());
      const Costs c = measure(text.value(), name, samples, ticks);
      fmt::print("| {} | {} | {:.3f} | {:.3f} | {:.3f} | {:.0f} / {:.0f} | {:.0f} |\n", name, c.bodies, c.step_ms,
                 c.lockstep_ms, c.rollback_ms, 1000 * (c.lockstep_ms - c.step_ms), 1000 * (c.rollback_ms - c.step_ms),
                 1000 * c.restore_ms);
    }
    // Pyramids of growing size, standing and knocked over: the largest
    // each mode sustains.
    std::vector<Costs> standing, pushed, knocked;
    fmt::print("\n| pyramid base | bodies | case | step (ms) | lockstep tick (ms) | rollback tick (ms) | "
               "worst rollback frame (ms) |\n|---:|---:|---|---:|---:|---:|---:|\n");
    const auto row = [](int base, const char* what, const Costs& c) {
      fmt::print("| {} | {} | {} | {:.3f} | {:.3f} | {:.3f} | {:.2f} |\n", base, c.bodies, what, c.step_ms,
                 c.lockstep_ms, c.rollback_ms, c.restore_ms + 9 * c.rollback_ms);
    };
    const std::vector<int> bases =
        quick ? std::vector<int>{10, 20, 28, 32, 40} : std::vector<int>{10, 20, 24, 28, 32, 36, 40, 60, 80, 100, 140};
    for (const int base : bases) {
      standing.push_back(measure(pyramid_scene(base), "pyramid", samples, ticks));
      row(base, "standing", standing.back());
      if (base <= 40) {  // two seconds of a pushed 821-body pyramid take 20 s a round
        pushed.push_back(measure_pushed(pyramid_scene(base), "pyramid", quick ? 60 : 120));
        row(base, "pushed every second", pushed.back());
      }
      // The collapse of the largest pyramids takes minutes a round: up to 80.
      if (base > 80) continue;
      knocked.push_back(measure_knocked(pyramid_scene(base), "pyramid", quick ? 30 : 60));
      row(base, "knocked over", knocked.back());
    }
    fmt::print(
        "\n| mode | standing, 60 Hz (16.7 ms) | pushed every second, 60 Hz | knocked over, 60 Hz | "
        "standing, 20 Hz (50 ms) | pushed every second, 20 Hz | knocked over, 20 Hz |\n"
        "|---|---:|---:|---:|---:|---:|---:|\n");
    const auto largest = [](const std::vector<Costs>& ladder, auto&& frame_ms, double budget) {
      size_t best = 0;
      for (const Costs& c : ladder) {
        if (frame_ms(c) <= budget) best = std::max(best, c.bodies);
      }
      return best == 0 ? std::string("none measured") : fmt::format("{} bodies", best);
    };
    const auto lockstep = [](const Costs& c) { return c.lockstep_ms; };
    const auto rollback = [](const Costs& c) { return c.restore_ms + 9 * c.rollback_ms; };
    for (const auto& [mode, frame] : {std::pair<const char*, double (*)(const Costs&)>{"lockstep (a tick per frame)",
                                                                                       lockstep},
                                      {"rollback (restore + 9 ticks per frame, worst case)", rollback}}) {
      fmt::print("| {} | {} | {} | {} | {} | {} | {} |\n", mode, largest(standing, frame, 1000.0 / 60),
                 largest(pushed, frame, 1000.0 / 60), largest(knocked, frame, 1000.0 / 60),
                 largest(standing, frame, 50.0), largest(pushed, frame, 50.0), largest(knocked, frame, 50.0));
    }
  } catch (const std::exception& e) {
    fmt::print(stderr, "bitstep bench session: {}\n", e.what());
    return exit_code::bad_input;  // a scene refused
  }
  return 0;
}

}  // namespace bitstep
