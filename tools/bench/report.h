// The files of a benchmark report: CSV and Markdown text, and plots drawn by
// gnuplot from a script kept beside them (so any figure can be redrawn).
#pragma once

#include <string>

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

}  // namespace bitstep::bench
