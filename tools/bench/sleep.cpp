// `bitstep bench sleep`: what a sleeping world costs next to the same world
// awake.
//
// Method. For each scene the world is built twice from the scene file. Awake:
// sleep off, `steps` steps timed from the start (the structure standing, as
// in the report's speed table). Asleep: sleep on (motion or still), stepped
// until every dynamic body sleeps, then `steps` steps timed. Each figure is
// the mean ms/step of one timed run (std::chrono::steady_clock); the ratio is
// awake / asleep. The asleep run also checks that nothing moved while asleep.
#include "tools/bench/sleep.h"

#include <fmt/core.h>

#include <chrono>
#include <cstdio>
#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "core/world.h"
#include "replay/replay.h"
#include "replay/scene.h"
#include "tools/cli/options.h"
#include "tools/cli/exit_codes.h"

namespace bitstep {

namespace {

struct SleepRow {
  std::string scene;
  int bodies = 0;
  double awake_ms = 0;
  double asleep_ms = 0;
  int sleep_step = -1;  // -1: never all asleep within the limit
};

bool build(const Scene& scene, World& world) {
  if (const Result<void> built = build_world(scene, world); !built.ok()) {
    fmt::print(stderr, "bitstep bench sleep: {}\n", built.error().message());
    return false;
  }
  return true;
}

double ms_per_step(World& world, int steps) {
  const auto start = std::chrono::steady_clock::now();
  for (int i = 0; i < steps; ++i) world.step();
  const std::chrono::duration<double, std::milli> elapsed = std::chrono::steady_clock::now() - start;
  return elapsed.count() / steps;
}

bool all_asleep(const World& world) {
  for (const Body& b : world.bodies()) {
    if (b.alive && b.type == BodyType::dynamic && !b.asleep) return false;
  }
  return true;
}

bool measure(const std::string& path, SleepMethod method, int steps, SleepRow& row) {
  Result<Scene> loaded = load_scene_file(path);
  if (!loaded.ok()) {
    fmt::print(stderr, "{}\n", loaded.error().message());
    return false;
  }
  Scene scene = std::move(loaded).value();
  scene.settings.sleep_method = SleepMethod::off;
  World awake(scene.settings);
  if (!build(scene, awake)) return false;
  row.scene = path.substr(path.find_last_of('/') + 1);
  row.awake_ms = ms_per_step(awake, steps);
  for (const Body& b : awake.bodies()) row.bodies += b.alive && b.type == BodyType::dynamic;

  scene.settings.sleep_method = method;
  World asleep(scene.settings);
  if (!build(scene, asleep)) return false;
  constexpr int limit = 600;
  for (int step = 1; step <= limit && row.sleep_step < 0; ++step) {
    asleep.step();
    if (all_asleep(asleep)) row.sleep_step = step;
  }
  if (row.sleep_step < 0) return true;
  std::vector<Pose> poses;
  for (const Body& b : asleep.bodies()) poses.push_back(b.pose);
  row.asleep_ms = ms_per_step(asleep, steps);
  for (size_t i = 0; i < poses.size(); ++i) {
    if (asleep.bodies()[i].pose.position != poses[i].position) {
      fmt::print(stderr, "bitstep bench sleep: {}: body {} moved while asleep\n", row.scene, i);
      return false;
    }
  }
  return true;
}

}  // namespace

int run_bench_sleep(int argc, char** argv) {
  int steps = 30;
  std::string scenes_dir = "scenes";
  SleepMethod method = SleepMethod::motion;
  std::vector<std::string> scenes = {"stack20.json", "pyramid20.json", "thrown.json", "wall128.json"};
  CLI::App app("ms/step of scenes awake and asleep", "bitstep bench sleep");
  app.add_flag_callback("--quick", [&scenes] { scenes = {"stack20.json", "pyramid20.json"}; }, "two scenes");
  app.add_flag_callback("--still", [&method] { method = SleepMethod::still; }, "JigLib's still pose, not motion");
  app.add_option("--scenes", scenes_dir, "the scenes' folder (default scenes)")->type_name("DIR");
  if (const std::optional<int> code = cli::parse(app, "bench sleep", argc, argv)) return *code;
  fmt::print("| scene | dynamic bodies | sleep | all asleep at step | awake ms/step | asleep ms/step | awake / asleep |\n");
  fmt::print("|---|---:|---|---:|---:|---:|---:|\n");
  for (const std::string& name : scenes) {
    SleepRow row;
    if (!measure(scenes_dir + "/" + name, method, steps, row)) return exit_code::bad_input;  // a scene refused
    const char* method_name = method == SleepMethod::motion ? "motion" : "still";
    if (row.sleep_step < 0) {
      fmt::print("| {} | {} | {} | never (600 steps) | {:.3f} | - | - |\n", row.scene, row.bodies, method_name,
                 row.awake_ms);
      continue;
    }
    fmt::print("| {} | {} | {} | {} | {:.3f} | {:.4f} | {:.0f}x |\n", row.scene, row.bodies, method_name,
               row.sleep_step, row.awake_ms, row.asleep_ms, row.awake_ms / row.asleep_ms);
    std::fflush(stdout);
  }
  return 0;
}

}  // namespace bitstep
