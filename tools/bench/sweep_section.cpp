// `bitstep bench`'s sweep section: the work-precision sweep, dt x iterations
// x variants for the cheap experiments, error against ms per simulated
// second with the Pareto front marked, a plot per experiment.
#include <fmt/core.h>

#include <algorithm>

#include "tools/bench/report.h"
#include "tools/bench/sections.h"
#include "tools/bench/stats.h"

namespace bitstep::bench {

namespace {

std::vector<double> sweep_dts() { return {1.0 / 30, 1.0 / 60, 1.0 / 120, 1.0 / 240}; }

std::vector<int> sweep_iterations(const Context& context) {
  if (context.options.quick) return {1, 4, 16};
  return {1, 2, 4, 8, 16, 32};
}

std::string iterations_text(const Context& context) {
  std::string text;
  for (int i : sweep_iterations(context)) text += (text.empty() ? "" : ", ") + std::to_string(i);
  return text;
}

// The rows of one experiment on the Pareto front, cheapest first.
std::vector<const Row*> cheapest_first_front(const std::vector<Row>& rows, const std::string& experiment) {
  std::vector<const Row*> front;
  for (const Row& r : rows) {
    if (r.experiment == experiment && r.on_front) front.push_back(&r);
  }
  std::sort(front.begin(), front.end(),
            [](const Row* a, const Row* b) { return a->ms_per_simulated_s() < b->ms_per_simulated_s(); });
  return front;
}

// The plot: a marker per run, each variant's its own (a later variant's
// smaller, so one on an earlier variant's shows inside it, and the key names
// a variant whose errors all equal an earlier one's "(same as ...)"), the
// Pareto front as a line, labelled where its error has dropped twofold
// since the last label (summary.md lists every point of it).
std::string plot_commands(const Context& context, const Experiment& e, const std::vector<Row>& rows,
                          const std::string& file, const std::string& front_file) {
  std::vector<std::vector<double>> errors(context.variants.size());
  std::vector<double> all;
  for (const Row& r : rows) {
    const size_t style = variant_style(context, r.variant);
    if (style < errors.size()) errors[style].push_back(r.result.error);
    all.push_back(r.result.error);
  }
  const std::vector<int> same = earlier_equal(errors);
  const LogZeroRow zero_row = log_y_with_zero_row(all);
  static constexpr double sizes[variant_styles] = {1.9, 1.9, 1.5, 1.5, 1.5, 1.3};
  std::string lines;
  for (size_t i = 0; i < context.variants.size(); ++i) {
    const std::string& variant = context.variants[i];
    const std::string title =
        same[i] < 0 ? variant : variant + " (same as " + context.variants[static_cast<size_t>(same[i])] + ")";
    lines += fmt::format(
        "{}'{}' using (strcol(1) eq '{}' ? $4 : NaN):(shown($5)) with points lc {} pt {} ps {} lw 1.5 title '{}'",
        lines.empty() ? "plot " : ", \\\n     ", file, variant, line_colours[i % variant_styles], point_types[i % variant_styles],
        sizes[i % variant_styles],
        title);
  }
  // Drawing the front's line resets `labelled`, the error last labelled
  // (the script is drawn twice, as SVG and as PNG).
  lines += fmt::format(
      ", \\\n     '{0}' using 1:(labelled = 1e300, shown($2)) with lines lw 2 lc 'black' title 'Pareto front', \\\n"
      "     '{0}' using 1:(shown($2)):($2 < labelled / 2 ? label_at($2, strcol(3)) : '') "
      "with labels left offset 0.7,0.5 font ',8' notitle",
      front_file);
  return fmt::format(
      "labelled = 1e300\nlabel_at(error, text) = (labelled = error, text)\n"
      "set title '{}: {}' noenhanced offset 0,0.8\nset tmargin 4\n"
      "set xlabel 'cost: wall-clock ms per simulated second'\nset ylabel 'error: {}'\n"
      "set logscale xy\nset format y '10^{{%L}}'\n{}set grid\n"
      "set label 1 'dt in {{1/30 .. 1/240}} x iterations in {{{}}}; front labels: variant dt iterations' "
      "at graph 0.5, graph 1.03 center font ',9'\n{}{}{}",
      e.name, e.description, e.error_label, key_below(static_cast<int>(context.variants.size()) + 1 + zero_row.entries),
      iterations_text(context), zero_row.commands, lines, zero_row.key_entry);
}

// wp_<experiment>.csv and wp_<experiment>_front.csv, and their plot.
bool write_sweep_plot(Context& context, const Experiment& e, const std::vector<Row>& rows) {
  std::string csv = "variant,dt,iterations,ms_per_simulated_s,error,pareto\n";
  for (const Row& r : rows) {
    csv += fmt::format("{},{},{},{:.6g},{:.6g},{}\n", r.variant, dt_name(r.dt), r.iterations, r.ms_per_simulated_s(),
                       r.result.error, r.on_front ? 1 : 0);
  }
  std::string front_csv = "ms_per_simulated_s,error,label\n";
  for (const Row* r : cheapest_first_front(rows, e.name)) {
    front_csv += fmt::format("{:.6g},{:.6g},{} {} it {}\n", r->ms_per_simulated_s(), r->result.error, r->variant,
                             dt_name(r->dt), r->iterations);
  }
  const std::string file = "wp_" + e.name + ".csv", front_file = "wp_" + e.name + "_front.csv";
  if (!context.write(file, csv) || !context.write(front_file, front_csv)) return false;
  if (!context.plots) return true;
  return context.draw("wp_" + e.name, plot_commands(context, e, rows, file, front_file));
}

// Every variant x dt x iterations of one experiment, the Pareto front marked.
std::vector<Row> sweep_experiment(Context& context, const Experiment& e, bool& ok) {
  std::vector<Row> rows;
  for (const std::string& variant : context.variants) {
    for (double dt : sweep_dts()) {
      for (int iterations : sweep_iterations(context)) {
        Row row{e.name, variant, dt, iterations, {}, false};
        if (!context.run_one(e, variant, dt, iterations, row.result)) {
          ok = false;
          continue;
        }
        rows.push_back(row);
      }
    }
  }
  std::vector<CostError> points;
  for (const Row& r : rows) points.push_back({r.ms_per_simulated_s(), r.result.error});
  const std::vector<bool> front = pareto_front(points);
  for (size_t i = 0; i < rows.size(); ++i) rows[i].on_front = front[i];
  return rows;
}

std::string sweep_markdown(const Context& context, const std::vector<Row>& sweep) {
  std::string md = fmt::format(
      "## Work-precision: error against cost\n\n"
      "dt in {{1/30, 1/60, 1/120, 1/240}} x iterations in {{{}}} x every variant; cost is wall-clock ms "
      "per simulated second. The Pareto front: no other run is both cheaper and more accurate "
      "(work_precision.csv).\n\n| experiment | Pareto front, cheapest first: variant dt iterations -> error @ ms/s |\n|---|---|\n",
      iterations_text(context));
  std::vector<std::string> names;
  for (const Row& r : sweep) {
    if (std::find(names.begin(), names.end(), r.experiment) == names.end()) names.push_back(r.experiment);
  }
  for (const std::string& name : names) {
    std::string cells;
    for (const Row* r : cheapest_first_front(sweep, name)) {
      cells += fmt::format("{}{} {} {} -> {:.2g} @ {:.3g}", cells.empty() ? "" : "; ", r->variant, dt_name(r->dt),
                           r->iterations, r->result.error, r->ms_per_simulated_s());
    }
    md += fmt::format("| {} | {} |\n", name, cells);
  }
  std::vector<std::string> plots;
  for (const std::string& name : names) {
    if (context.plots) plots.push_back("wp_" + name + ".png");
  }
  return md + "\n" + plots_line(plots);
}

}  // namespace

int sweep_runs(const Context& context) {
  return static_cast<int>(context.selected(true).size() * sweep_dts().size() * sweep_iterations(context).size()) *
         static_cast<int>(context.variants.size());
}

Section run_sweep(Context& context) {
  Section section;
  std::vector<Row> sweep;
  for (const Experiment* e : context.selected(true)) {
    const std::vector<Row> rows = sweep_experiment(context, *e, section.ok);
    section.ok = write_sweep_plot(context, *e, rows) && section.ok;
    sweep.insert(sweep.end(), rows.begin(), rows.end());
  }
  std::string csv = "experiment,variant,dt,iterations,error,failed,ms_per_simulated_s,pareto\n";
  for (const Row& r : sweep) {
    csv += fmt::format("{},{},{},{},{:.6g},{},{:.6g},{}\n", r.experiment, r.variant, dt_name(r.dt), r.iterations,
                       r.result.error, r.result.failed ? 1 : 0, r.ms_per_simulated_s(), r.on_front ? 1 : 0);
  }
  section.ok = context.write("work_precision.csv", csv) && section.ok;
  if (!sweep.empty()) section.markdown = sweep_markdown(context, sweep);
  return section;
}

}  // namespace bitstep::bench
