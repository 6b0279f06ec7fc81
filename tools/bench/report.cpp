#include "tools/bench/report.h"

#include <fmt/core.h>

#include <algorithm>
#include <cmath>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "tools/cli/file_output.h"

namespace bitstep::bench {

namespace {

// 'text' for /bin/sh, any character allowed.
std::string shell_quote(const std::string& text) {
  std::string quoted = "'";
  for (char c : text) {
    if (c == '\'') {
      quoted += "'\\''";
    } else {
      quoted += c;
    }
  }
  return quoted + "'";
}

}  // namespace

std::string csv_field(const std::string& text) {
  if (text.find_first_of(",\"\n") == std::string::npos) return text;
  std::string quoted = "\"";
  for (char c : text) {
    if (c == '"') quoted += '"';
    quoted += c;
  }
  return quoted + "\"";
}

bool write_report_file(const std::string& dir, const std::string& name, const std::string& text,
                       std::string& reason) {
  return write_file_atomically(dir + "/" + name, text, reason);
}

bool gnuplot_available() { return std::system("command -v gnuplot >/dev/null 2>&1") == 0; }

bool plot(const std::string& dir, const std::string& stem, const std::string& commands, std::string& reason) {
  // The script kept beside the CSV files draws under the real names; the one
  // run here (removed after) under temporary names, renamed into place when
  // gnuplot succeeded: never a half-drawn plot under the real name.
  const auto script = [&](const char* suffix) {
    return fmt::format(
        "# Draws {0}.svg and {0}.png from the CSV files beside it: gnuplot {0}.gp\n"
        "set datafile separator ','\n"
        "set terminal svg size 900,560 dynamic font 'sans,12'\n"
        "set output '{0}.svg{2}'\n"
        "{1}\n"
        "set terminal pngcairo size 900,560 font 'sans,10'\n"
        "set output '{0}.png{2}'\n"
        "replot\n",
        stem, commands, suffix);
  };
  if (!write_report_file(dir, stem + ".gp", script(""), reason)) return false;
  if (!write_report_file(dir, stem + ".gp.run", script(".partial"), reason)) return false;
  const std::string command = "cd " + shell_quote(dir) + " && gnuplot " + shell_quote(stem + ".gp.run") + " 2>" +
                              shell_quote(stem + ".gp.log");
  const std::string base = dir + "/" + stem;
  const bool drawn = std::system(command.c_str()) == 0;
  std::remove((base + ".gp.run").c_str());
  for (const char* ext : {".svg", ".png"}) {
    const std::string partial = base + ext + ".partial";
    if (drawn && std::rename(partial.c_str(), (base + ext).c_str()) == 0) continue;
    std::remove(partial.c_str());
    if (drawn) {
      reason = fmt::format("cannot rename {} to {}{}", partial, base, ext);
      return false;
    }
  }
  if (!drawn) {
    reason = fmt::format("gnuplot failed on {}/{}.gp (its messages: {}/{}.gp.log)", dir, stem, dir, stem);
    return false;
  }
  std::remove((dir + "/" + stem + ".gp.log").c_str());
  return true;
}

std::string plots_line(const std::vector<std::string>& plots) {
  if (plots.empty()) return "";
  std::string line = "Plots (`gnuplot NAME.gp` draws one again):";
  for (size_t i = 0; i < plots.size(); ++i) line += fmt::format("{} `{}`", i == 0 ? "" : ",", plots[i]);
  return line + ".\n\n";
}

std::string key_below(int entries) {
  return fmt::format(
      "set key at screen 0.5, screen 0.01 center bottom horizontal Left reverse noenhanced samplen 2.5\n"
      "set bmargin {}\n",
      4 + (entries + 1) / 2);
}

LogZeroRow log_y_with_zero_row(const std::vector<double>& values) {
  bool zero = false;
  double smallest = std::numeric_limits<double>::infinity();
  for (double v : values) {
    if (v == 0) zero = true;
    if (v > 0 && std::isfinite(v)) smallest = std::min(smallest, v);
  }
  LogZeroRow row;
  row.entries = zero ? 1 : 0;
  if (!zero) {
    row.commands = "shown(v) = v\n";
    return row;
  }
  // The lowest decade tic is 10^decade; the zero row sits half a decade
  // below it, the dotted line between, the axis ends just under the row.
  const double decade = std::isfinite(smallest) ? std::floor(std::log10(smallest)) : 0;
  row.commands = fmt::format(
      "zero_row = {:.6g}\nshown(v) = v == 0 ? zero_row : v\nset yrange [{:.6g}:*]\nset ytics add ('0' zero_row)\n"
      "set arrow 9 from graph 0, first {:.6g} to graph 1, first {:.6g} nohead dt 3 lw 1.5 lc 'gray40' back\n",
      std::pow(10.0, decade - 0.5), std::pow(10.0, decade - 0.8), std::pow(10.0, decade - 0.25),
      std::pow(10.0, decade - 0.25));
  row.key_entry = ", \\\n     keyentry with lines dt 3 lw 1.5 lc 'gray40' title 'exactly 0 (drawn on row \"0\")'";
  return row;
}

std::vector<int> earlier_equal(const std::vector<std::vector<double>>& series) {
  std::vector<int> equal(series.size(), -1);
  for (size_t i = 0; i < series.size(); ++i) {
    for (size_t j = 0; j < i && equal[i] < 0; ++j) {
      if (!series[i].empty() && series[i] == series[j]) equal[i] = static_cast<int>(j);
    }
  }
  return equal;
}

}  // namespace bitstep::bench
