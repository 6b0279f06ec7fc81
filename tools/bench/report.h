// The files of a benchmark report: CSV and Markdown text, and plots drawn by
// gnuplot from a script kept beside them (so any figure can be redrawn).
#pragma once

#include <string>
#include <vector>

namespace bitstep::bench {

// A CSV field, quoted when it holds a comma, a quote or a newline.
std::string csv_field(const std::string& text);

// Writes dir/name atomically (never a partial file); false with a reason.
bool write_report_file(const std::string& dir, const std::string& name, const std::string& text,
                       std::string& reason);

bool gnuplot_available();

// Writes dir/<stem>.gp: `commands` drawn once as <stem>.svg and once as
// <stem>.png, then runs gnuplot in dir. False with a reason.
bool plot(const std::string& dir, const std::string& stem, const std::string& commands, std::string& reason);

// The summary's line naming a section's plots, drawn beside it ("" for
// none): named rather than embedded, so a folder keeping only some of them
// (tools/report keeps those docs/bench.md shows) has no broken image.
std::string plots_line(const std::vector<std::string>& plots);

// A log y axis that shows results of exactly 0 instead of losing them below
// its floor. When `values` hold a 0: a row marked "0" on the axis half a
// decade below the smallest positive value, a dotted line above it, and a
// key entry saying so. `commands` define shown(v), v or the zero row for 0,
// for the plot's using columns; `key_entry` (a plot element, led by a comma)
// is empty when no value is 0.
struct LogZeroRow {
  std::string commands;
  std::string key_entry;
  int entries = 0;  // key entries: 1 with a zero row
};
LogZeroRow log_y_with_zero_row(const std::vector<double>& values);

// For each series, the index of the first earlier series equal to it, or -1:
// curves that would hide one another, to be named "(same as ...)" in the key.
std::vector<int> earlier_equal(const std::vector<std::vector<double>>& series);

// A variant's dash type and marker, by its place in the variants run
// (standard, standard+shock, guendelman, guendelman+shock, soft, the peer):
// the pairs that often give the same values (the two pipelines, with the
// shock step or without) differ in both, an open marker against a cross.
inline constexpr int variant_styles = 6;
inline constexpr int dash_types[variant_styles] = {1, 2, 4, 5, 3, 1};
inline constexpr int point_types[variant_styles] = {4, 6, 2, 1, 8, 9};
// Colours: gnuplot's first four, its dark blue for the soft step, then its
// red for the peer (not its yellow).
inline constexpr int line_colours[variant_styles] = {1, 2, 3, 4, 6, 7};
// Line widths by drawing order: a curve drawn on an earlier one shows inside
// it (the last, the peer's, seldom lies on another and stays readable).
inline constexpr double draw_widths[variant_styles] = {4, 3.2, 2.5, 1.8, 1.4, 2};

// The key of every plot: below the plot area, so no curve runs through it,
// with the bottom margin its `entries` need at two or more a row.
std::string key_below(int entries);

}  // namespace bitstep::bench
