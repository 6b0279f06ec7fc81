// The shared context of `bitstep bench`'s sections (tools/bench/context.h).
#include "tools/bench/context.h"

#include <fmt/core.h>
#include <unistd.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <filesystem>

#include "tools/bench/bitstep_engine.h"
#include "tools/bench/report.h"
#include "tools/bench/scene_specs.h"

namespace bitstep::bench {

namespace {

// The program that runs the experiments on Bullet, or empty with why not.
std::string find_peer(const std::string& scenes, std::string& why_not) {
  const std::string path = executable_dir() + "/bitstep-bullet";
  if (access(path.c_str(), X_OK) != 0) {
    why_not = "Bullet comparison skipped: " + path +
              " was not built (install libbullet-dev - tools/install_deps.sh bench - and build again)";
    return {};
  }
  const std::string stale = stale_program(path, scenes);
  if (!stale.empty()) {
    why_not = "Bullet comparison skipped: " + stale;
    return {};
  }
  return path;
}

}  // namespace

double Row::ms_per_step() const {
  const double steps = std::round(result.simulated_s / dt);
  return steps > 0 ? result.wall_ms / steps : 0;
}

double Row::ms_per_simulated_s() const { return result.simulated_s > 0 ? result.wall_ms / result.simulated_s : 0; }

std::string executable_dir() {
  std::error_code error;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", error);
  return error ? std::string(".") : self.parent_path().string();
}

std::string bitstep_hash(const std::string& scene_path, int steps) {
  SceneSpecs specs;
  std::string reason;
  if (!specs_from_scene_file(scene_path, specs, reason)) return "error: " + reason;
  for (const Variant& v : bitstep_variants()) {
    if (v.name != default_variant) continue;
    auto engine = v.make(StepConfig{});
    specs.add_to(*engine);
    for (int i = 0; i < steps; ++i) engine->step();
    return fmt::format("{:016x}", engine->state_hash());
  }
  return "-";
}

// A program built beside this one is from other sources when its bitstep
// ends a short run of a moving scene on another hash: `cmake --build` of one
// target (tools/run.sh builds `bitstep` alone) leaves the others as they
// were. Timing or comparing such a program would report an old bitstep.
std::string stale_program(const std::string& program, const std::string& scenes) {
  constexpr int steps = 60;
  const std::string scene = scenes + "/" + std::string(freshness_scene);
  const std::string here = bitstep_hash(scene, steps);
  if (here.rfind("error", 0) == 0) return {};  // no scene to check with: nothing to say
  std::string there;
  const std::string command =
      fmt::format("{} hash {} --variant {} --steps {}", quote(program), quote(scene), default_variant, steps);
  if (!capture(command, there)) return program + " failed: " + command;
  while (!there.empty() && (there.back() == '\n' || there.back() == '\r')) there.pop_back();
  if (there == here) return {};
  return fmt::format(
      "{} is not built from this bitstep's sources ({} steps of {}: {} there, {} here); "
      "build every target again (cmake --build build/release)",
      program, steps, freshness_scene, there, here);
}

std::string quote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

bool capture(const std::string& command, std::string& output) {
  output.clear();
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return false;
  char buffer[4096];
  size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, n);
  return pclose(pipe) == 0;
}

std::string dt_name(double dt) { return fmt::format("1/{}", static_cast<int>(std::lround(1.0 / dt))); }

Context::Context(const Options& chosen) : options(chosen) {
  run_options.quick = options.quick;
  run_options.scenes_dir = options.scenes;
  for (const Variant& v : bitstep_variants()) variants.push_back(v.name);
  if (options.peer)
    peer = find_peer(options.scenes, peer_note);
  else peer_note = "Bullet comparison skipped (--no-peer)";
  if (!peer.empty()) variants.push_back(std::string(peer_variant));
}

std::vector<const Experiment*> Context::selected(bool sweep_only) const {
  std::vector<const Experiment*> list;
  for (const Experiment& e : experiments()) {
    if (!options.only.empty() && options.only.count(e.name) == 0) continue;
    if (sweep_only && !e.sweep) continue;
    // The 8,256-brick wall takes minutes per variant: full runs only.
    if (options.quick && options.only.empty() && e.name == "wall128") continue;
    list.push_back(&e);
  }
  return list;
}

// wall128 is by far the slowest scene a step, for up to 2,000 steps: only
// bitstep's default and Bullet run it (the others are in wall64).
std::vector<std::string> Context::variants_for(const Experiment& e) const {
  if (e.name != "wall128") return variants;
  std::vector<std::string> some;
  for (const std::string& v : variants) {
    if (v == default_variant || v == peer_variant) some.push_back(v);
  }
  return some;
}

bool Context::run_one(const Experiment& e, const std::string& variant, double dt, int iterations,
                      ExperimentResult& out) {
  progress->advance(fmt::format("{} {} dt {} it {}", e.name, variant, dt_name(dt), iterations));
  StepConfig config;
  config.dt = dt;
  config.iterations = iterations;
  if (variant != peer_variant) {
    for (const Variant& v : bitstep_variants()) {
      if (v.name == variant) {
        out = e.run(v, config, run_options);
        return true;
      }
    }
    return false;
  }
  const std::string command = fmt::format("{} run {} --variant {} --dt {:.17g} --iterations {} --scenes {}{}",
                                          quote(peer), e.name, peer_variant, dt, iterations, quote(options.scenes),
                                          options.quick ? " --quick" : "");
  std::string output, reason;
  if (!capture(command, output) || !parse_result(output, out, reason)) {
    progress->note(fmt::format("bitstep bench: {} on bullet failed: {}{}", e.name, reason, output.substr(0, 300)));
    return false;
  }
  return true;
}

bool Context::write(const std::string& name, const std::string& text) const {
  std::string reason;
  if (write_report_file(options.out, name, text, reason)) return true;
  fmt::print(stderr, "bitstep bench: {}\n", reason);
  write_failed = true;
  return false;
}

size_t variant_style(const Context& context, const std::string& variant) {
  const auto at = std::find(context.variants.begin(), context.variants.end(), variant);
  return static_cast<size_t>(at - context.variants.begin());
}

bool Context::draw(const std::string& stem, const std::string& commands) const {
  std::string reason;
  if (plot(options.out, stem, commands, reason)) return true;
  progress->note("bitstep bench: " + reason);
  return false;
}

}  // namespace bitstep::bench
