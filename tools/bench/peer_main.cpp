// A peer program: the benchmark's experiments on the engines compiled into
// it (Bullet, and bitstep's variants), one run per invocation, its result
// printed in the text form of tools/bench/experiments.h. bitstep bench runs
// it as a child process, so bitstep itself never links a peer engine.
//
//   PROGRAM list
//   PROGRAM run EXPERIMENT --variant NAME --dt SECONDS --iterations N [--quick] [--scenes DIR]
//   PROGRAM hash SCENE --variant NAME --steps N     final state hash, hex
//   PROGRAM memory SCENE --variant NAME --steps N   peak resident KiB after loading the scene, and after N steps
//   PROGRAM speed SCENE --variant NAME --from K --steps N [--threads T]
//                                                  CPU and wall-clock ms per step of N steps after K
#include <CLI/CLI.hpp>

#include <cstdio>
#include <string>
#include <string_view>
#include <vector>

#include "tools/bench/costs.h"
#include "tools/bench/experiments.h"
#include "tools/bench/peer.h"
#include "tools/bench/scene_specs.h"
#include "tools/bench/speed.h"

namespace {

using namespace bitstep::bench;

int fail(const std::string& message) {
  std::fprintf(stderr, "%s\n", message.c_str());
  return 2;
}

const Variant* find_variant(const std::vector<Variant>& variants, std::string_view name) {
  for (const Variant& v : variants) {
    if (v.name == name) return &v;
  }
  return nullptr;
}

}  // namespace

int main(int argc, char** argv) {
  const std::vector<Variant> variants = peer_variants();
  const std::string program = argc > 0 ? argv[0] : "peer";
  // The commands' options, on CLI11 as bitstep's own (tools/cli/options.h);
  // every command but list takes all of them and uses its own.
  CLI::App app("a peer program of bitstep bench: its experiments on the engines compiled in", program);
  app.require_subcommand(1);
  app.add_subcommand("list", "the variants, one a line");
  std::string target, variant_name;
  StepConfig config;
  RunOptions options;
  long steps = 0, from = 0;
  const auto command_with_options = [&](const char* name, const char* argument, const char* description) {
    CLI::App* command = app.add_subcommand(name, description);
    command->add_option(argument, target)->required();
    command->add_option("--variant", variant_name, "the engine's variant");
    command->add_option("--dt", config.dt, "the step, seconds");
    command->add_option("--iterations", config.iterations, "solver iterations");
    command->add_option("--steps", steps, "steps to run");
    command->add_option("--from", from, "steps before the timed ones");
    command->add_option("--threads", config.threads, "workers (1-64)");
    command->add_flag("--quick", options.quick, "the short run");
    command->add_option("--scenes", options.scenes_dir, "the scenes' folder");
  };
  command_with_options("run", "EXPERIMENT", "an experiment's result, in the text form of experiments.h");
  command_with_options("hash", "SCENE", "the final state hash after --steps, hex");
  command_with_options("memory", "SCENE", "peak resident KiB after loading the scene, and after --steps");
  command_with_options("speed", "SCENE", "CPU and wall-clock ms per step of --steps after --from");
  try {
    app.parse(argc, argv);
  } catch (const CLI::CallForHelp&) {
    std::fputs(app.help().c_str(), stdout);
    return 0;
  } catch (const CLI::ParseError& error) {
    // An unknown word is the likelier mistake than what CLI11 checks first.
    const std::vector<std::string> unknown = app.remaining();
    return fail(program + ": " + (unknown.empty() ? error.what() : CLI::ExtrasError(unknown).what()));
  }
  const std::string command = app.get_subcommands().front()->get_name();
  if (command == "list") {
    for (const Variant& v : variants) std::printf("%s\n", v.name.c_str());
    return 0;
  }
  const Variant* variant = find_variant(variants, variant_name);
  if (variant == nullptr) return fail(program + ": unknown variant '" + variant_name + "'");
  if (!(config.dt > 0) || config.iterations < 1) return fail(program + ": --dt and --iterations must be positive");
  if (config.threads < 1 || config.threads > 64) return fail(program + ": --threads 1-64");

  if (command == "run") {
    const Experiment* experiment = find_experiment(target);
    if (experiment == nullptr) return fail(program + ": unknown experiment '" + target + "'");
    std::fputs(serialize(experiment->run(*variant, config, options)).c_str(), stdout);
    return 0;
  }
  if (command == "hash" || command == "memory" || command == "speed") {
    SceneSpecs specs;
    std::string reason;
    if (!specs_from_scene_file(target, specs, reason)) return fail(program + ": " + reason);
    const long loaded_kib = peak_resident_kib();
    auto engine = variant->make(config);
    specs.add_to(*engine);
    if (command == "speed") {
      if (from < 0 || steps < 1 || from > 100000 || steps > 100000) return fail(program + ": --from 0-100000, --steps 1-100000");
      const StepTimes t = ms_per_step(*engine, static_cast<int>(from), static_cast<int>(steps));
      std::printf("%.9g %.9g\n", t.cpu, t.wall);
      return 0;
    }
    for (long s = 0; s < steps; ++s) engine->step();
    if (command == "memory") {
      std::printf("%ld %ld\n", loaded_kib, peak_resident_kib());
    } else {
      std::printf("%016llx\n", static_cast<unsigned long long>(engine->state_hash()));
    }
    return 0;
  }
  return fail(program + ": unknown command '" + command + "'");
}
