#include "tools/cli/replay_command.h"

#include <fmt/core.h>

#include <cstdio>
#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <string>

#include "replay/json_tree.h"
#include "replay/limits.h"
#include "replay/replay.h"
#include "tools/cli/file_output.h"
#include "replay/state_dump.h"
#include "replay/state_hash.h"
#include "tools/cli/body_trace.h"
#include "tools/cli/options.h"
#include "tools/cli/shared_options.h"
#include "tools/cli/exit_codes.h"
#include "tools/cli/thread_option.h"

namespace bitstep {

namespace {

// A step count 0..limits::max_replay_steps.
bool parse_steps(const std::string& text, int64_t& out) {
  long long value = 0;
  if (!cli::read_integer(text, 0, limits::max_replay_steps, value)) return false;
  out = value;
  return true;
}

// The trace's rows at every step a run shows `watch`.
StepWatch trace_watch(std::optional<BodyTrace>& trace) {
  if (!trace) return {};
  return [&trace](const World& world) { trace->record(world); };
}

}  // namespace

int record_command(int argc, char** argv, const char* engine_version) {
  std::string scene_path, inputs_path, output, settings_text;
  int64_t steps = -1;
  int threads = 1;
  bool embed_scene = false;
  TraceOptions trace_options;
  CLI::App app("run a scene with inputs and write a replay with its hash chain", "bitstep record");
  app.add_option("SCENE", scene_path, "a bitstep-scene JSON file")->required();
  app.add_option("--inputs", inputs_path, "the inputs: a replay's, or an inputs file")->type_name("FILE");
  app.add_option("--settings", settings_text, "scene settings the replay keeps (else those of --inputs' replay)")
      ->type_name("JSON");
  app.add_flag("--embed-scene", embed_scene, "put the scene itself in the replay");
  cli::add_threads(app, threads, 1, "N workers step the world (the same bits for any N)");
  cli::add_trace(app, trace_options);
  cli::add_read(app, "--steps", "an integer 0.." + std::to_string(limits::max_replay_steps),
                [&steps](const std::string& text) { return parse_steps(text, steps); }, "steps to record")
      ->type_name("N")
      ->required();
  app.add_option("-o", output, "the replay to write")->type_name("REPLAY")->required();
  if (const std::optional<int> code = cli::parse(app, "record", argc, argv)) return *code;
  if (const std::string error = trace_options.check(); !error.empty()) {
    fmt::print(stderr, "bitstep record: {}\n", error);
    return exit_code::usage;
  }
  Result<Scene> loaded = load_scene_file(scene_path);
  if (!loaded.ok()) {
    fmt::print(stderr, "bitstep record: {}\n", loaded.error().message());
    return exit_code::bad_input;
  }
  Replay replay;
  replay.scene = std::move(loaded).value();
  replay.steps = steps;
  if (!inputs_path.empty()) {
    Result<InputsFile> inputs = load_inputs_file(inputs_path, replay.scene);
    if (!inputs.ok()) {
      fmt::print(stderr, "bitstep record: {}\n", inputs.error().message());
      return exit_code::bad_input;
    }
    replay.inputs = std::move(inputs->inputs);
    replay.settings_override = inputs->settings_override;
    if (!replay.inputs.empty() && replay.inputs.back().step > steps) {
      fmt::print(stderr, "bitstep record: {}: {}.step: after the last step ({})\n", inputs_path,
                 replay.inputs.back().source.path, steps);
      return exit_code::bad_input;
    }
  }
  // --settings replaces the settings override of a replay given as --inputs.
  if (!settings_text.empty()) replay.settings_override = settings_text;
  if (!replay.settings_override.empty()) {
    Result<std::string> applied = apply_settings_text(replay.settings_override, "--settings", replay.scene.settings);
    if (!applied.ok()) {
      fmt::print(stderr, "bitstep record: {}\n", applied.error().message());
      return exit_code::usage;
    }
    replay.settings_override = std::move(applied).value();
  }
  if (embed_scene) {
    // The scene itself in the replay (compact, numbers as written): a
    // replay shared between players verifies without the scene file.
    const Result<std::string> text = read_text_file(scene_path);
    if (!text.ok()) {
      fmt::print(stderr, "bitstep record: {}\n", text.error().message());
      return exit_code::bad_input;
    }
    replay.inline_scene = json::write(json::parse(text.value()).value());  // parsed above already
  } else {
    // The scene as the replay will name it: relative to the replay's folder.
    const std::filesystem::path out_dir = std::filesystem::absolute(output).parent_path();
    replay.scene_file = std::filesystem::absolute(scene_path).lexically_proximate(out_dir).generic_string();
  }

  World world(replay.scene.settings);
  if (const Result<void> built = build_world(replay.scene, world); !built.ok()) {
    fmt::print(stderr, "bitstep record: {}\n", built.error().within(scene_path).message());
    return exit_code::bad_input;
  }
  std::string reason;
  // The output is opened (under its temporary name) before the run: an
  // unwritable path fails at once, not after every step.
  AtomicFile file;
  if (!file.open(output, reason)) {
    fmt::print(stderr, "bitstep record: {}\n", reason);
    return exit_code::output_failed;
  }
  const std::unique_ptr<ThreadPool> pool = make_pool(threads);
  world.set_executor(pool.get());
  replay.scene_hash = state_hash(world);
  std::optional<BodyTrace> trace;
  if (const int code = trace_options.open("record", replay.scene.settings.dt, static_cast<uint64_t>(steps), trace);
      code != exit_code::success) {
    return code;
  }
  run_inputs(world, replay.inputs, steps, replay.hashes, -1, nullptr, trace_watch(trace));
  if (!TraceOptions::finish("record", trace)) return exit_code::output_failed;
  const std::string text = replay_json(replay, std::string("bitstep ") + engine_version);
  std::fwrite(text.data(), 1, text.size(), file.stream());
  if (!file.commit(reason)) {
    fmt::print(stderr, "bitstep record: {}\n", reason);
    return exit_code::output_failed;
  }
  fmt::print("recorded {}: {} steps, {} inputs, final hash {:016x}\n", output, steps, replay.inputs.size(),
             replay.hashes.empty() ? replay.scene_hash : replay.hashes.back());
  if (trace) fmt::print("trace written to {}\n", trace_options.path);
  return exit_code::success;
}

int verify_command(int argc, char** argv) {
  std::vector<std::string> paths;
  int64_t dump_step = -1;
  std::string dump_path;
  int threads = 1;
  TraceOptions trace_options;
  CLI::App app("re-run replays; exit 0 only if every step's hash matches", "bitstep verify");
  app.add_option("REPLAY", paths, "replays to verify")->required();
  app.add_option_function<std::pair<std::string, std::string>>(
         "--dump-at",
         [&dump_step, &dump_path](const std::pair<std::string, std::string>& value) {
           if (!parse_steps(value.first, dump_step)) {
             cli::refuse("--dump-at", "a step 0.." + std::to_string(limits::max_replay_steps), value.first);
           }
           dump_path = value.second;
         },
         "write the full state after STEP as exact JSON to FILE (one replay)")
      ->type_name("STEP FILE");
  cli::add_trace(app, trace_options);
  cli::add_threads(app, threads, 1, "N workers step the world (the same bits for any N)");
  if (const std::optional<int> code = cli::parse(app, "verify", argc, argv)) return *code;
  if ((!dump_path.empty() || !trace_options.path.empty()) && paths.size() != 1) {
    fmt::print(stderr,
               "bitstep verify: usage: bitstep verify [--threads N] REPLAY... | bitstep verify REPLAY [--dump-at STEP "
               "FILE] [--trace FILE [--trace-every K] [--trace-format csv|jsonl]]\n");
    return exit_code::usage;
  }
  if (const std::string error = trace_options.check(); !error.empty()) {
    fmt::print(stderr, "bitstep verify: {}\n", error);
    return exit_code::usage;
  }
  // The dump's file is opened (under its temporary name) before the run:
  // an unwritable path fails at once.
  AtomicFile dump_file;
  if (std::string reason; !dump_path.empty() && !dump_file.open(dump_path, reason)) {
    fmt::print(stderr, "bitstep verify: {}\n", reason);
    return exit_code::output_failed;
  }
  const std::unique_ptr<ThreadPool> pool = make_pool(threads);
  // With several replays: 4 when any was refused, else 1 when any differs.
  bool all_match = true, all_read = true;
  for (const std::string& path : paths) {
    const Result<Replay> loaded = load_replay_file(path, true);
    if (!loaded.ok()) {
      fmt::print(stderr, "bitstep verify: {}\n", loaded.error().message());
      all_read = false;
      continue;
    }
    const Replay& replay = loaded.value();
    if (!dump_path.empty() && dump_step > replay.steps) {  // before the run, not after it
      fmt::print(stderr, "bitstep verify: --dump-at {}: the replay {} has {} steps\n", dump_step, path, replay.steps);
      return exit_code::usage;
    }
    std::optional<BodyTrace> trace;
    if (const int code = trace_options.open("verify", replay.scene.settings.dt, static_cast<uint64_t>(replay.steps), trace);
        code != exit_code::success) {
      return code;
    }
    std::string dump;
    const Verification v =
        verify_replay(replay, dump_step, dump_path.empty() ? nullptr : &dump, pool.get(), trace_watch(trace));
    if (!TraceOptions::finish("verify", trace)) return exit_code::output_failed;
    if (trace) fmt::print("trace written to {}\n", trace_options.path);
    if (!dump_path.empty() && !dump.empty()) {
      std::string reason;
      std::fwrite(dump.data(), 1, dump.size(), dump_file.stream());
      if (!dump_file.commit(reason)) {
        fmt::print(stderr, "bitstep verify: {}\n", reason);
        return exit_code::output_failed;
      }
      fmt::print("wrote the state after step {} to {}\n", dump_step, dump_path);
    }
    if (!v.built.ok()) {
      fmt::print(stderr, "bitstep verify: {}\n", v.built.error().within(path).message());
      all_read = false;
      continue;
    }
    if (!v.scene_matches) {
      fmt::print("{}: DIFFERS before step 1: the scene builds a world with hash {:016x}, recorded {:016x}\n", path,
                 v.scene_hash, replay.scene_hash);
      all_match = false;
      continue;
    }
    if (v.divergent_step != 0) {
      const size_t at = static_cast<size_t>(v.divergent_step - 1);
      fmt::print("{}: DIFFERS at step {} of {}: hash {:016x}, recorded {:016x}\n", path, v.divergent_step,
                 replay.steps, v.hashes[at], replay.hashes[at]);
      all_match = false;
      continue;
    }
    fmt::print("{}: {} steps match, final hash {:016x}\n", path, replay.steps,
               v.hashes.empty() ? v.scene_hash : v.hashes.back());
  }
  if (!all_read) return exit_code::bad_input;
  return all_match ? exit_code::success : exit_code::check_failed;
}

int diff_command(int argc, char** argv) {
  std::string paths[2];
  CLI::App app("the first body, contact or field where two dumps (bitstep verify --dump-at) differ", "bitstep diff");
  app.add_option("DUMP_A", paths[0], "a dump")->required();
  app.add_option("DUMP_B", paths[1], "another dump")->required();
  if (const std::optional<int> code = cli::parse(app, "diff", argc, argv)) return *code;
  std::string texts[2];
  for (int i = 0; i < 2; ++i) {
    Result<std::string> text = read_text_file(paths[i]);
    if (!text.ok()) {
      fmt::print(stderr, "bitstep diff: {}\n", text.error().message());
      return exit_code::bad_input;
    }
    texts[i] = std::move(text).value();
  }
  const Result<DumpDifference> diff = diff_dumps(texts[0], texts[1], paths[0], paths[1]);
  if (!diff.ok()) {
    fmt::print(stderr, "bitstep diff: {}\n", diff.error().message());
    return exit_code::bad_input;
  }
  const DumpDifference& d = diff.value();
  if (!d) {
    fmt::print("the states are identical\n");
    return exit_code::success;
  }
  fmt::print("first difference: {}\n", *d);
  return exit_code::check_failed;
}

}  // namespace bitstep
