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
#include <cstdio>
#include <cstdlib>
#include <cstring>
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
  if (argc < 2) return fail(program + ": usage: list | run EXPERIMENT ... | hash SCENE ... | memory SCENE ...");
  const std::string_view command = argv[1];
  if (command == "list") {
    for (const Variant& v : variants) std::printf("%s\n", v.name.c_str());
    return 0;
  }
  if (argc < 3) return fail(program + ": " + std::string(command) + " needs an argument");
  const std::string target = argv[2];
  StepConfig config;
  RunOptions options;
  std::string variant_name;
  long steps = 0, from = 0;
  for (int i = 3; i < argc; ++i) {
    const std::string_view arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--variant" && has_value) {
      variant_name = argv[++i];
    } else if (arg == "--dt" && has_value) {
      config.dt = std::strtod(argv[++i], nullptr);
    } else if (arg == "--iterations" && has_value) {
      config.iterations = std::atoi(argv[++i]);
    } else if (arg == "--steps" && has_value) {
      steps = std::strtol(argv[++i], nullptr, 10);
    } else if (arg == "--from" && has_value) {
      from = std::strtol(argv[++i], nullptr, 10);
    } else if (arg == "--threads" && has_value) {
      config.threads = std::atoi(argv[++i]);
    } else if (arg == "--quick") {
      options.quick = true;
    } else if (arg == "--scenes" && has_value) {
      options.scenes_dir = argv[++i];
    } else {
      return fail(program + ": unknown option '" + std::string(arg) + "'");
    }
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
  return fail(program + ": unknown command '" + std::string(command) + "'");
}
