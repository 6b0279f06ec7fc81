// The options several commands share, declared once: --threads (run,
// record, verify, bench) and --trace with --trace-every and --trace-format
// (run, record, verify).
#pragma once

#include <CLI/CLI.hpp>

#include "tools/cli/body_trace.h"

namespace bitstep::cli {

// --threads N: N workers, min..max_threads (tools/cli/thread_option.h).
CLI::Option* add_threads(CLI::App& app, int& threads, int min, const std::string& description);

// --trace FILE, --trace-every K and --trace-format csv|jsonl into `trace`
// (its format checked after parsing: TraceOptions::check).
void add_trace(CLI::App& app, TraceOptions& trace);

}  // namespace bitstep::cli
