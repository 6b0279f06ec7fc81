#include "tools/bench/report.h"

#include <fmt/core.h>

#include <cstdio>
#include <cstdlib>

#include "tools/file_output.h"

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

}  // namespace bitstep::bench
