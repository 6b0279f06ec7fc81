#include "tools/cli/shared_options.h"

#include <cstdint>

#include "tools/cli/options.h"
#include "tools/cli/thread_option.h"

namespace bitstep::cli {

CLI::Option* add_threads(CLI::App& app, int& threads, int min, const std::string& description) {
  return add_read(
             app, "--threads", "an integer " + std::to_string(min) + ".." + std::to_string(max_threads),
             [&threads, min](const std::string& text) {
               int n = 0;
               if (!parse_threads(text.c_str(), n) || n < min) return false;
               threads = n;
               return true;
             },
             description)
      ->type_name("N");
}

void add_trace(CLI::App& app, TraceOptions& trace) {
  app.add_option("--trace", trace.path, "write every body's pose and velocities to FILE (.csv or .jsonl)")
      ->type_name("FILE");
  add_read(
      app, "--trace-every", "a positive integer",
      [&trace](const std::string& text) {
        long long n = 0;
        if (!read_integer(text, 1, INT64_MAX, n)) return false;
        trace.every = static_cast<uint64_t>(n);
        return true;
      },
      "rows every K-th step (default 1)")
      ->type_name("K");
  add_read(
      app, "--trace-format", "csv or jsonl",
      [&trace](const std::string& text) {
        trace.format = text;
        return text == "csv" || text == "jsonl";
      },
      "csv or jsonl (default: from FILE's extension)")
      ->type_name("FORMAT");
}

}  // namespace bitstep::cli
