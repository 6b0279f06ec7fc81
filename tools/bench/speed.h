// `bitstep bench`'s speed section: bitstep's default variant against Bullet
// in the phases a game meets (a structure standing, a pile during its impact
// and once settled), as CPU time per step. Each engine runs in the peer
// program, a process of its own per round; the rounds alternate the engines
// so that both meet the same load on a shared machine, and the table keeps
// the median of each.
#pragma once

#include <string>
#include <vector>

#include "tools/bench/engine.h"

namespace bitstep::bench {

struct SpeedCase {
  std::string scene;  // file name in the scenes folder
  std::string phase;  // what the timed steps show
  int from_step = 0;  // steps run before the timing starts
  int steps = 0;      // steps timed
};

const std::vector<SpeedCase>& speed_cases();

// Steps `from_step` times, then returns the process CPU time (all threads)
// and the wall-clock time per step (ms) of the next `steps` steps.
struct StepTimes {
  double cpu = 0, wall = 0;
};
StepTimes ms_per_step(Engine& engine, int from_step, int steps);

struct SpeedRow {
  SpeedCase c;
  // One per round: CPU ms/step of bitstep and Bullet on one thread; wall
  // ms/step of bitstep on one thread and on the threaded column's workers.
  std::vector<double> bitstep_ms, bullet_ms, one_thread_wall_ms, threads_wall_ms;
  // Instructions per timed step on one thread, counted once by callgrind;
  // 0 when not counted (no valgrind).
  double bitstep_instructions = 0, bullet_instructions = 0;
};

double median(std::vector<double> values);
// `threads`: the workers of the threaded column (bitstep bench --threads).
std::string speed_csv(const std::vector<SpeedRow>& rows, int threads);
// The summary's section: a table of medians and bitstep / Bullet ratios.
std::string speed_section(const std::vector<SpeedRow>& rows, const std::string& bitstep_variant, int threads);

}  // namespace bitstep::bench
