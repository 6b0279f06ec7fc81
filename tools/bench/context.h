// What every section of `bitstep bench` shares: the options, the variants
// run (bitstep's five and the peer engine's when its program was built),
// the peer program's path, the progress bar, one experiment run (here or in
// the peer program), and writing a report file or drawing a gnuplot plot.
#pragma once

#include <cstddef>
#include <set>
#include <string>
#include <string_view>
#include <vector>

#include "tools/bench/experiments.h"
#include "tools/cli/progress_bar.h"

namespace bitstep::bench {

inline constexpr std::string_view peer_variant = "bullet";
inline constexpr std::string_view default_variant = "standard+shock";  // bitstep's default settings

struct Options {
  bool quick = false;
  std::string out = "bench-report";
  std::string scenes = "scenes";
  std::set<std::string> sections{"results", "sweep", "scale", "speed", "costs", "determinism"};
  std::set<std::string> only;  // experiments; empty: all
  bool peer = true;
  int threads = 2;  // the speed section's threaded column
  std::string readme;  // a README whose headline table the run rewrites; empty: none
};

// One experiment run at one dt and iteration count.
struct Row {
  std::string experiment;
  std::string variant;
  double dt = 0;
  int iterations = 0;
  ExperimentResult result;
  bool on_front = false;  // on the work-precision sweep's Pareto front

  double ms_per_step() const;
  double ms_per_simulated_s() const;
};

// The folder of the running program (the peer programs are built beside it).
std::string executable_dir();
// The final state hash of bitstep's default variant after `steps` steps of a
// scene file, hex ("error: ..." when the scene cannot be read).
std::string bitstep_hash(const std::string& scene_path, int steps);
// The scene a peer program's freshness is checked on: it moves from the start.
inline constexpr std::string_view freshness_scene = "thrown.json";
// Empty when `program` (built beside this one) runs this bitstep's sources;
// otherwise why not, in one line.
std::string stale_program(const std::string& program, const std::string& scenes);
// 'text' for /bin/sh.
std::string quote(const std::string& text);
// Runs a command and returns its output (stdout and stderr); false when it fails.
bool capture(const std::string& command, std::string& output);
// "1/60".
std::string dt_name(double dt);

struct Context;

// A variant's place among the variants run: its colour and marker in every plot.
size_t variant_style(const Context& context, const std::string& variant);

struct Context {
  explicit Context(const Options& options);

  bool wants(const std::string& section) const { return options.sections.count(section) != 0; }
  // The experiments chosen (--only; wall128 in full runs only); `sweep_only`:
  // those of the work-precision sweep.
  std::vector<const Experiment*> selected(bool sweep_only) const;
  // The variants an experiment runs on (wall128: bitstep's default and the peer).
  std::vector<std::string> variants_for(const Experiment& e) const;
  // One experiment run, in this process or in the peer program.
  bool run_one(const Experiment& e, const std::string& variant, double dt, int iterations, ExperimentResult& out);
  // Writes out/<name>; false (said on stderr) when it cannot.
  bool write(const std::string& name, const std::string& text) const;
  // Draws out/<stem>.svg and .png from gnuplot commands; false (noted) when it cannot.
  bool draw(const std::string& stem, const std::string& commands) const;

  Options options;
  RunOptions run_options;
  std::vector<std::string> variants;
  std::string peer, peer_note;  // the peer program, or why there is none
  bool plots = false;           // gnuplot was found
  mutable bool write_failed = false;  // a report file could not be written
  ProgressBar* progress = nullptr;
};

}  // namespace bitstep::bench
