#include "tools/synctest_command.h"

#include <fmt/core.h>

#include <cstdlib>
#include <string>
#include <variant>

#include "replay/json_tree.h"
#include "replay/sync_test.h"
#include "tools/exit_codes.h"

namespace bitstep {

namespace {

bool parse_count(const char* text, long long lo, long long hi, int64_t& out) {
  char* end = nullptr;
  const long long value = std::strtoll(text, &end, 10);
  if (end == text || *end != '\0' || value < lo || value > hi) return false;
  out = value;
  return true;
}

// Whether the file is a replay (its "format"), as far as it can be read:
// an unreadable file is taken for a scene, whose loader names the problem.
bool is_replay(const std::string& path) {
  std::string text, reason;
  if (!read_text_file(path, text, reason)) return false;
  const auto tree = json::parse(text);
  const json::Node* format = std::holds_alternative<json::Node>(tree) ? std::get<json::Node>(tree).member("format") : nullptr;
  return format != nullptr && format->text == "bitstep-replay";
}

}  // namespace

int synctest_command(int argc, char** argv) {
  std::string path;
  int64_t frames = 8, steps = -1;
  for (int i = 0; i < argc; ++i) {
    const std::string arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--frames" && has_value) {
      if (!parse_count(argv[++i], 1, 64, frames)) {
        fmt::print(stderr, "bitstep synctest: --frames needs an integer 1..64, got '{}'\n", argv[i]);
        return exit_code::usage;
      }
    } else if (arg == "--steps" && has_value) {
      if (!parse_count(argv[++i], 1, 1000000, steps)) {
        fmt::print(stderr, "bitstep synctest: --steps needs an integer 1..1000000, got '{}'\n", argv[i]);
        return exit_code::usage;
      }
    } else if (!arg.empty() && arg[0] != '-' && path.empty()) {
      path = arg;
    } else {
      fmt::print(stderr, "bitstep synctest: unknown or incomplete option '{}'\n", arg);
      return exit_code::usage;
    }
  }
  if (path.empty()) {
    fmt::print(stderr, "bitstep synctest: usage: bitstep synctest SCENE|REPLAY [--frames K] [--steps N]\n");
    return exit_code::usage;
  }
  Scene scene;
  std::vector<Input> inputs;
  std::vector<uint64_t> golden;
  if (is_replay(path)) {
    auto loaded = load_replay_file(path, false);
    if (const auto* error = std::get_if<ReplayError>(&loaded)) {
      fmt::print(stderr, "bitstep synctest: {}\n", error->message());
      return exit_code::bad_input;
    }
    Replay& replay = std::get<Replay>(loaded);
    scene = std::move(replay.scene);
    inputs = std::move(replay.inputs);
    golden = std::move(replay.hashes);
    if (steps < 0) steps = replay.steps;
  } else {
    auto loaded = load_scene_file(path);
    if (const auto* error = std::get_if<SceneError>(&loaded)) {
      fmt::print(stderr, "bitstep synctest: {}\n", error->message());
      return exit_code::bad_input;
    }
    scene = std::move(std::get<Scene>(loaded));
    if (steps < 0) steps = 600;
  }
  World world(scene.settings);
  std::string reason;
  if (!build_world(scene, world, reason)) {
    fmt::print(stderr, "bitstep synctest: {}: {}\n", path, reason);
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
