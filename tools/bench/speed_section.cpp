// `bitstep bench`'s speed section: CPU ms/step of bitstep's default and of
// the peer engine in the standing, impact and settled phases of shipped
// scenes (tools/bench/speed.h), every run in the peer program.
#include <fmt/core.h>

#include <algorithm>
#include <cstdio>
#include <cstring>

#include "tools/bench/sections.h"
#include "tools/bench/speed.h"

namespace bitstep::bench {

namespace {

int speed_rounds(const Context& context) { return context.options.quick ? 3 : 7; }

// One round of one case: run 0 is bitstep, 1 the peer engine, 2 bitstep on
// the threaded column's workers. False (said on stderr) when it fails.
bool time_run(Context& context, SpeedRow& row, int run) {
  const std::string_view variant = run == 1 ? peer_variant : default_variant;
  const int threads = run == 2 ? context.options.threads : 1;
  context.progress->advance(fmt::format("speed {} {} {} on {}", row.c.scene, row.c.phase, variant, threads));
  std::string output;
  const std::string command =
      fmt::format("{} speed {} --variant {} --from {} --steps {} --threads {}", quote(context.peer),
                  quote(context.options.scenes + "/" + row.c.scene), variant, row.c.from_step, row.c.steps, threads);
  double cpu = 0, wall = 0;
  if (!capture(command, output) || std::sscanf(output.c_str(), "%lf %lf", &cpu, &wall) != 2) {
    fmt::print(stderr, "bitstep bench: speed {} {}: {}\n", row.c.scene, variant, output);
    return false;
  }
  if (run == 0) {
    row.bitstep_ms.push_back(cpu);
    row.one_thread_wall_ms.push_back(wall);
  } else if (run == 1) {
    row.bullet_ms.push_back(cpu);
  } else {
    row.threads_wall_ms.push_back(wall);
  }
  return true;
}

// Every case, bitstep's default then Bullet in each round, in the peer
// program (so both are the same build). False at the first failed run.
bool time_rounds(Context& context, std::vector<SpeedRow>& speed) {
  for (int round = 0; round < speed_rounds(context); ++round) {
    for (SpeedRow& row : speed) {
      for (const int run : {0, 1, 2}) {
        if (!time_run(context, row, run)) return false;
      }
    }
  }
  return true;
}

bool have_valgrind() {
  std::string where;
  return capture("command -v valgrind", where) && !where.empty();
}

// The instructions per timed step of one engine on one thread, counted by
// callgrind (collecting only around the timed steps: ms_per_step); false
// (said on stderr) when the run fails.
bool count_instructions(Context& context, const SpeedRow& row, std::string_view variant, double& out) {
  context.progress->advance(fmt::format("instructions {} {} {}", row.c.scene, row.c.phase, variant));
  const std::string command = fmt::format(
      "valgrind --tool=callgrind --collect-atstart=no --callgrind-out-file=/dev/null {} speed {} "
      "--variant {} --from {} --steps {} --threads 1",
      quote(context.peer), quote(context.options.scenes + "/" + row.c.scene), variant, row.c.from_step, row.c.steps);
  std::string output;
  const char* const label = "Collected : ";
  const size_t at = capture(command, output) ? output.find(label) : std::string::npos;
  unsigned long long collected = 0;
  if (at == std::string::npos || std::sscanf(output.c_str() + at + std::strlen(label), "%llu", &collected) != 1) {
    fmt::print(stderr, "bitstep bench: instructions {} {}: {}\n", row.c.scene, variant, output.substr(0, 300));
    return false;
  }
  out = static_cast<double>(collected) / std::max(row.c.steps, 1);
  return true;
}

bool count_all_instructions(Context& context, std::vector<SpeedRow>& speed) {
  for (SpeedRow& row : speed) {
    if (!count_instructions(context, row, default_variant, row.bitstep_instructions) ||
        !count_instructions(context, row, peer_variant, row.bullet_instructions)) {
      return false;
    }
  }
  return true;
}

}  // namespace

int speed_runs(const Context& context) {
  if (context.peer.empty()) return 0;
  const int counts = have_valgrind() ? 2 : 0;
  return static_cast<int>(speed_cases().size()) * (speed_rounds(context) * 3 + counts);
}

Section run_speed(Context& context) {
  Section section;
  if (context.peer.empty()) return section;
  std::vector<SpeedRow> speed;
  for (const SpeedCase& c : speed_cases()) speed.push_back({c, {}, {}, {}, {}});
  section.ok = time_rounds(context, speed);
  if (!have_valgrind()) {
    context.progress->note("speed: instruction counts skipped: valgrind was not found (tools/install_deps.sh bench)");
  } else {
    section.ok = count_all_instructions(context, speed) && section.ok;
  }
  section.ok = context.write("speed.csv", speed_csv(speed, context.options.threads)) && section.ok;
  if (!speed.empty()) {
    section.markdown = speed_section(speed, std::string(default_variant), context.options.threads);
  }
  return section;
}

}  // namespace bitstep::bench
