#include "tools/bench/speed.h"

#include <algorithm>
#include <chrono>
#include <cstdio>
#include <ctime>

// Under callgrind (`valgrind --tool=callgrind --collect-atstart=no`) only
// the timed steps are counted: the bench's instruction counts. Outside
// valgrind the requests are a few no-op instructions.
#if __has_include(<valgrind/callgrind.h>)
#include <valgrind/callgrind.h>
#define BITSTEP_COUNT_INSTRUCTIONS() CALLGRIND_TOGGLE_COLLECT
#else
#define BITSTEP_COUNT_INSTRUCTIONS() \
  do {                               \
  } while (false)
#endif

namespace bitstep::bench {

namespace {

double cpu_ms() {
  timespec t{};
  clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &t);
  return static_cast<double>(t.tv_sec) * 1e3 + static_cast<double>(t.tv_nsec) * 1e-6;
}

std::string format(const char* pattern, double a, double b = 0, double c = 0) {
  char buffer[128];
  std::snprintf(buffer, sizeof buffer, pattern, a, b, c);
  return buffer;
}

// "2.70M / 1.45M (1.86x) | ", or "- | " when not counted.
std::string instructions_cell(double ours, double theirs) {
  if (ours <= 0 || theirs <= 0) return "- | ";
  return format("%.3gM / %.3gM (%.2fx) | ", ours * 1e-6, theirs * 1e-6, ours / theirs);
}

}  // namespace

// At 60 Hz: structures timed after their first second (every contact
// found, the loads settled in); thrown's 75 bodies during the impact (its
// first second) and after 10 s, the playground after 10 s.
const std::vector<SpeedCase>& speed_cases() {
  static const std::vector<SpeedCase> cases = {
      {"stack20.json", "standing", 60, 240},      {"pyramid20.json", "standing", 60, 120},
      {"wall64.json", "standing", 60, 20},        {"thrown.json", "impact", 0, 60},
      {"thrown.json", "settled", 600, 120},       {"playground.json", "settled", 600, 60},
      {"knocked20.json", "knocked over", 0, 120}, {"dice.json", "tumbling", 0, 120},
  };
  return cases;
}

StepTimes ms_per_step(Engine& engine, int from_step, int steps) {
  for (int i = 0; i < from_step; ++i) engine.step();
  const double cpu_start = cpu_ms();
  const auto wall_start = std::chrono::steady_clock::now();
  BITSTEP_COUNT_INSTRUCTIONS();
  for (int i = 0; i < steps; ++i) engine.step();
  BITSTEP_COUNT_INSTRUCTIONS();
  const double wall = std::chrono::duration<double, std::milli>(std::chrono::steady_clock::now() - wall_start).count();
  const double n = std::max(steps, 1);
  return {(cpu_ms() - cpu_start) / n, wall / n};
}

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
}

std::string speed_csv(const std::vector<SpeedRow>& rows, int threads) {
  std::string csv =
      "scene,phase,from_step,steps,round,bitstep_cpu_ms_per_step,bullet_cpu_ms_per_step,bitstep_wall_ms_per_step,"
      "bitstep_" +
      std::to_string(threads) +
      "_threads_wall_ms_per_step,bitstep_instructions_per_step,"
      "bullet_instructions_per_step\n";
  const auto at = [](const std::vector<double>& v, size_t k) { return k < v.size() ? v[k] : 0.0; };
  for (const SpeedRow& r : rows) {
    for (size_t k = 0; k < r.bitstep_ms.size(); ++k) {
      csv += r.c.scene + "," + r.c.phase + "," + std::to_string(r.c.from_step) + "," + std::to_string(r.c.steps) + "," +
             std::to_string(k + 1) + format(",%.6g", r.bitstep_ms[k]) + format(",%.6g", at(r.bullet_ms, k)) +
             format(",%.6g,%.6g", at(r.one_thread_wall_ms, k), at(r.threads_wall_ms, k)) +
             format(",%.0f,%.0f\n", r.bitstep_instructions, r.bullet_instructions);
    }
  }
  return csv;
}

std::string speed_section(const std::vector<SpeedRow>& rows, const std::string& bitstep_variant, int threads) {
  const size_t rounds = rows.empty() ? 0 : rows.front().bitstep_ms.size();
  std::string md = "## Speed against Bullet\n\nCPU ms per step at 60 Hz, 10 iterations, one thread: bitstep's `" +
                   bitstep_variant + "` and Bullet, each in a process of its own, median of " + std::to_string(rounds) +
                   " alternating rounds (speed.csv has every round); beside them the instructions per "
                   "timed step, counted once by callgrind (the same on any x86-64 machine for these "
                   "binaries; time ratios depend on the CPU, and this one has no hardware counters). The "
                   "last two columns: bitstep's wall-clock "
                   "ms per step on " +
                   std::to_string(threads) +
                   " workers (`--threads`), the same bits, and its speed-up over one thread's wall clock; "
                   "below 64 manifolds, or where contact order is not local (a pile whose slots are "
                   "scattered), the sweeps stay on one thread.\n\n"
                   "| scene | phase | steps timed | bitstep ms/step | Bullet ms/step | bitstep / Bullet | "
                   "instructions/step, bitstep / Bullet | " +
                   std::to_string(threads) +
                   " threads ms/step | speed-up |\n"
                   "|---|---|---:|---:|---:|---:|---:|---:|---:|\n";
  for (const SpeedRow& r : rows) {
    const double ours = median(r.bitstep_ms), theirs = median(r.bullet_ms);
    const double one = median(r.one_thread_wall_ms), shared = median(r.threads_wall_ms);
    md += "| " + r.c.scene + " | " + r.c.phase + " | " + std::to_string(r.c.from_step) + "-" +
          std::to_string(r.c.from_step + r.c.steps) + format(" | %.3g | %.3g | ", ours, theirs) +
          (theirs > 0 ? format("%.2fx | ", ours / theirs) : std::string("- | ")) +
          instructions_cell(r.bitstep_instructions, r.bullet_instructions) +
          (shared > 0 ? format("%.3g | %.2fx |\n", shared, one / shared) : std::string("- | - |\n"));
  }
  return md + "\n";
}

}  // namespace bitstep::bench
