#include "tools/cli/run_command.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <cstring>
#include <optional>
#include <span>
#include <string>
#include <vector>

#include "replay/limits.h"
#include "replay/replay.h"
#include "replay/scene.h"
#include "replay/snapshot.h"
#include "replay/state_hash.h"
#include "tools/cli/body_trace.h"
#include "tools/cli/options.h"
#include "tools/cli/shared_options.h"
#include "tools/cli/exit_codes.h"
#include "tools/cli/file_output.h"
#include "tools/cli/thread_option.h"

namespace bitstep {

namespace {

struct RunOptions {
  std::string scene_path;
  long long steps = -1;  // -1: from seconds
  std::string seconds = "10";
  long long hash_every = 0;
  bool json = false;
  long long snapshot_at = -1;   // write a snapshot after this step
  std::string snapshot_path;
  std::string restore_path;     // continue from this snapshot instead of the scene's start
  std::string settings;         // JSON object of "settings" keys over the scene's
  TraceOptions trace;           // --trace: every body's pose and velocities
  int threads = 1;              // --threads: workers stepping the world (the same bits for any count)
  bool events = false;          // --events: each step's contact and sensor events
};

constexpr const char* event_names[] = {"contact begin", "contact end", "sensor begin",
                                       "sensor end",    "left world",  "joint broken"};

// "step 42: contact begin "box.3" (shape 0) - "ground" (shape 0)",
// "step 9000: left world "ball"" (core/world.h: removed past the bound)
std::string event_line(uint64_t step, const WorldEvent& e, const Scene& scene) {
  auto name = [&](uint32_t slot) {
    return slot < scene.bodies.size() && !scene.bodies[slot].name.empty() ? "\"" + scene.bodies[slot].name + "\""
                                                                          : "body " + std::to_string(slot);
  };
  if (e.kind == EventKind::left_world) return fmt::format("step {}: left world {}", step, name(e.key.body_a));
  if (e.kind == EventKind::joint_broken) {
    return fmt::format("step {}: joint broken: joint {} between {} and {}", step, e.joint, name(e.key.body_a),
                       name(e.key.body_b));
  }
  return fmt::format("step {}: {} {} (shape {}) - {} (shape {})", step, event_names[static_cast<int>(e.kind)],
                     name(e.key.body_a), e.key.shape_a, name(e.key.body_b), e.key.shape_b);
}

double to_double(Fixed f) { return static_cast<double>(f.raw()) * 0x1p-32; }

// The command line into `o`: nullopt, or the exit status (--help, a usage error).
std::optional<int> parse_options(int argc, char** argv, RunOptions& o) {
  CLI::App app("run a scene: a line per second and the final state hash", "bitstep run");
  app.add_option("SCENE", o.scene_path, "a bitstep-scene JSON file")->required();
  cli::add_read(app, "--steps", "a non-negative integer",
                [&o](const std::string& text) { return cli::read_integer(text, 0, INT64_MAX, o.steps); },
                "steps to run (default: --seconds of them)")
      ->type_name("N");
  app.add_option("--seconds", o.seconds, "seconds of simulated time (default 10)")->type_name("S");
  cli::add_read(app, "--hash-every", "a non-negative integer",
                [&o](const std::string& text) { return cli::read_integer(text, 0, INT64_MAX, o.hash_every); },
                "print the state hash every K-th step")
      ->type_name("K");
  app.add_flag("--json", o.json, "one JSON object instead of the table");
  app.add_option("--settings", o.settings, "scene settings over the scene's: '{\"sleep\": \"still\"}'")
      ->type_name("JSON");
  app.add_option_function<std::pair<std::string, std::string>>(
         "--snapshot-at",
         [&o](const std::pair<std::string, std::string>& value) {
           if (!cli::read_integer(value.first, 0, INT64_MAX, o.snapshot_at)) {
             cli::refuse("--snapshot-at", "a non-negative step", value.first);
           }
           o.snapshot_path = value.second;
         },
         "write a snapshot of the world after step K to FILE")
      ->type_name("K FILE");
  app.add_option("--restore", o.restore_path, "start from this snapshot instead of the scene's start")
      ->type_name("FILE");
  cli::add_trace(app, o.trace);
  cli::add_threads(app, o.threads, 1, "N workers step the world (the same bits for any N)");
  app.add_flag("--events", o.events, "print each step's contact and sensor begin and end events");
  if (const std::optional<int> code = cli::parse(app, "run", argc, argv)) return code;
  if (const std::string error = o.trace.check(); !error.empty()) {
    fmt::print(stderr, "bitstep run: {}\n", error);
    return exit_code::usage;
  }
  return std::nullopt;
}

struct SecondSummary {
  long long second;
  StepStats stats;   // at the interval's last step, but max_penetration: the largest over its steps
  double max_drift;  // m, the largest over the interval's steps
  double ms_per_step;
};

// The largest distance of any dynamic body from where it started: for a
// scene that should stand, its stability number.
double max_drift(const World& world, const std::vector<Vec3>& start) {
  double drift = 0;
  for (size_t i = 0; i < start.size(); ++i) {
    const Body& body = world.bodies()[i];
    if (!body.alive || body.type != BodyType::dynamic) continue;
    const Vec3 d = body.pose.position - start[i];
    const double x = to_double(d.x), y = to_double(d.y), z = to_double(d.z);
    drift = std::max(drift, std::sqrt(x * x + y * y + z * z));
  }
  return drift;
}

// The per-interval maxima, taken at every step: a deep contact or a far
// excursion between two report lines is not lost.
struct IntervalMaxima {
  Fixed penetration;
  double drift = 0;

  void add(const StepStats& stats, double step_drift) {
    penetration = max(penetration, stats.max_penetration);
    drift = std::max(drift, step_drift);
  }
};

// Why a world restored from a snapshot is not one of this scene's, or
// empty. Its settings are the scene's (after --settings), and every slot
// the scene fills holds, unless it was emptied or refilled since (its
// generation moved on), a body of the same type, mass and shapes. The
// step's state may differ in anything else.
bool same_shapes(const std::vector<Shape>& a, const std::vector<Shape>& b) {
  if (a.size() != b.size()) return false;
  for (size_t i = 0; i < a.size(); ++i) {
    const Shape& x = a[i];
    const Shape& y = b[i];
    if (x.type != y.type || !(x.half_extents == y.half_extents) || x.radius != y.radius ||
        x.half_height != y.half_height || !(x.local.position == y.local.position) ||
        !(x.local.orientation == y.local.orientation)) {
      return false;
    }
  }
  return true;
}

std::string snapshot_mismatch(const World& restored, const World& scene_world) {
  // Two empty worlds hash alike exactly when their settings are the same.
  if (state_hash(World(restored.settings())) != state_hash(World(scene_world.settings()))) {
    return "its settings differ from the scene's";
  }
  const std::vector<Body>& theirs = restored.bodies();
  const std::vector<Body>& ours = scene_world.bodies();
  if (theirs.size() < ours.size()) {
    return fmt::format("it has {} body slots, the scene {}", theirs.size(), ours.size());
  }
  for (size_t i = 0; i < ours.size(); ++i) {
    const Body& a = theirs[i];
    const Body& b = ours[i];
    if (!a.alive || a.generation != b.generation) continue;  // removed or refilled since
    if (a.type != b.type || a.inverse_mass != b.inverse_mass || !same_shapes(a.shapes, b.shapes)) {
      return fmt::format("slot {} holds another body than the scene's body {}", i, i);
    }
  }
  return {};
}

// Every dynamic body asleep (and there is at least one).
bool all_asleep(const StepStats& stats) { return stats.awake_bodies == 0 && stats.sleeping_bodies > 0; }

std::string all_asleep_text(long long step) { return step < 0 ? "never" : fmt::format("step {}", step); }
std::string all_asleep_json(long long step) { return step < 0 ? "null" : std::to_string(step); }

}  // namespace

int run_scene_command(int argc, char** argv) {
  RunOptions options;
  if (const std::optional<int> code = parse_options(argc, argv, options)) return *code;
  Result<Scene> loaded = load_scene_file(options.scene_path);
  if (!loaded.ok()) {
    fmt::print(stderr, "bitstep run: {}\n", loaded.error().message());
    return exit_code::bad_input;
  }
  Scene& scene = loaded.value();
  if (!options.settings.empty()) {
    if (const Result<std::string> applied = apply_settings_text(options.settings, "--settings", scene.settings);
        !applied.ok()) {
      fmt::print(stderr, "bitstep run: {}\n", applied.error().message());
      return exit_code::usage;
    }
  }
  World world(scene.settings);
  if (const Result<void> built = build_world(scene, world); !built.ok()) {
    fmt::print(stderr, "bitstep run: {}\n", built.error().within(options.scene_path).message());
    return exit_code::bad_input;
  }
  const std::unique_ptr<ThreadPool> pool = make_pool(options.threads);
  world.set_executor(pool.get());
  if (!options.restore_path.empty()) {
    const Result<std::string> bytes = read_text_file(options.restore_path, limits::max_snapshot_file_bytes);
    if (!bytes.ok()) {
      fmt::print(stderr, "bitstep run: {}\n", bytes.error().message());
      return exit_code::bad_input;
    }
    const std::span<const uint8_t> image(reinterpret_cast<const uint8_t*>(bytes->data()), bytes->size());
    World restored(scene.settings);
    if (const Result<void> read = restore(image, restored); !read.ok()) {
      fmt::print(stderr, "bitstep run: {}\n", read.error().within(options.restore_path).message());
      return exit_code::bad_input;
    }
    if (const std::string mismatch = snapshot_mismatch(restored, world); !mismatch.empty()) {
      fmt::print(stderr, "bitstep run: {}: not a snapshot of {}: {}\n", options.restore_path, options.scene_path,
                 mismatch);
      return exit_code::bad_input;
    }
    restored.set_executor(pool.get());
    world = std::move(restored);
  }
  long long steps = options.steps;
  if (steps < 0) {
    const ParseResult seconds = parse_fixed(options.seconds);
    if (!seconds.ok() || seconds.value < Fixed{}) {
      fmt::print(stderr, "bitstep run: --seconds '{}': {}\n", options.seconds, describe(seconds.error));
      return exit_code::usage;
    }
    steps = (seconds.value / scene.settings.dt).raw() >> 32;
  }
  if (options.snapshot_at >= 0 && (options.snapshot_at < 1 || options.snapshot_at > steps)) {
    fmt::print(stderr, "bitstep run: --snapshot-at {}: the run has steps 1..{}\n", options.snapshot_at, steps);
    return exit_code::usage;
  }
  // The snapshot's file is opened (under its temporary name) before the
  // run: an unwritable path fails at once, not at step K.
  AtomicFile snapshot_file;
  std::string reason;
  if (!options.snapshot_path.empty() && !snapshot_file.open(options.snapshot_path, reason)) {
    fmt::print(stderr, "bitstep run: --snapshot-at: {}\n", reason);
    return exit_code::output_failed;
  }
  const long long steps_per_second = std::max<long long>(1, (Fixed::one() / scene.settings.dt).raw() >> 32);
  std::optional<BodyTrace> trace;
  if (const int code = options.trace.open("run", scene.settings.dt, world.step_count() + static_cast<uint64_t>(steps), trace);
      code != exit_code::success) {
    return code;
  }
  if (trace) trace->record_start(world);

  if (!options.json) {
    fmt::print("scene {}: {} bodies, dt {} s, {} velocity iterations, {} steps\n", options.scene_path,
               scene.bodies.size(), to_string(scene.settings.dt), scene.settings.velocity_iterations, steps);
    fmt::print("{:>6} {:>7} {:>9} {:>13} {:>12} {:>14} {:>9}\n", "t (s)", "awake", "contacts", "max pen (mm)",
               "drift (mm)", "KE (J)", "ms/step");
  }
  std::vector<Vec3> start;
  for (const Body& body : world.bodies()) start.push_back(body.pose.position);
  std::vector<SecondSummary> seconds;
  std::vector<std::pair<long long, uint64_t>> hashes;
  using Clock = std::chrono::steady_clock;
  Clock::duration busy{};
  long long steps_in_second = 0;
  IntervalMaxima maxima;
  long long all_asleep_step = -1;  // the world's step counter when every dynamic body first slept
  std::vector<std::string> event_json;  // --events --json
  world.set_events(options.events);
  for (long long step = 1; step <= steps; ++step) {
    const auto began = Clock::now();
    world.step();
    busy += Clock::now() - began;
    ++steps_in_second;
    const StepStats stats = world.stats();
    maxima.add(stats, max_drift(world, start));
    if (all_asleep_step < 0 && all_asleep(stats)) all_asleep_step = static_cast<long long>(world.step_count());
    if (trace) trace->record(world);
    // Without --events the world lists only bodies that left it (core/world.h).
    for (const WorldEvent& e : world.events()) {
      if (options.json) {
        event_json.push_back(fmt::format("{{\"step\": {}, \"kind\": \"{}\", \"bodies\": [{}, {}], \"shapes\": [{}, {}]}}",
                                         world.step_count(), event_names[static_cast<int>(e.kind)], e.key.body_a,
                                         e.key.body_b, e.key.shape_a, e.key.shape_b));
      } else {
        fmt::print("{}\n", event_line(world.step_count(), e, scene));
      }
    }
    if (step == options.snapshot_at) {
      const std::vector<uint8_t> image = snapshot(world);
      std::fwrite(image.data(), 1, image.size(), snapshot_file.stream());
      if (!snapshot_file.commit(reason)) {
        fmt::print(stderr, "bitstep run: --snapshot-at: {}\n", reason);
        return exit_code::output_failed;
      }
      if (!options.json) fmt::print("step {}: snapshot written to {}\n", world.step_count(), options.snapshot_path);
    }
    if (options.hash_every > 0 && step % options.hash_every == 0) {
      hashes.emplace_back(step, state_hash(world));
      if (!options.json) fmt::print("step {} hash {:016x}\n", step, hashes.back().second);
    }
    if (step % steps_per_second == 0 || step == steps) {
      const double ms = std::chrono::duration<double, std::milli>(busy).count() / static_cast<double>(steps_in_second);
      SecondSummary summary{(step + steps_per_second - 1) / steps_per_second, stats, maxima.drift, ms};
      summary.stats.max_penetration = maxima.penetration;
      seconds.push_back(summary);
      busy = {};
      steps_in_second = 0;
      maxima = {};
      const SecondSummary& s = seconds.back();
      if (!options.json) {
        fmt::print("{:>6} {:>7} {:>9} {:>13.3f} {:>12.3f} {:>14.4f} {:>9.3f}\n", s.second, s.stats.awake_bodies,
                   s.stats.contact_points, to_double(s.stats.max_penetration) * 1000.0, s.max_drift * 1000.0,
                   to_double(s.stats.kinetic_energy), s.ms_per_step);
      }
    }
  }
  if (!TraceOptions::finish("run", trace)) return exit_code::output_failed;
  const uint64_t final_hash = state_hash(world);
  if (!options.json) {
    if (scene.settings.sleep_method != SleepMethod::off) fmt::print("all asleep: {}\n", all_asleep_text(all_asleep_step));
    if (trace) fmt::print("trace written to {}\n", options.trace.path);
    fmt::print("final step {} hash {:016x}\n", world.step_count(), final_hash);
    return exit_code::success;
  }
  // Machine-readable: Fixed values as exact decimal text.
  fmt::print("{{\"scene\": \"{}\", \"bodies\": {}, \"dt\": \"{}\", \"steps\": {}, \"seconds\": [", options.scene_path,
             scene.bodies.size(), to_string(scene.settings.dt), world.step_count());
  for (size_t i = 0; i < seconds.size(); ++i) {
    const SecondSummary& s = seconds[i];
    fmt::print("{}{{\"t\": {}, \"awake\": {}, \"contacts\": {}, \"max_penetration\": \"{}\", \"max_drift\": {:.6f}, "
               "\"kinetic_energy\": \"{}\", \"ms_per_step\": {:.4f}}}",
               i == 0 ? "" : ", ", s.second, s.stats.awake_bodies, s.stats.contact_points,
               to_string(s.stats.max_penetration), s.max_drift, to_string(s.stats.kinetic_energy), s.ms_per_step);
  }
  fmt::print("], \"hashes\": [");
  for (size_t i = 0; i < hashes.size(); ++i) {
    fmt::print("{}{{\"step\": {}, \"hash\": \"{:016x}\"}}", i == 0 ? "" : ", ", hashes[i].first, hashes[i].second);
  }
  fmt::print("]");
  if (options.events || !event_json.empty()) {
    fmt::print(", \"events\": [");
    for (size_t i = 0; i < event_json.size(); ++i) fmt::print("{}{}", i == 0 ? "" : ", ", event_json[i]);
    fmt::print("]");
  }
  fmt::print(", \"all_asleep_step\": {}, \"final_hash\": \"{:016x}\"}}\n", all_asleep_json(all_asleep_step), final_hash);
  return 0;
}

}  // namespace bitstep
