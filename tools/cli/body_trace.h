// bitstep run / record / verify --trace: every live body's pose and velocities at the traced
// steps, one row per body per step, as CSV or JSON Lines. Numbers are exact
// decimal text (fixed/decimal.h to_string: the shortest text that parses
// back to the same bits), never a double. The position is the body's centre
// of mass, as the world stores it.
#pragma once

#include <cstdint>
#include <optional>
#include <string>

#include "core/world.h"
#include "tools/cli/file_output.h"

namespace bitstep {

enum class TraceFormat : uint8_t { csv, jsonl };

// `named` ("csv" or "jsonl", --trace-format) when given, else the format of
// the file's extension (.csv, .jsonl); nullopt when neither names one.
std::optional<TraceFormat> trace_format(const std::string& named, const std::string& path);

// The columns of a row, in order (the CSV header, the JSON Lines keys).
inline constexpr const char* trace_columns[] = {"step", "time", "body", "asleep", "px", "py", "pz", "qw", "qx",
                                                "qy",   "qz",   "vx",   "vy",     "vz", "wx", "wy", "wz"};

class BodyTrace {
 public:
  BodyTrace(TraceFormat format, uint64_t every) : format_(format), every_(every) {}

  // Creates the file (under a temporary name until finish) and writes the
  // CSV header; false with a reason.
  bool open(const std::string& path, std::string& reason);
  // The rows of every live body, in slot order: at the start of a run
  // whatever its step (a run restored from a snapshot starts mid-way), then
  // after each step whose counter is a multiple of `every`.
  void record_start(const World& world);
  void record(const World& world);
  // Renames the file into place; false with a reason.
  bool finish(std::string& reason);

  // Whether step x dt stays inside Q32.32 (the time column) up to `last_step`.
  static bool time_fits(Fixed dt, uint64_t last_step);

 private:
  void write_rows(const World& world);
  void write_row(const World& world, uint32_t slot);

  TraceFormat format_;
  uint64_t every_;
  AtomicFile file_;
};

// The options --trace FILE, --trace-every K and --trace-format csv|jsonl,
// the same for run, record and verify (declared by tools/cli/shared_options.h).
struct TraceOptions {
  std::string path;  // empty: no trace
  uint64_t every = 1;
  std::string format;  // "csv", "jsonl", or empty: from the extension

  // After the options: an error when a trace is asked for in no format.
  std::string check() const;
  // The trace of a run whose last step is `last_step`, opened, or an error
  // printed as "bitstep COMMAND: --trace: ..." and its exit code (usage:
  // the time column leaves Q32.32; output_failed: the file).
  int open(const char* command, Fixed dt, uint64_t last_step, std::optional<BodyTrace>& trace) const;
  // Renames the file into place, or prints why not; true when done.
  static bool finish(const char* command, std::optional<BodyTrace>& trace);
};

}  // namespace bitstep
