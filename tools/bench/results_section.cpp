// `bitstep bench`'s results section: every experiment at 60 Hz and 10
// iterations on every variant; the error and ms/step tables, the further
// figures, and a plot of each experiment's drift over time.
#include <fmt/core.h>

#include <algorithm>
#include <filesystem>

#include "tools/bench/report.h"
#include "tools/bench/sections.h"

namespace bitstep::bench {

namespace {

// series_<experiment>.csv: every variant's time series; a plot of the drift.
bool write_series(Context& context, const Experiment& e, const std::vector<Row>& rows) {
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
  if (!context.write(file, csv)) return false;
  if (!context.plots) return true;
  // Each variant keeps its colour, dash and marker in every plot; a curve
  // drawn later is thinner, so one lying on an earlier curve shows inside it,
  // and the key names it "(same as ...)".
  std::vector<std::vector<double>> drifts;
  std::vector<double> all;
  for (const Row& r : rows) {
    drifts.emplace_back();
    for (const auto& values : r.result.rows) {
      if (values.size() > 1) drifts.back().push_back(values[1]);
    }
    all.insert(all.end(), drifts.back().begin(), drifts.back().end());
  }
  const std::vector<int> same = earlier_equal(drifts);
  const LogZeroRow zero_row = log_y_with_zero_row(all);
  std::string lines;
  for (size_t i = 0; i < rows.size(); ++i) {
    const Row& r = rows[i];
    const size_t style = variant_style(context, r.variant);
    const std::string title =
        same[i] < 0 ? r.variant : r.variant + " (same as " + rows[static_cast<size_t>(same[i])].variant + ")";
    lines += fmt::format(
        "{}'{}' using (strcol(1) eq '{}' ? $2 : NaN):(shown($3)) with linespoints lc {} lw {} dt {} pt {} ps 1.3 "
        "pi {} title '{}'",
        lines.empty() ? "plot " : ", \\\n     ", file, r.variant, line_colours[style % variant_styles],
        draw_widths[i % variant_styles], dash_types[style % variant_styles], point_types[style % variant_styles], 17 + 4 * static_cast<int>(i), title);
  }
  const std::string commands = fmt::format(
      "set title '{}: {} (60 Hz, 10 iterations)' noenhanced\n"
      "set xlabel 'simulated time (s)'\nset ylabel 'largest drift of any body from its start (m)'\n"
      "set logscale y\nset format y '10^{{%L}}'\n{}set grid\n{}{}{}",
      e.name, e.description, key_below(static_cast<int>(rows.size()) + zero_row.entries), zero_row.commands, lines,
      zero_row.key_entry);
  return context.draw("stability_" + e.name, commands);
}

std::string results_csv(const std::vector<Row>& results) {
  std::string csv = "experiment,group,variant,dt,iterations,error,failed,ms_per_step,ms_per_simulated_s,metrics\n";
  for (const Row& r : results) {
    const Experiment* e = find_experiment(r.experiment);
    std::string metrics;
    for (const auto& [name, value] : r.result.metrics) {
      metrics += fmt::format("{}{}={:.6g}", metrics.empty() ? "" : " ", name, value);
    }
    csv += fmt::format("{},{},{},{:.17g},{},{:.6g},{},{:.6g},{:.6g},{}\n", r.experiment, e->group, r.variant, r.dt,
                       r.iterations, r.result.error, r.result.failed ? 1 : 0, r.ms_per_step(), r.ms_per_simulated_s(),
                       csv_field(metrics));
  }
  return csv;
}

const Row* find_row(const std::vector<Row>& results, const std::string& experiment, const std::string& variant) {
  for (const Row& r : results) {
    if (r.experiment == experiment && r.variant == variant) return &r;
  }
  return nullptr;
}

std::string variant_header(const Context& context, const char* first) {
  std::string header = fmt::format("| {} |", first), rule = "|---|---|";
  header += " measured |";
  for (const std::string& v : context.variants) {
    header += " " + v + " |";
    rule += "---:|";
  }
  return header + "\n" + rule + "\n";
}

// The error table, then the ms/step table: one row per experiment, one column per variant.
std::string error_and_speed_tables(const Context& context, const std::vector<Row>& results,
                                   const std::vector<std::string>& names) {
  std::string md = variant_header(context, "experiment");
  for (const std::string& name : names) {
    md += fmt::format("| {} | {} |", name, find_experiment(name)->error_label);
    for (const std::string& v : context.variants) {
      const Row* r = find_row(results, name, v);
      md += r == nullptr ? " - |" : fmt::format(" {:.3g}{} |", r->result.error, r->result.failed ? " fell" : "");
    }
    md += "\n";
  }
  md += "\nms/step (wall clock inside the step only):\n\n" + variant_header(context, "experiment");
  for (const std::string& name : names) {
    md += fmt::format("| {} | ms/step |", name);
    for (const std::string& v : context.variants) {
      const Row* r = find_row(results, name, v);
      md += r == nullptr ? " - |" : fmt::format(" {:.3g} |", r->ms_per_step());
    }
    md += "\n";
  }
  return md;
}

std::string results_markdown(const Context& context, const std::vector<Row>& results) {
  std::string md =
      "## Every experiment at 60 Hz, 10 iterations\n\n"
      "Error (the experiment's own metric; `fell`: a body moved 10 cm, or the run failed its bound), "
      "then ms/step. Variants: bitstep's pipeline `standard` or `guendelman`, with or without the shock "
      "step (`+shock`; bitstep's default is `standard+shock`), and Bullet 3.24 from Debian.\n\n";
  std::vector<std::string> names;
  for (const Row& r : results) {
    if (std::find(names.begin(), names.end(), r.experiment) == names.end()) names.push_back(r.experiment);
  }
  md += error_and_speed_tables(context, results, names);
  md += "\nFurther figures per run (results.csv has them all):\n\n| experiment | variant | figures |\n|---|---|---|\n";
  for (const Row& r : results) {
    std::string figures;
    for (const auto& [metric, value] : r.result.metrics) {
      figures += fmt::format("{}{} {:.4g}", figures.empty() ? "" : ", ", metric, value);
    }
    if (!figures.empty()) md += fmt::format("| {} | {} | {} |\n", r.experiment, r.variant, figures);
  }
  std::vector<std::string> plots;
  for (const std::string& name : names) {
    if (context.plots && std::filesystem::exists(context.options.out + "/stability_" + name + ".png")) {
      plots.push_back("stability_" + name + ".png");
    }
  }
  return md + "\n" + plots_line(plots);
}

}  // namespace

int results_runs(const Context& context) {
  int runs = 0;
  for (const Experiment* e : context.selected(false)) runs += static_cast<int>(context.variants_for(*e).size());
  return runs;
}

Section run_results(Context& context) {
  Section section;
  std::vector<Row> results;
  for (const Experiment* e : context.selected(false)) {
    std::vector<Row> rows;
    for (const std::string& variant : context.variants_for(*e)) {
      Row row{e->name, variant, 1.0 / 60, 10, {}, false};
      if (!context.run_one(*e, variant, row.dt, row.iterations, row.result)) {
        section.ok = false;
        continue;
      }
      rows.push_back(row);
    }
    if (!rows.empty() && !rows.front().result.columns.empty()) {
      section.ok = write_series(context, *e, rows) && section.ok;
    }
    results.insert(results.end(), rows.begin(), rows.end());
  }
  section.ok = context.write("results.csv", results_csv(results)) && section.ok;
  if (!results.empty()) section.markdown = results_markdown(context, results);
  return section;
}

}  // namespace bitstep::bench
