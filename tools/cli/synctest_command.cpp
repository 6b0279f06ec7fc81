#include "tools/cli/synctest_command.h"

#include <fmt/core.h>

#include <string>

#include "replay/json_tree.h"
#include "replay/sync_test.h"
#include "tools/cli/options.h"
#include "tools/cli/exit_codes.h"

namespace bitstep {

namespace {

// Whether the file is a replay (its "format"), as far as it can be read:
// an unreadable file is taken for a scene, whose loader names the problem.
bool is_replay(const std::string& path) {
  const Result<std::string> text = read_text_file(path);
  if (!text.ok()) return false;
  const Result<json::Node> tree = json::parse(text.value());
  const json::Node* format = tree.ok() ? tree->member("format") : nullptr;
  return format != nullptr && format->text == "bitstep-replay";
}

}  // namespace

int synctest_command(int argc, char** argv) {
  std::string path;
  int64_t frames = 8, steps = -1;
  CLI::App app("after every tick roll back K ticks and simulate them again: every hash must be the same",
               "bitstep synctest");
  app.add_option("SCENE|REPLAY", path, "a scene, or a replay (its inputs and chain)")->required();
  cli::add_integer(app, "--frames", 1, 64, frames, "ticks rolled back (default 8)")->type_name("K");
  cli::add_integer(app, "--steps", 1, 1000000, steps, "ticks of a scene (default 600)")->type_name("N");
  if (const std::optional<int> code = cli::parse(app, "synctest", argc, argv)) return *code;
  Scene scene;
  std::vector<Input> inputs;
  std::vector<uint64_t> golden;
  if (is_replay(path)) {
    Result<Replay> loaded = load_replay_file(path, false);
    if (!loaded.ok()) {
      fmt::print(stderr, "bitstep synctest: {}\n", loaded.error().message());
      return exit_code::bad_input;
    }
    Replay& replay = loaded.value();
    scene = std::move(replay.scene);
    inputs = std::move(replay.inputs);
    golden = std::move(replay.hashes);
    if (steps < 0) steps = replay.steps;
  } else {
    Result<Scene> loaded = load_scene_file(path);
    if (!loaded.ok()) {
      fmt::print(stderr, "bitstep synctest: {}\n", loaded.error().message());
      return exit_code::bad_input;
    }
    scene = std::move(loaded).value();
    if (steps < 0) steps = 600;
  }
  World world(scene.settings);
  if (const Result<void> built = build_world(scene, world); !built.ok()) {
    fmt::print(stderr, "bitstep synctest: {}\n", built.error().within(path).message());
    return exit_code::bad_input;
  }
  const SyncTestResult r = sync_test(world, inputs, steps, static_cast<int>(frames));
  if (!r.ok()) {
    fmt::print(stderr, "bitstep synctest: {}: tick {} simulated again gave {:016x}, the first time {:016x}: {}\n", path,
               r.mismatch_tick, r.again_hash, r.first_hash, r.difference);
    return exit_code::check_failed;
  }
  fmt::print("{}: {} ticks, {} frames rolled back after each: {} ticks simulated again, every hash the same\n", path,
             steps, frames, r.rollbacks);
  fmt::print("final hash at tick {}: {:016x}\n", steps, r.hashes.empty() ? 0 : r.hashes.back());
  if (!golden.empty()) {
    const int64_t divergent = first_divergent_step(golden, r.hashes);
    if (divergent != 0) {
      fmt::print(stderr, "bitstep synctest: {}: the chain differs from the replay's at step {}\n", path, divergent);
      return exit_code::check_failed;
    }
    fmt::print("the chain is the replay's ({} hashes)\n", golden.size());
  }
  return exit_code::success;
}

}  // namespace bitstep
