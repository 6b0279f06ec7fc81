// The benchmark's experiments: accuracy against analytic answers and
// stability on hard cases, each written once against tools/bench/engine.h
// so bitstep and a peer engine are measured by the same code.
#pragma once

#include <string>
#include <utility>
#include <vector>

#include "tools/bench/engine.h"

namespace bitstep::bench {

struct ExperimentResult {
  double error = 0;        // the experiment's error metric (Experiment::error_label), >= 0
  bool failed = false;     // the structure fell or the answer is meaningless (error says how far)
  double wall_ms = 0;      // wall-clock time spent inside Engine::step
  double simulated_s = 0;  // simulated time stepped
  std::vector<std::pair<std::string, double>> metrics;  // further named figures
  std::vector<std::string> columns;                     // time series: column names ("t" first)
  std::vector<std::vector<double>> rows;
};

struct RunOptions {
  bool quick = false;             // shorter runs
  std::string scenes_dir = "scenes";
};

struct Experiment {
  std::string name;
  std::string group;        // "accuracy" or "stability"
  std::string error_label;  // what `error` measures, with its unit
  std::string description;
  bool sweep = false;       // part of the dt x iterations work-precision sweep
  ExperimentResult (*run)(const Variant& variant, const StepConfig& config, const RunOptions& options);
};

const std::vector<Experiment>& experiments();
const Experiment* find_experiment(const std::string& name);

// A result as text lines (the peer programs print it, bitstep bench reads it)
// and back; parse returns false on any malformed line.
std::string serialize(const ExperimentResult& result);
bool parse_result(const std::string& text, ExperimentResult& result, std::string& reason);

}  // namespace bitstep::bench
