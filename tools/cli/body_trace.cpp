#include "tools/cli/body_trace.h"

#include <fmt/core.h>

#include <array>
#include <cstdint>
#include <cstdio>
#include <cstdlib>
#include <limits>

#include "fixed/decimal.h"
#include "tools/cli/exit_codes.h"

namespace bitstep {

namespace {

bool ends_with(const std::string& text, std::string_view suffix) {
  return text.size() >= suffix.size() && text.compare(text.size() - suffix.size(), suffix.size(), suffix) == 0;
}

// A row's values in the order of trace_columns, each as exact text.
std::array<std::string, std::size(trace_columns)> row_values(const World& world, uint32_t slot) {
  const Body& body = world.bodies()[slot];
  const uint64_t step = world.step_count();
  const Fixed time = Fixed::from_raw(world.settings().dt.raw() * static_cast<int64_t>(step));  // checked by time_fits
  const Vec3& p = body.pose.position;
  const Quat& q = body.pose.orientation;
  const Vec3& v = body.linear_velocity;
  const Vec3& w = body.angular_velocity;
  return {std::to_string(step), to_string(time),  std::to_string(slot), body.asleep ? "true" : "false",
          to_string(p.x),       to_string(p.y),   to_string(p.z),       to_string(q.w),
          to_string(q.x),       to_string(q.y),   to_string(q.z),       to_string(v.x),
          to_string(v.y),       to_string(v.z),   to_string(w.x),       to_string(w.y),
          to_string(w.z)};
}

}  // namespace

std::optional<TraceFormat> trace_format(const std::string& named, const std::string& path) {
  if (named == "csv") return TraceFormat::csv;
  if (named == "jsonl") return TraceFormat::jsonl;
  if (!named.empty()) return std::nullopt;
  if (ends_with(path, ".csv")) return TraceFormat::csv;
  if (ends_with(path, ".jsonl")) return TraceFormat::jsonl;
  return std::nullopt;
}

bool BodyTrace::time_fits(Fixed dt, uint64_t last_step) {
  const auto limit = static_cast<uint64_t>(std::numeric_limits<int64_t>::max() / dt.raw());
  return last_step <= limit;
}

bool BodyTrace::open(const std::string& path, std::string& reason) {
  if (!file_.open(path, reason)) return false;
  if (format_ == TraceFormat::csv) {
    for (size_t i = 0; i < std::size(trace_columns); ++i) {
      fmt::print(file_.stream(), "{}{}", i == 0 ? "" : ",", trace_columns[i]);
    }
    fmt::print(file_.stream(), "\n");
  }
  return true;
}

void BodyTrace::record_start(const World& world) { write_rows(world); }

void BodyTrace::record(const World& world) {
  if (world.step_count() % every_ == 0) write_rows(world);
}

void BodyTrace::write_rows(const World& world) {
  for (uint32_t slot = 0; slot < world.bodies().size(); ++slot) {
    if (world.bodies()[slot].alive) write_row(world, slot);
  }
}

void BodyTrace::write_row(const World& world, uint32_t slot) {
  const auto values = row_values(world, slot);
  std::FILE* out = file_.stream();
  if (format_ == TraceFormat::csv) {
    for (size_t i = 0; i < values.size(); ++i) fmt::print(out, "{}{}", i == 0 ? "" : ",", values[i]);
    fmt::print(out, "\n");
    return;
  }
  // step, body and asleep as JSON numbers and booleans; the Fixed values as
  // strings, as in `run --json`, so that no reader turns them into doubles.
  for (size_t i = 0; i < values.size(); ++i) {
    const bool bare = i == 0 || i == 2 || i == 3;
    fmt::print(out, "{}\"{}\": {}{}{}", i == 0 ? "{" : ", ", trace_columns[i], bare ? "" : "\"", values[i], bare ? "" : "\"");
  }
  fmt::print(out, "}}\n");
}

bool BodyTrace::finish(std::string& reason) { return file_.commit(reason); }

std::string TraceOptions::check() const {
  if (path.empty() || trace_format(format, path)) return {};
  return fmt::format("--trace {}: name it .csv or .jsonl, or give --trace-format", path);
}

int TraceOptions::open(const char* command, Fixed dt, uint64_t last_step, std::optional<BodyTrace>& trace) const {
  if (path.empty()) return exit_code::success;
  if (!BodyTrace::time_fits(dt, last_step)) {
    fmt::print(stderr, "bitstep {}: --trace: the last step's time is beyond the Q32.32 range\n", command);
    return exit_code::usage;
  }
  trace.emplace(*trace_format(format, path), every);
  if (std::string reason; !trace->open(path, reason)) {
    fmt::print(stderr, "bitstep {}: --trace: {}\n", command, reason);
    trace.reset();
    return exit_code::output_failed;
  }
  return exit_code::success;
}

bool TraceOptions::finish(const char* command, std::optional<BodyTrace>& trace) {
  std::string reason;
  if (!trace || trace->finish(reason)) return true;
  fmt::print(stderr, "bitstep {}: --trace: {}\n", command, reason);
  return false;
}

}  // namespace bitstep
