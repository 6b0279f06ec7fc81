#include "tools/bench/headline.h"

#include <fmt/core.h>

#include <algorithm>
#include <charconv>
#include <map>
#include <optional>
#include <utility>
#include <vector>

#include "tools/bench/experiments.h"
#include "tools/bench/speed.h"

namespace bitstep::bench {

namespace {

// The experiments the front page shows: one of each kind a user asks about
// first (an exact answer, a joint, a tall stack, the largest wall, a hard
// impact, a mass ratio), bitstep's default against Bullet.
constexpr const char* shown[] = {"free_fall", "pendulum", "chain_stretch", "stack50",
                                 "wall128",   "thrown",   "heavy_on_light"};
constexpr std::string_view bitstep_variant = "standard+shock";
constexpr std::string_view peer_variant = "bullet";

using Record = std::vector<std::string>;

// One CSV line into fields; a quoted field may hold commas and doubled
// quotes (what report.h's csv_field writes).
std::optional<Record> split_line(std::string_view line) {
  Record fields(1);
  bool quoted = false;
  for (size_t i = 0; i < line.size(); ++i) {
    const char c = line[i];
    if (quoted) {
      if (c != '"') {
        fields.back() += c;
      } else if (i + 1 < line.size() && line[i + 1] == '"') {
        fields.back() += '"';
        ++i;
      } else {
        quoted = false;
      }
    } else if (c == '"') {
      quoted = true;
    } else if (c == ',') {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  if (quoted) return std::nullopt;
  return fields;
}

// A CSV row: column name -> field, and where it stands ("results.csv: line 7").
struct CsvRow {
  std::string place;
  std::map<std::string, std::string> fields;
};

// A CSV file's rows under its header line; an error names the line.
Result<std::vector<CsvRow>> read_csv(std::string_view text, const std::string& name) {
  std::vector<CsvRow> rows;
  Record header;
  int line_number = 0;
  while (!text.empty()) {
    const size_t end = std::min(text.find('\n'), text.size());
    const std::string_view line = text.substr(0, end);
    text.remove_prefix(std::min(end + 1, text.size()));
    ++line_number;
    if (line.empty()) continue;
    const std::optional<Record> fields = split_line(line);
    const std::string place = fmt::format("{}: line {}", name, line_number);
    if (!fields) return Error{place, "a quoted field is not closed"};
    if (header.empty()) {
      header = *fields;
      continue;
    }
    if (fields->size() != header.size()) {
      return Error{place, fmt::format("{} fields, the header has {}", fields->size(), header.size())};
    }
    CsvRow& row = rows.emplace_back();
    row.place = place;
    for (size_t i = 0; i < header.size(); ++i) row.fields[header[i]] = (*fields)[i];
  }
  if (header.empty()) return Error{name, "empty"};
  return rows;
}

// A field that must be a number; an error names it.
Result<double> number(const CsvRow& row, const std::string& column) {
  const std::string& place = row.place;
  const auto found = row.fields.find(column);
  if (found == row.fields.end()) return Error{place, "no column " + column};
  double value = 0;
  const std::string& text = found->second;
  const auto [end, error] = std::from_chars(text.data(), text.data() + text.size(), value);
  if (error != std::errc() || end != text.data() + text.size()) {
    return Error{place, fmt::format("{} is '{}', not a number", column, text)};
  }
  return value;
}

struct Cell {
  std::string error = "-", ms = "-";
};

// The range and median of the ratio of bitstep's median CPU ms/step to
// Bullet's, over the speed table's cases (a scene in a phase).
Result<std::string> speed_sentence(std::string_view speed_csv) {
  const auto rows = read_csv(speed_csv, "speed.csv");
  if (!rows.ok()) return rows.error();
  std::vector<std::pair<std::string, std::pair<std::vector<double>, std::vector<double>>>> cases;
  std::vector<std::string> phase_names;
  for (const CsvRow& row : rows.value()) {
    const auto bitstep = number(row, "bitstep_cpu_ms_per_step");
    if (!bitstep.ok()) return bitstep.error();
    const auto peer = number(row, "bullet_cpu_ms_per_step");
    if (!peer.ok()) return peer.error();
    const auto scene = row.fields.find("scene"), phase = row.fields.find("phase");
    if (scene == row.fields.end() || phase == row.fields.end()) return Error{row.place, "no scene or phase column"};
    const std::string key = scene->second + " " + phase->second;
    if (std::find(phase_names.begin(), phase_names.end(), phase->second) == phase_names.end()) {
      phase_names.push_back(phase->second);
    }
    auto found = std::find_if(cases.begin(), cases.end(), [&](const auto& c) { return c.first == key; });
    if (found == cases.end()) found = cases.insert(cases.end(), {key, {}});
    found->second.first.push_back(bitstep.value());
    found->second.second.push_back(peer.value());
  }
  if (cases.empty()) return Error{"speed.csv", "no rows"};
  std::vector<double> ratios;
  for (const auto& [key, times] : cases) ratios.push_back(median(times.first) / median(times.second));
  const auto [low, high] = std::minmax_element(ratios.begin(), ratios.end());
  std::string phases;
  for (const std::string& phase : phase_names) phases += (phases.empty() ? "" : ", ") + phase;
  return fmt::format(
      "Speed: in the report's {} cases of a scene and a phase ({}), bitstep takes {:.2f}x to {:.2f}x Bullet's CPU "
      "time per step on one thread, median {:.2f}x.\n",
      ratios.size(), phases, *low, *high, median(ratios));
}

}  // namespace

Result<std::string> headline_block(std::string_view results_csv, std::string_view speed_csv) {
  const auto rows = read_csv(results_csv, "results.csv");
  if (!rows.ok()) return rows.error();
  std::map<std::string, std::pair<Cell, Cell>> cells;  // experiment -> bitstep, Bullet
  for (const CsvRow& row : rows.value()) {
    const auto experiment = row.fields.find("experiment"), variant = row.fields.find("variant");
    if (experiment == row.fields.end() || variant == row.fields.end()) {
      return Error{row.place, "no experiment or variant column"};
    }
    if (variant->second != bitstep_variant && variant->second != peer_variant) continue;
    const auto error = number(row, "error");
    if (!error.ok()) return error.error();
    const auto failed = number(row, "failed");
    if (!failed.ok()) return failed.error();
    const auto ms = number(row, "ms_per_step");
    if (!ms.ok()) return ms.error();
    Cell& cell =
        variant->second == bitstep_variant ? cells[experiment->second].first : cells[experiment->second].second;
    cell.error = fmt::format("{:.3g}{}", error.value(), failed.value() != 0 ? " fell" : "");
    cell.ms = fmt::format("{:.3g}", ms.value());
  }
  const auto speed = speed_sentence(speed_csv);
  if (!speed.ok()) return speed.error();
  std::string md = fmt::format(
      "{}\n| experiment | measured | bitstep | Bullet 3.24 | bitstep ms/step | Bullet ms/step |\n"
      "|---|---|---:|---:|---:|---:|\n",
      headline_begin);
  for (const char* name : shown) {
    const Experiment* experiment = find_experiment(name);
    const auto found = cells.find(name);
    if (experiment == nullptr || found == cells.end()) return Error{"results.csv", fmt::format("no row for {}", name)};
    const auto& [ours, theirs] = found->second;
    // The description less what --quick would change: the report is a full run.
    const std::string& description = experiment->description;
    const std::string what = description.substr(0, description.find(" (quick:"));
    md += fmt::format("| {} | {} | {} | {} | {} | {} |\n", what, experiment->error_label, ours.error, theirs.error,
                      ours.ms, theirs.ms);
  }
  return md + "\n" + speed.value() + std::string(headline_end) + "\n";
}

Result<std::string> with_headline(std::string_view readme, std::string_view block) {
  const size_t begin = readme.find(headline_begin);
  const size_t end = readme.find(headline_end);
  if (begin == std::string_view::npos || end == std::string_view::npos || end < begin) {
    return Error{"", fmt::format("no '{}' line followed by '{}'", headline_begin, headline_end)};
  }
  const size_t after = std::min(readme.find('\n', end), readme.size());
  std::string text(readme.substr(0, begin));
  text += block;
  if (after < readme.size()) text += readme.substr(after + 1);
  return text;
}

}  // namespace bitstep::bench
