#include "tools/bench_speed.h"

#include <algorithm>
#include <cstdio>
#include <ctime>

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

}  // namespace

// At 60 Hz: structures timed after their first second (every contact
// found, the loads settled in); thrown's 75 bodies during the impact (its
// first second) and after 10 s, the playground after 10 s.
const std::vector<SpeedCase>& speed_cases() {
  static const std::vector<SpeedCase> cases = {
      {"stack20.json", "standing", 60, 240},  {"pyramid20.json", "standing", 60, 120},
      {"wall64.json", "standing", 60, 20},    {"thrown.json", "impact", 0, 60},
      {"thrown.json", "settled", 600, 120},   {"playground.json", "settled", 600, 60},
  };
  return cases;
}

double cpu_ms_per_step(Engine& engine, int from_step, int steps) {
  for (int i = 0; i < from_step; ++i) engine.step();
  const double start = cpu_ms();
  for (int i = 0; i < steps; ++i) engine.step();
  return (cpu_ms() - start) / std::max(steps, 1);
}

double median(std::vector<double> values) {
  if (values.empty()) return 0;
  std::sort(values.begin(), values.end());
  const size_t n = values.size();
  return n % 2 == 1 ? values[n / 2] : (values[n / 2 - 1] + values[n / 2]) / 2;
}

std::string speed_csv(const std::vector<SpeedRow>& rows) {
  std::string csv = "scene,phase,from_step,steps,round,bitstep_cpu_ms_per_step,bullet_cpu_ms_per_step\n";
  for (const SpeedRow& r : rows) {
    for (size_t k = 0; k < r.bitstep_ms.size(); ++k) {
      csv += r.c.scene + "," + r.c.phase + "," + std::to_string(r.c.from_step) + "," + std::to_string(r.c.steps) +
             "," + std::to_string(k + 1) + format(",%.6g", r.bitstep_ms[k]) +
             format(",%.6g\n", k < r.bullet_ms.size() ? r.bullet_ms[k] : 0.0);
    }
  }
  return csv;
}

std::string speed_section(const std::vector<SpeedRow>& rows, const std::string& bitstep_variant) {
  const size_t rounds = rows.empty() ? 0 : rows.front().bitstep_ms.size();
  std::string md = "## Speed against Bullet\n\nCPU ms per step at 60 Hz, 10 iterations, one thread: bitstep's `" +
                   bitstep_variant + "` and Bullet, each in a process of its own, median of " +
                   std::to_string(rounds) +
                   " alternating rounds (speed.csv has every round). Instruction counts need hardware "
                   "counters, which this machine does not offer.\n\n"
                   "| scene | phase | steps timed | bitstep ms/step | Bullet ms/step | bitstep / Bullet |\n"
                   "|---|---|---:|---:|---:|---:|\n";
  for (const SpeedRow& r : rows) {
    const double ours = median(r.bitstep_ms), theirs = median(r.bullet_ms);
    md += "| " + r.c.scene + " | " + r.c.phase + " | " + std::to_string(r.c.from_step) + "-" +
          std::to_string(r.c.from_step + r.c.steps) + format(" | %.3g | %.3g | ", ours, theirs) +
          (theirs > 0 ? format("%.2fx |\n", ours / theirs) : std::string("- |\n"));
  }
  return md + "\n";
}

}  // namespace bitstep::bench
