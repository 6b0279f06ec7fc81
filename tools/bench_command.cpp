// `bitstep bench`: the suite that reports speed against error.
//
//   results      every experiment at 60 Hz and 10 iterations, on each of
//                bitstep's four variants and on Bullet (when its peer program
//                was built): the error, ms/step, the stability time series;
//   sweep        the work-precision sweep: dt x iterations x variants for
//                the cheap experiments, error against ms per simulated
//                second, with the Pareto front marked;
//   scale        ms/step against body count, awake and asleep, with the
//                exponent of a power-law fit;
//   speed        CPU ms/step of bitstep's default and Bullet in standing,
//                impact and settled phases of shipped scenes, and the ratio;
//   costs        an 8-frame rollback's cost and wall128's peak memory;
//   determinism  the final state hash of bitstep and Bullet from the peer
//                programs built at -O0 and at -O3 -ffast-math.
// Everything goes into a report directory: CSV per experiment, summary.md,
// and a gnuplot script per plot drawn as SVG and PNG.
#include "tools/bench_command.h"

#include <fmt/core.h>
#include <unistd.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <cstdio>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <map>
#include <set>
#include <sstream>
#include <string>
#include <string_view>
#include <vector>

#include "tools/bench_bitstep_engine.h"
#include "tools/bench_experiments.h"
#include "tools/bench_report.h"
#include "tools/bench_costs.h"
#include "tools/bench_scale.h"
#include "tools/bench_stats.h"
#include "tools/bench_scene_specs.h"
#include "tools/bench_speed.h"
#include "tools/exit_codes.h"
#include "tools/thread_option.h"
#include "tools/progress_bar.h"

namespace bitstep {

namespace {

using namespace bitstep::bench;

constexpr std::string_view peer_variant = "bullet";
constexpr std::string_view default_variant = "standard+shock";  // bitstep's default settings

struct Options {
  bool quick = false;
  std::string out = "bench-report";
  std::string scenes = "scenes";
  std::set<std::string> sections{"results", "sweep", "scale", "speed", "costs", "determinism"};
  std::set<std::string> only;  // experiments; empty: all
  bool peer = true;
  int threads = 2;  // the speed section's threaded column
};

struct Row {
  std::string experiment;
  std::string variant;
  double dt = 0;
  int iterations = 0;
  ExperimentResult result;
  bool on_front = false;
};

std::string executable_dir() {
  std::error_code error;
  const auto self = std::filesystem::read_symlink("/proc/self/exe", error);
  return error ? std::string(".") : self.parent_path().string();
}

std::string quote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) quoted += c == '\'' ? std::string("'\\''") : std::string(1, c);
  return quoted + "'";
}

// Runs a command and returns its standard output; false when it fails.
bool capture(const std::string& command, std::string& output) {
  output.clear();
  FILE* pipe = popen((command + " 2>&1").c_str(), "r");
  if (pipe == nullptr) return false;
  char buffer[4096];
  size_t n = 0;
  while ((n = std::fread(buffer, 1, sizeof buffer, pipe)) > 0) output.append(buffer, n);
  return pclose(pipe) == 0;
}

// The program that runs the experiments on Bullet, or empty with why not.
std::string find_peer(std::string& why_not) {
  const std::string path = executable_dir() + "/bitstep-bullet";
  if (access(path.c_str(), X_OK) != 0) {
    why_not = "Bullet comparison skipped: " + path +
              " was not built (install libbullet-dev - tools/install_deps.sh bench - and build again)";
    return {};
  }
  return path;
}

std::string dt_name(double dt) { return fmt::format("1/{}", static_cast<int>(std::lround(1.0 / dt))); }

class Bench {
 public:
  explicit Bench(const Options& options) : options_(options) {
    run_options_.quick = options.quick;
    run_options_.scenes_dir = options.scenes;
    for (const Variant& v : bitstep_variants()) variants_.push_back(v.name);
    if (options.peer) peer_ = find_peer(peer_note_);
    else peer_note_ = "Bullet comparison skipped (--no-peer)";
    if (!peer_.empty()) variants_.push_back(std::string(peer_variant));
  }

  int run() {
    std::error_code error;
    std::filesystem::create_directories(options_.out, error);
    if (error) {
      fmt::print(stderr, "bitstep bench: cannot create {}: {}\n", options_.out, error.message());
      return exit_code::output_failed;
    }
    plots_ = gnuplot_available();
    ProgressBar progress(planned_runs());
    progress_ = &progress;
    if (!peer_note_.empty()) progress.note(peer_note_);
    if (!plots_) progress.note("plots skipped: gnuplot not found (tools/install_deps.sh bench installs gnuplot-nox)");
    const auto start = std::chrono::steady_clock::now();
    bool ok = true;
    if (wants("results")) ok = run_results() && ok;
    if (wants("sweep")) ok = run_sweep() && ok;
    if (wants("scale")) ok = run_scale() && ok;
    if (wants("speed")) ok = run_speed() && ok;
    if (wants("costs")) ok = run_costs() && ok;
    if (wants("determinism")) ok = run_determinism() && ok;
    const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
    progress.finish();
    ok = write_summary(elapsed.count()) && ok;
    if (write_failed_) return exit_code::output_failed;  // its line was printed
    fmt::print("report: {}/summary.md ({:.0f} s)\n", options_.out, elapsed.count());
    return ok ? exit_code::success : exit_code::check_failed;
  }

 private:
  bool wants(const std::string& section) const { return options_.sections.count(section) != 0; }

  std::vector<const Experiment*> selected(bool sweep_only) const {
    std::vector<const Experiment*> list;
    for (const Experiment& e : experiments()) {
      if (!options_.only.empty() && options_.only.count(e.name) == 0) continue;
      if (sweep_only && !e.sweep) continue;
      // The 8,256-brick wall takes minutes per variant: full runs only.
      if (options_.quick && options_.only.empty() && e.name == "wall128") continue;
      list.push_back(&e);
    }
    return list;
  }

  // wall128 takes ~0.24 s a step for up to 2,000 steps: only bitstep's
  // default and Bullet run it (the others are in wall64).
  std::vector<std::string> variants_for(const Experiment& e) const {
    if (e.name != "wall128") return variants_;
    std::vector<std::string> some;
    for (const std::string& v : variants_) {
      if (v == default_variant || v == peer_variant) some.push_back(v);
    }
    return some;
  }

  std::vector<double> sweep_dts() const { return {1.0 / 30, 1.0 / 60, 1.0 / 120, 1.0 / 240}; }
  std::vector<int> sweep_iterations() const {
    if (options_.quick) return {1, 4, 16};
    return {1, 2, 4, 8, 16, 32};
  }

  int planned_runs() const {
    int runs = 0;
    const int variants = static_cast<int>(variants_.size());
    if (wants("results")) {
      for (const Experiment* e : selected(false)) runs += static_cast<int>(variants_for(*e).size());
    }
    if (wants("sweep")) {
      runs += static_cast<int>(selected(true).size() * sweep_dts().size() * sweep_iterations().size()) * variants;
    }
    if (wants("scale")) runs += static_cast<int>(scale_sizes(options_.quick).size()) * 4;
    if (wants("speed") && !peer_.empty()) runs += static_cast<int>(speed_cases().size()) * speed_rounds() * 3;
    if (wants("costs")) runs += static_cast<int>(rollback_scenes().size()) + (peer_.empty() ? 0 : 2);
    if (wants("determinism")) runs += 1;
    return runs;
  }

  // One experiment run, in this process or in the peer program.
  bool run_one(const Experiment& e, const std::string& variant, double dt, int iterations, ExperimentResult& out) {
    progress_->advance(fmt::format("{} {} dt {} it {}", e.name, variant, dt_name(dt), iterations));
    StepConfig config;
    config.dt = dt;
    config.iterations = iterations;
    if (variant != peer_variant) {
      for (const Variant& v : bitstep_variants()) {
        if (v.name == variant) {
          out = e.run(v, config, run_options_);
          return true;
        }
      }
      return false;
    }
    const std::string command = fmt::format("{} run {} --variant {} --dt {:.17g} --iterations {} --scenes {}{}",
                                            quote(peer_), e.name, peer_variant, dt, iterations,
                                            quote(options_.scenes), options_.quick ? " --quick" : "");
    std::string output, reason;
    if (!capture(command, output) || !parse_result(output, out, reason)) {
      progress_->note(fmt::format("bitstep bench: {} on bullet failed: {}{}", e.name, reason,
                                  output.substr(0, 300)));
      return false;
    }
    return true;
  }

  // --- results -----------------------------------------------------------------

  bool run_results() {
    bool ok = true;
    for (const Experiment* e : selected(false)) {
      std::vector<Row> rows;
      for (const std::string& variant : variants_for(*e)) {
        Row row{e->name, variant, 1.0 / 60, 10, {}, false};
        if (!run_one(*e, variant, row.dt, row.iterations, row.result)) {
          ok = false;
          continue;
        }
        rows.push_back(row);
      }
      if (!rows.empty() && !rows.front().result.columns.empty()) ok = write_series(*e, rows) && ok;
      results_.insert(results_.end(), rows.begin(), rows.end());
    }
    std::string csv = "experiment,group,variant,dt,iterations,error,failed,ms_per_step,ms_per_simulated_s,metrics\n";
    for (const Row& r : results_) {
      const Experiment* e = find_experiment(r.experiment);
      std::string metrics;
      for (const auto& [name, value] : r.result.metrics) metrics += fmt::format("{}{}={:.6g}", metrics.empty() ? "" : " ", name, value);
      csv += fmt::format("{},{},{},{:.17g},{},{:.6g},{},{:.6g},{:.6g},{}\n", r.experiment, e->group, r.variant, r.dt,
                         r.iterations, r.result.error, r.result.failed ? 1 : 0, ms_per_step(r),
                         ms_per_second(r.result), csv_field(metrics));
    }
    return write("results.csv", csv) && ok;
  }

  static double ms_per_step(const Row& r) {
    const double steps = std::round(r.result.simulated_s / r.dt);
    return steps > 0 ? r.result.wall_ms / steps : 0;
  }
  static double ms_per_second(const ExperimentResult& r) { return r.simulated_s > 0 ? r.wall_ms / r.simulated_s : 0; }

  // series_<experiment>.csv: every variant's time series; a plot of the drift.
  bool write_series(const Experiment& e, const std::vector<Row>& rows) {
    std::string csv = "variant";
    for (const std::string& c : rows.front().result.columns) csv += "," + c;
    csv += "\n";
    for (const Row& r : rows) {
      for (const auto& values : r.result.rows) {
        csv += r.variant;
        for (double v : values) csv += fmt::format(",{:.6g}", v);
        csv += "\n";
      }
    }
    const std::string file = "series_" + e.name + ".csv";
    if (!write(file, csv)) return false;
    if (!plots_) return true;
    std::string lines;
    for (const Row& r : rows) {
      lines += fmt::format("{}'{}' using (strcol(1) eq '{}' ? $2 : NaN):(max($3, 1e-6)) with lines lw 2 title '{}'",
                           lines.empty() ? "plot " : ", \\\n     ", file, r.variant, r.variant);
    }
    const std::string commands = fmt::format(
        "max(a, b) = a > b ? a : b\n"
        "set title '{}: {} (60 Hz, 10 iterations)' noenhanced\n"
        "set xlabel 'simulated time (s)'\nset ylabel 'largest drift of any body from its start (m)'\n"
        "set logscale y\nset format y '10^{{%L}}'\nset key left top noenhanced\nset grid\n"
        "set label 1 'drift below 1 um is drawn at 1 um' at graph 0.98, graph 0.04 right font ',9'\n{}",
        e.name, e.description, lines);
    return draw("stability_" + e.name, commands);
  }

  // --- sweep ---------------------------------------------------------------------

  bool run_sweep() {
    bool ok = true;
    for (const Experiment* e : selected(true)) {
      std::vector<Row> rows;
      for (const std::string& variant : variants_) {
        for (double dt : sweep_dts()) {
          for (int iterations : sweep_iterations()) {
            Row row{e->name, variant, dt, iterations, {}, false};
            if (!run_one(*e, variant, dt, iterations, row.result)) {
              ok = false;
              continue;
            }
            rows.push_back(row);
          }
        }
      }
      std::vector<CostError> points;
      for (const Row& r : rows) points.push_back({ms_per_second(r.result), r.result.error});
      const std::vector<bool> front = pareto_front(points);
      for (size_t i = 0; i < rows.size(); ++i) rows[i].on_front = front[i];
      ok = write_sweep_plot(*e, rows) && ok;
      sweep_.insert(sweep_.end(), rows.begin(), rows.end());
    }
    std::string csv = "experiment,variant,dt,iterations,error,failed,ms_per_simulated_s,pareto\n";
    for (const Row& r : sweep_) {
      csv += fmt::format("{},{},{},{},{:.6g},{},{:.6g},{}\n", r.experiment, r.variant, dt_name(r.dt), r.iterations,
                         r.result.error, r.result.failed ? 1 : 0, ms_per_second(r.result), r.on_front ? 1 : 0);
    }
    return write("work_precision.csv", csv) && ok;
  }

  bool write_sweep_plot(const Experiment& e, const std::vector<Row>& rows) {
    std::string csv = "variant,dt,iterations,ms_per_simulated_s,error,pareto\n";
    std::vector<const Row*> front;
    for (const Row& r : rows) {
      csv += fmt::format("{},{},{},{:.6g},{:.6g},{}\n", r.variant, dt_name(r.dt), r.iterations,
                         ms_per_second(r.result), r.result.error, r.on_front ? 1 : 0);
      if (r.on_front) front.push_back(&r);
    }
    std::sort(front.begin(), front.end(),
              [](const Row* a, const Row* b) { return ms_per_second(a->result) < ms_per_second(b->result); });
    std::string front_csv = "ms_per_simulated_s,error,label\n";
    for (const Row* r : front) {
      front_csv += fmt::format("{:.6g},{:.6g},{} {} it {}\n", ms_per_second(r->result), r->result.error, r->variant,
                               dt_name(r->dt), r->iterations);
    }
    const std::string file = "wp_" + e.name + ".csv", front_file = "wp_" + e.name + "_front.csv";
    if (!write(file, csv) || !write(front_file, front_csv)) return false;
    if (!plots_) return true;
    std::string lines;
    int point_type = 5;
    for (const std::string& variant : variants_) {
      lines += fmt::format("{}'{}' using (strcol(1) eq '{}' ? $4 : NaN):(max($5, floor_error)) with points pt {} ps 1.2 title '{}'",
                           lines.empty() ? "plot " : ", \\\n     ", file, variant, point_type++, variant);
    }
    lines += fmt::format(", \\\n     '{0}' using 1:(max($2, floor_error)) with lines lw 2 lc 'black' title 'Pareto front', \\\n"
                         "     '{0}' using 1:(max($2, floor_error)):3 with labels left offset 0.6,0.3 font ',7' notitle",
                         front_file);
    const std::string commands = fmt::format(
        "max(a, b) = a > b ? a : b\nfloor_error = 1e-12\n"
        "set title '{}: {}' noenhanced\n"
        "set xlabel 'cost: wall-clock ms per simulated second'\nset ylabel 'error: {}'\n"
        "set logscale xy\nset format y '10^{{%L}}'\nset key outside right noenhanced\nset grid\n"
        "set label 1 'dt in {{1/30 .. 1/240}} x iterations in {{{}}}; errors below 1e-12 drawn at 1e-12' at graph 0, graph -0.13 font ',9'\n"
        "set bmargin 6\n{}",
        e.name, e.description, e.error_label, iterations_text(), lines);
    return draw("wp_" + e.name, commands);
  }

  std::string iterations_text() const {
    std::string text;
    for (int i : sweep_iterations()) text += (text.empty() ? "" : ", ") + std::to_string(i);
    return text;
  }

  // --- scale ---------------------------------------------------------------------

  bool run_scale() {
    for (const char* structure : {"pyramid", "columns"}) {
      for (bool asleep : {false, true}) {
        for (int n : scale_sizes(options_.quick)) {
          progress_->advance(fmt::format("scale {} {} {}", structure, asleep ? "asleep" : "awake", n));
          scale_.push_back(measure_scale(structure, n, asleep));
        }
      }
    }
    std::string csv = "structure,state,bodies,steps_timed,ms_per_step,stayed_asleep\n";
    for (const ScaleRow& r : scale_) {
      csv += fmt::format("{},{},{},{},{:.6g},{}\n", r.structure, r.asleep ? "asleep" : "awake", r.bodies, r.steps,
                         r.ms_per_step, r.stayed_asleep ? 1 : 0);
    }
    if (!write("scale.csv", csv)) return false;
    if (!plots_) return true;
    std::string lines;
    for (const char* structure : {"pyramid", "columns"}) {
      for (const char* state : {"awake", "asleep"}) {
        lines += fmt::format(
            "{}'scale.csv' using (strcol(1) eq '{}' && strcol(2) eq '{}' ? $3 : NaN):5 with linespoints lw 2 title '{} {}'",
            lines.empty() ? "plot " : ", \\\n     ", structure, state, structure, state);
      }
    }
    return draw("scale", "set title 'bitstep ms/step against body count (60 Hz, 10 iterations)'\n"
                         "set xlabel 'dynamic bodies'\nset ylabel 'ms per step'\nset logscale xy\n"
                         "set key left top\nset grid\n" + lines);
  }

  // --- speed ---------------------------------------------------------------------

  int speed_rounds() const { return options_.quick ? 3 : 7; }

  // Every case, bitstep's default then Bullet in each round, in the peer
  // program (so both are the same build).
  bool run_speed() {
    if (peer_.empty()) return true;
    for (const SpeedCase& c : speed_cases()) speed_.push_back({c, {}, {}, {}, {}});
    for (int round = 0; round < speed_rounds(); ++round) {
      for (SpeedRow& row : speed_) {
        for (const int run : {0, 1, 2}) {  // bitstep, Bullet, bitstep on options_.threads
          const std::string_view variant = run == 1 ? peer_variant : default_variant;
          const int threads = run == 2 ? options_.threads : 1;
          progress_->advance(fmt::format("speed {} {} {} on {}", row.c.scene, row.c.phase, variant, threads));
          std::string output;
          const std::string command =
              fmt::format("{} speed {} --variant {} --from {} --steps {} --threads {}", quote(peer_),
                          quote(options_.scenes + "/" + row.c.scene), variant, row.c.from_step, row.c.steps, threads);
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
        }
      }
    }
    return write("speed.csv", speed_csv(speed_, options_.threads));
  }

  // --- costs ---------------------------------------------------------------------

  static std::vector<std::string> rollback_scenes() {
    return {"stack20.json", "pyramid20.json", "wall128.json", "thrown.json", "playground.json"};
  }

  // Rollbacks from step 60 (1 s in: thrown's cubes in their pile, the
  // playground's bodies still moving); wall128's peak memory in the peer
  // program, bitstep's default and Bullet, 10 steps each (every contact of
  // the standing wall exists from the first step).
  bool run_costs() {
    const int rounds = options_.quick ? 10 : 50;
    for (const std::string& scene : rollback_scenes()) {
      progress_->advance("rollback " + scene);
      try {
        rollback_.push_back(measure_rollback(options_.scenes, scene, 60, rounds));
      } catch (const std::exception& error) {
        fmt::print(stderr, "bitstep bench: rollback: {}\n", error.what());
        return false;
      }
    }
    std::string csv =
        "scene,from_step,bodies,snapshot_bytes,state_bytes,rounds,snapshot_save_ms,state_save_ms,restore_ms,"
        "rollback_ms,state_restore_ms,state_rollback_ms,frame_share,same_bits\n";
    for (const RollbackRow& r : rollback_) {
      csv += fmt::format("{},{},{},{},{},{},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.6g},{:.4g},{}\n", r.scene, r.from_step,
                         r.bodies, r.snapshot_bytes, r.state_bytes, r.rounds, r.snapshot_save_ms, r.state_save_ms,
                         r.restore_ms, r.rollback_ms, r.state_restore_ms, r.state_rollback_ms,
                         r.state_rollback_ms / frame_ms, r.same_bits ? 1 : 0);
    }
    if (!write("rollback.csv", csv)) return false;
    if (peer_.empty()) return true;
    for (std::string_view variant : {default_variant, peer_variant}) {
      progress_->advance(fmt::format("memory wall128 {}", variant));
      std::string output;
      const std::string command = fmt::format("{} memory {} --variant {} --steps {}", quote(peer_),
                                              quote(options_.scenes + "/wall128.json"), variant, memory_steps);
      MemoryRow row{std::string(variant), 0, 0};
      if (!capture(command, output) || std::sscanf(output.c_str(), "%ld %ld", &row.loaded_kib, &row.peak_kib) != 2) {
        fmt::print(stderr, "bitstep bench: memory {}: {}\n", variant, output);
        return false;
      }
      memory_.push_back(row);
    }
    csv = "scene,engine,steps,loaded_kib,peak_kib\n";
    for (const MemoryRow& r : memory_) {
      csv += fmt::format("wall128.json,{},{},{},{}\n", r.engine, memory_steps, r.loaded_kib, r.peak_kib);
    }
    return write("memory.csv", csv);
  }

  std::string costs_section() const {
    std::string md = fmt::format(
        "## Costs a game pays\n\nAn {}-frame rollback: restore the state saved at step 60, then {} steps, "
        "against the {:.1f} ms of a 60 Hz frame (mean of {} rounds; every round, either way, must end on the same "
        "state hash). `state`: a rollback state (the step's state alone, saved into a kept buffer, restored in "
        "place); `snapshot`: the whole world's image, restored into a new world.\n\n"
        "| scene | bodies | state (bytes/body) | snapshot (bytes/body) | save state (us) | save snapshot (us) | "
        "restore state (us) | restore snapshot (us) | state + {} steps (ms) | snapshot + {} steps (ms) | "
        "share of the frame | same bits |\n|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|\n",
        rollback_frames, rollback_frames, frame_ms, rollback_.empty() ? 0 : rollback_.front().rounds,
        rollback_frames, rollback_frames);
    for (const RollbackRow& r : rollback_) {
      const double n = static_cast<double>(std::max<size_t>(r.bodies, 1));
      md += fmt::format("| {} | {} | {:.0f} | {:.0f} | {:.0f} | {:.0f} | {:.0f} | {:.0f} | {:.3g} | {:.3g} | {:.0f}% | {} |\n",
                        r.scene, r.bodies, static_cast<double>(r.state_bytes) / n,
                        static_cast<double>(r.snapshot_bytes) / n, 1000 * r.state_save_ms,
                        1000 * r.snapshot_save_ms, 1000 * r.state_restore_ms, 1000 * r.restore_ms,
                        r.state_rollback_ms, r.rollback_ms, 100 * r.state_rollback_ms / frame_ms,
                        r.same_bits ? "yes" : "**no**");
    }
    if (memory_.empty()) return md + "\nwall128's peak memory: needs the peer program (" + peer_note_ + ").\n\n";
    md += fmt::format(
        "\nPeak resident memory of wall128 (8,256 bricks), each engine in a process of its own (the peer "
        "program), after {} steps; `loaded`: the process after reading the scene, before building the engine.\n\n"
        "| engine | loaded (MiB) | peak (MiB) |\n|---|---:|---:|\n",
        memory_steps);
    for (const MemoryRow& r : memory_) {
      md += fmt::format("| {} | {:.1f} | {:.1f} |\n", r.engine, static_cast<double>(r.loaded_kib) / 1024,
                        static_cast<double>(r.peak_kib) / 1024);
    }
    return md + "\n";
  }

  // Exponent k of ms/step = c n^k over the sizes of at least 100 bodies.
  PowerLaw scale_fit(const std::string& structure, bool asleep) const {
    std::vector<double> x, y;
    for (const ScaleRow& r : scale_) {
      if (r.structure == structure && r.asleep == asleep && r.bodies >= 100) {
        x.push_back(r.bodies);
        y.push_back(r.ms_per_step);
      }
    }
    return fit_power_law(x, y);
  }

  // --- determinism ---------------------------------------------------------------

  struct HashRow {
    std::string engine, scene, build_o0, build_fast, this_build;
  };

  bool run_determinism() {
    progress_->advance("determinism hashes");
    const std::string dir = executable_dir();
    const std::string o0 = dir + "/bitstep-peer-O0", fast = dir + "/bitstep-peer-O3-fast-math";
    if (access(o0.c_str(), X_OK) != 0 || access(fast.c_str(), X_OK) != 0) {
      determinism_note_ = "skipped: the peer programs bitstep-peer-O0 / bitstep-peer-O3-fast-math were not built "
                          "(they need libbullet-dev)";
      progress_->note("determinism " + determinism_note_);
      return true;
    }
    const int steps = 300;
    bool ok = true;
    for (const char* scene : {"stack20.json", "thrown.json"}) {
      const std::string path = options_.scenes + "/" + std::string(scene);
      for (const std::string& engine : {std::string(default_variant), std::string(peer_variant)}) {
        HashRow row{engine, scene, {}, {}, "-"};
        for (auto [program, out] : {std::pair{o0, &row.build_o0}, std::pair{fast, &row.build_fast}}) {
          const std::string command =
              fmt::format("{} hash {} --variant {} --steps {}", quote(program), quote(path), engine, steps);
          if (!capture(command, *out)) {
            progress_->note("bitstep bench: " + command + " failed: " + *out);
            ok = false;
          }
          while (!out->empty() && (out->back() == '\n' || out->back() == '\r')) out->pop_back();
        }
        if (engine == default_variant) row.this_build = this_build_hash(path, steps);
        hashes_.push_back(row);
      }
    }
    std::string csv = "engine,scene,steps,hash_O0,hash_O3_fast_math,hash_this_build\n";
    for (const HashRow& r : hashes_) {
      csv += fmt::format("{},{},{},{},{},{}\n", r.engine, r.scene, steps, r.build_o0, r.build_fast, r.this_build);
    }
    return write("determinism.csv", csv) && ok;
  }

  std::string this_build_hash(const std::string& path, int steps) const {
    SceneSpecs specs;
    std::string reason;
    if (!specs_from_scene_file(path, specs, reason)) return "error: " + reason;
    for (const Variant& v : bitstep_variants()) {
      if (v.name != default_variant) continue;
      auto engine = v.make(StepConfig{});
      specs.add_to(*engine);
      for (int i = 0; i < steps; ++i) engine->step();
      return fmt::format("{:016x}", engine->state_hash());
    }
    return "-";
  }

  // --- summary -------------------------------------------------------------------

  bool write_summary(double seconds) const {
    std::string md = fmt::format("# bitstep bench report\n\n{}\n\n", machine_line(seconds));
    if (!peer_note_.empty()) md += peer_note_ + ".\n\n";
    if (!results_.empty()) md += results_section();
    if (!sweep_.empty()) md += sweep_section();
    if (!scale_.empty()) md += scale_section();
    if (!speed_.empty()) md += speed_section(speed_, std::string(default_variant), options_.threads);
    if (!rollback_.empty()) md += costs_section();
    if (!hashes_.empty() || !determinism_note_.empty()) md += determinism_section();
    return write("summary.md", md);
  }

  std::string machine_line(double seconds) const {
    std::string cpu = "unknown CPU";
    std::ifstream info("/proc/cpuinfo");
    std::string line;
    while (std::getline(info, line)) {
      if (line.rfind("model name", 0) == 0) {
        cpu = line.substr(line.find(':') + 2);
        break;
      }
    }
    const std::time_t now = std::time(nullptr);
    char date[32];
    std::strftime(date, sizeof date, "%Y-%m-%d", std::gmtime(&now));
    return fmt::format("{}, {}, {} hardware threads, single-threaded runs (but the speed section's threads column); `bitstep bench{}` took {:.0f} s.", date,
                       cpu, sysconf(_SC_NPROCESSORS_ONLN), options_.quick ? " --quick" : "", seconds);
  }

  const Row* result(const std::string& experiment, const std::string& variant) const {
    for (const Row& r : results_) {
      if (r.experiment == experiment && r.variant == variant) return &r;
    }
    return nullptr;
  }

  std::string variant_header(const char* first) const {
    std::string header = fmt::format("| {} |", first), rule = "|---|---|";
    header += " measured |";
    for (const std::string& v : variants_) {
      header += " " + v + " |";
      rule += "---:|";
    }
    return header + "\n" + rule + "\n";
  }

  std::string results_section() const {
    std::string md =
        "## Every experiment at 60 Hz, 10 iterations\n\n"
        "Error (the experiment's own metric; `fell`: a body moved 10 cm, or the run failed its bound), "
        "then ms/step. Variants: bitstep's pipeline `standard` or `guendelman`, with or without the shock "
        "step (`+shock`; bitstep's default is `standard+shock`), and Bullet 3.24 from Debian.\n\n";
    md += variant_header("experiment");
    std::vector<std::string> names;
    for (const Row& r : results_) {
      if (std::find(names.begin(), names.end(), r.experiment) == names.end()) names.push_back(r.experiment);
    }
    for (const std::string& name : names) {
      md += fmt::format("| {} | {} |", name, find_experiment(name)->error_label);
      for (const std::string& v : variants_) {
        const Row* r = result(name, v);
        md += r == nullptr ? " - |" : fmt::format(" {:.3g}{} |", r->result.error, r->result.failed ? " fell" : "");
      }
      md += "\n";
    }
    md += "\nms/step (wall clock inside the step only):\n\n" + variant_header("experiment");
    for (const std::string& name : names) {
      md += fmt::format("| {} | ms/step |", name);
      for (const std::string& v : variants_) {
        const Row* r = result(name, v);
        md += r == nullptr ? " - |" : fmt::format(" {:.3g} |", ms_per_step(*r));
      }
      md += "\n";
    }
    md += "\nFurther figures per run (results.csv has them all):\n\n| experiment | variant | figures |\n|---|---|---|\n";
    for (const Row& r : results_) {
      std::string figures;
      for (const auto& [metric, value] : r.result.metrics) figures += fmt::format("{}{} {:.4g}", figures.empty() ? "" : ", ", metric, value);
      if (!figures.empty()) md += fmt::format("| {} | {} | {} |\n", r.experiment, r.variant, figures);
    }
    md += "\n";
    for (const std::string& name : names) {
      if (plots_ && std::filesystem::exists(options_.out + "/stability_" + name + ".png")) {
        md += fmt::format("![{0}](stability_{0}.png)\n", name);
      }
    }
    return md + "\n";
  }

  std::string sweep_section() const {
    std::string md = fmt::format(
        "## Work-precision: error against cost\n\n"
        "dt in {{1/30, 1/60, 1/120, 1/240}} x iterations in {{{}}} x every variant; cost is wall-clock ms "
        "per simulated second. The Pareto front: no other run is both cheaper and more accurate "
        "(work_precision.csv).\n\n| experiment | Pareto front, cheapest first: variant dt iterations -> error @ ms/s |\n|---|---|\n",
        iterations_text());
    std::vector<std::string> names;
    for (const Row& r : sweep_) {
      if (std::find(names.begin(), names.end(), r.experiment) == names.end()) names.push_back(r.experiment);
    }
    for (const std::string& name : names) {
      std::vector<const Row*> front;
      for (const Row& r : sweep_) {
        if (r.experiment == name && r.on_front) front.push_back(&r);
      }
      std::sort(front.begin(), front.end(),
                [](const Row* a, const Row* b) { return ms_per_second(a->result) < ms_per_second(b->result); });
      std::string cells;
      for (const Row* r : front) {
        cells += fmt::format("{}{} {} {} -> {:.2g} @ {:.3g}", cells.empty() ? "" : "; ", r->variant, dt_name(r->dt),
                             r->iterations, r->result.error, ms_per_second(r->result));
      }
      md += fmt::format("| {} | {} |\n", name, cells);
    }
    md += "\n";
    for (const std::string& name : names) {
      if (plots_) md += fmt::format("![{0}](wp_{0}.png)\n", name);
    }
    return md + "\n";
  }

  std::string scale_section() const {
    std::string md =
        "## Scale\n\nms/step of bitstep's default variant against dynamic body count; asleep: sleep on, every "
        "body created asleep at rest. Power-law fit ms = c n^k over the sizes of at least 100 bodies.\n\n"
        "| structure | state | bodies | ms/step |\n|---|---|---:|---:|\n";
    for (const ScaleRow& r : scale_) {
      md += fmt::format("| {} | {}{} | {} | {:.4g} |\n", r.structure, r.asleep ? "asleep" : "awake",
                        r.asleep && !r.stayed_asleep ? " (woke)" : "", r.bodies, r.ms_per_step);
    }
    md += "\n| structure | state | exponent k |\n|---|---|---:|\n";
    for (const char* structure : {"pyramid", "columns"}) {
      for (bool asleep : {false, true}) {
        const PowerLaw fit = scale_fit(structure, asleep);
        md += fmt::format("| {} | {} | {} |\n", structure, asleep ? "asleep" : "awake",
                          fit.ok ? fmt::format("{:.2f}", fit.exponent) : std::string("-"));
      }
    }
    if (plots_) md += "\n![scale](scale.png)\n";
    return md + "\n";
  }

  std::string determinism_section() const {
    std::string md = "## Determinism across builds\n\n";
    if (!determinism_note_.empty()) return md + determinism_note_ + "\n\n";
    md += "Final state hash after 300 steps at 60 Hz, 10 iterations, from the peer program compiled "
          "(with bitstep's sources) at -O0 and at -O3 -ffast-math, and from this bitstep. Debian's Bullet "
          "library is a prebuilt binary: only its header-inlined code changes with these flags.\n\n"
          "| engine | scene | -O0 | -O3 -ffast-math | this build | same bits? |\n|---|---|---|---|---|---|\n";
    for (const HashRow& r : hashes_) {
      const bool same = r.build_o0 == r.build_fast && (r.this_build == "-" || r.this_build == r.build_o0);
      md += fmt::format("| {} | {} | `{}` | `{}` | `{}` | {} |\n", r.engine, r.scene, r.build_o0, r.build_fast,
                        r.this_build, same ? "yes" : "**no**");
    }
    return md + "\n";
  }

  // --- files ---------------------------------------------------------------------

  bool write(const std::string& name, const std::string& text) const {
    std::string reason;
    if (write_report_file(options_.out, name, text, reason)) return true;
    fmt::print(stderr, "bitstep bench: {}\n", reason);
    write_failed_ = true;
    return false;
  }

  bool draw(const std::string& stem, const std::string& commands) const {
    std::string reason;
    if (plot(options_.out, stem, commands, reason)) return true;
    progress_->note("bitstep bench: " + reason);
    return false;
  }

  Options options_;
  mutable bool write_failed_ = false;  // a report file could not be written
  RunOptions run_options_;
  std::vector<std::string> variants_;
  std::string peer_, peer_note_, determinism_note_;
  bool plots_ = false;
  ProgressBar* progress_ = nullptr;
  std::vector<Row> results_, sweep_;
  std::vector<ScaleRow> scale_;
  std::vector<SpeedRow> speed_;
  struct MemoryRow {
    std::string engine;
    long loaded_kib, peak_kib;
  };
  static constexpr int memory_steps = 10;
  std::vector<RollbackRow> rollback_;
  std::vector<MemoryRow> memory_;
  std::vector<HashRow> hashes_;
};

std::set<std::string> split(const std::string& list) {
  std::set<std::string> items;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (!item.empty()) items.insert(item);
  }
  return items;
}

}  // namespace

int run_bench_suite(int argc, char** argv) {
  Options options;
  for (int i = 0; i < argc; ++i) {
    const std::string_view arg = argv[i];
    const bool has_value = i + 1 < argc;
    if (arg == "--quick") {
      options.quick = true;
    } else if (arg == "--full") {
      options.quick = false;
    } else if (arg == "--out" && has_value) {
      options.out = argv[++i];
    } else if (arg == "--scenes" && has_value) {
      options.scenes = argv[++i];
    } else if (arg == "--no-peer") {
      options.peer = false;
    } else if (arg == "--threads" && has_value) {
      if (!parse_threads(argv[++i], options.threads) || options.threads < 2) {
        fmt::print(stderr, "bitstep bench: --threads needs an integer 2..{}, got '{}'\n", max_threads, argv[i]);
        return 2;
      }
    } else if (arg == "--sections" && has_value) {
      options.sections = split(argv[++i]);
      for (const std::string& s : options.sections) {
        if (s != "results" && s != "sweep" && s != "scale" && s != "speed" && s != "costs" && s != "determinism") {
          fmt::print(stderr,
                     "bitstep bench: unknown section '{}' (results, sweep, scale, speed, costs, determinism)\n", s);
          return 2;
        }
      }
    } else if (arg == "--only" && has_value) {
      options.only = split(argv[++i]);
      for (const std::string& name : options.only) {
        if (find_experiment(name) == nullptr) {
          fmt::print(stderr, "bitstep bench: unknown experiment '{}'\n", name);
          return 2;
        }
      }
    } else {
      fmt::print(stderr,
                 "bitstep bench: unknown option '{}' (options: --quick, --full, --out DIR, --scenes DIR, "
                 "--sections LIST, --only EXPERIMENTS, --no-peer, --threads N)\n",
                 arg);
      return 2;
    }
  }
  try {
    return Bench(options).run();
  } catch (const std::exception& error) {
    fmt::print(stderr, "bitstep bench: {}\n", error.what());
    return 1;
  }
}

}  // namespace bitstep
