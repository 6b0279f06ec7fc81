// The six sections of `bitstep bench`. Each runs its runs, writes its CSV
// files and plots into the report folder, and returns its part of
// summary.md; each also says how many runs it plans (the progress bar's
// total). The command (tools/bench/command.cpp) runs them in this order.
#pragma once

#include <string>

#include "tools/bench/context.h"

namespace bitstep::bench {

struct Section {
  bool ok = true;        // every run and file succeeded
  std::string markdown;  // the summary's section; empty: nothing to report
};

// Every experiment at 60 Hz and 10 iterations on every variant:
// results.csv, series_<experiment>.csv, stability_<experiment>.{gp,svg,png}.
int results_runs(const Context& context);
Section run_results(Context& context);

// dt x iterations x variants for the cheap experiments, with the Pareto
// front: work_precision.csv, wp_<experiment>.csv, wp_<experiment>_front.csv,
// wp_<experiment>.{gp,svg,png}.
int sweep_runs(const Context& context);
Section run_sweep(Context& context);

// bitstep's ms/step against body count, awake and asleep: scale.csv, scale.{gp,svg,png}.
int scale_runs(const Context& context);
Section run_scale(Context& context);

// bitstep's default against the peer engine in the peer program: speed.csv.
int speed_runs(const Context& context);
Section run_speed(Context& context);

// Rollback costs and wall128's peak memory: rollback.csv, memory.csv.
int costs_runs(const Context& context);
Section run_costs(Context& context);

// Final state hashes from the peer programs built at -O0 and -O3 -ffast-math: determinism.csv.
int determinism_runs(const Context& context);
Section run_determinism(Context& context);

}  // namespace bitstep::bench
