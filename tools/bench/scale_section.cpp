// `bitstep bench`'s scale section: bitstep's default variant, ms/step
// against body count for pyramids and columns, awake and asleep, with the
// exponent of a power-law fit and a plot.
#include <fmt/core.h>

#include <algorithm>

#include "tools/bench/report.h"
#include "tools/bench/scale.h"
#include "tools/bench/sections.h"
#include "tools/bench/stats.h"

namespace bitstep::bench {

namespace {

// Exponent k of ms/step = c n^k over the sizes of at least 100 bodies.
PowerLaw scale_fit(const std::vector<ScaleRow>& scale, const std::string& structure, bool asleep) {
  std::vector<double> x, y;
  for (const ScaleRow& r : scale) {
    if (r.structure == structure && r.asleep == asleep && r.bodies >= 100) {
      x.push_back(r.bodies);
      y.push_back(r.ms_per_step);
    }
  }
  return fit_power_law(x, y);
}

bool write_scale(Context& context, const std::vector<ScaleRow>& scale) {
  std::string csv = "structure,state,bodies,steps_timed,ms_per_step,stayed_asleep\n";
  for (const ScaleRow& r : scale) {
    csv += fmt::format("{},{},{},{},{:.6g},{}\n", r.structure, r.asleep ? "asleep" : "awake", r.bodies, r.steps,
                       r.ms_per_step, r.stayed_asleep ? 1 : 0);
  }
  if (!context.write("scale.csv", csv)) return false;
  if (!context.plots || scale.empty()) return true;
  // The x range spans the sizes measured (a decade's margin left nothing
  // but white); each line keeps its own dash and marker.
  std::vector<double> ms;
  int fewest = 0, most = 0;
  for (const ScaleRow& r : scale) {
    ms.push_back(r.ms_per_step);
    fewest = fewest == 0 ? r.bodies : std::min(fewest, r.bodies);
    most = std::max(most, r.bodies);
  }
  const LogZeroRow zero_row = log_y_with_zero_row(ms);
  std::string lines;
  int line = 0;
  for (const char* structure : {"pyramid", "columns"}) {
    for (const char* state : {"awake", "asleep"}) {
      lines += fmt::format(
          "{}'scale.csv' using (strcol(1) eq '{}' && strcol(2) eq '{}' ? $3 : NaN):(shown($5)) with linespoints "
          "lc {} lw 2 dt {} pt {} ps 1.3 title '{} {}'",
          lines.empty() ? "plot " : ", \\\n     ", structure, state, line_colours[line], dash_types[line],
          point_types[line], structure, state);
      ++line;
    }
  }
  return context.draw("scale", fmt::format("set title 'bitstep ms/step against body count (60 Hz, 10 iterations)'\n"
                                           "set xlabel 'dynamic bodies'\nset ylabel 'ms per step'\nset logscale xy\n"
                                           "set xrange [{}:{}]\n{}set grid\n{}{}{}",
                                           fewest / 1.3, most * 1.3, key_below(4 + zero_row.entries), zero_row.commands,
                                           lines, zero_row.key_entry));
}

std::string scale_markdown(const Context& context, const std::vector<ScaleRow>& scale) {
  std::string md =
      "## Scale\n\nms/step of bitstep's default variant against dynamic body count; asleep: sleep on, every "
      "body created asleep at rest. Power-law fit ms = c n^k over the sizes of at least 100 bodies.\n\n"
      "| structure | state | bodies | ms/step |\n|---|---|---:|---:|\n";
  for (const ScaleRow& r : scale) {
    md += fmt::format("| {} | {}{} | {} | {:.4g} |\n", r.structure, r.asleep ? "asleep" : "awake",
                      r.asleep && !r.stayed_asleep ? " (woke)" : "", r.bodies, r.ms_per_step);
  }
  md += "\n| structure | state | exponent k |\n|---|---|---:|\n";
  for (const char* structure : {"pyramid", "columns"}) {
    for (bool asleep : {false, true}) {
      const PowerLaw fit = scale_fit(scale, structure, asleep);
      md += fmt::format("| {} | {} | {} |\n", structure, asleep ? "asleep" : "awake",
                        fit.ok ? fmt::format("{:.2f}", fit.exponent) : std::string("-"));
    }
  }
  return md + "\n" + plots_line(context.plots ? std::vector<std::string>{"scale.png"} : std::vector<std::string>{});
}

}  // namespace

int scale_runs(const Context& context) { return static_cast<int>(scale_sizes(context.options.quick).size()) * 4; }

Section run_scale(Context& context) {
  std::vector<ScaleRow> scale;
  for (const char* structure : {"pyramid", "columns"}) {
    for (bool asleep : {false, true}) {
      for (int n : scale_sizes(context.options.quick)) {
        context.progress->advance(fmt::format("scale {} {} {}", structure, asleep ? "asleep" : "awake", n));
        scale.push_back(measure_scale(structure, n, asleep));
      }
    }
  }
  Section section;
  section.ok = write_scale(context, scale);
  if (!scale.empty()) section.markdown = scale_markdown(context, scale);
  return section;
}

}  // namespace bitstep::bench
