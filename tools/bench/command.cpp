// `bitstep bench`: the suite that reports speed against error.
//
//   results      every experiment at 60 Hz and 10 iterations, on each of
//                bitstep's five variants and on Bullet (when its peer program
//                was built): the error, ms/step, the stability time series;
//   sweep        the work-precision sweep: dt x iterations x variants for
//                the cheap experiments, error against ms per simulated
//                second, with the Pareto front marked;
//   scale        ms/step against body count, awake and asleep, with the
//                exponent of a power-law fit;
//   speed        CPU ms/step of bitstep's default and Bullet in standing,
//                impact and settled phases of shipped scenes, and the ratio;
//   costs        an 8-frame rollback's cost and wall128's peak memory;
//   determinism  the final state hash of bitstep and Bullet from the peer
//                programs built at -O0 and at -O3 -ffast-math.
// Everything goes into a report directory: CSV per experiment, summary.md,
// and a gnuplot script per plot drawn as SVG and PNG. This file parses the
// options, runs the chosen sections (tools/bench/sections.h) and writes
// summary.md.
#include "tools/bench/command.h"

#include <fmt/core.h>
#include <unistd.h>

#include <chrono>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <set>
#include <sstream>
#include <string>
#include <string_view>

#include "replay/scene.h"
#include "tools/bench/context.h"
#include "tools/bench/headline.h"
#include "tools/bench/report.h"
#include "tools/bench/sections.h"
#include "tools/cli/exit_codes.h"
#include "tools/cli/file_output.h"
#include "tools/cli/options.h"
#include "tools/cli/shared_options.h"

namespace bitstep {

namespace {

using namespace bitstep::bench;

// The sections in the order they run and appear in summary.md.
struct SectionEntry {
  const char* name;
  int (*runs)(const Context&);
  Section (*run)(Context&);
};

constexpr SectionEntry all_sections[] = {
    {"results", results_runs, run_results}, {"sweep", sweep_runs, run_sweep},
    {"scale", scale_runs, run_scale},       {"speed", speed_runs, run_speed},
    {"costs", costs_runs, run_costs},       {"determinism", determinism_runs, run_determinism},
};

std::string machine_line(const Options& options, double seconds) {
  std::string cpu = "unknown CPU";
  std::ifstream info("/proc/cpuinfo");
  std::string line;
  while (std::getline(info, line)) {
    if (line.rfind("model name", 0) == 0) {
      cpu = line.substr(line.find(':') + 2);
      break;
    }
  }
  const std::time_t now = std::time(nullptr);
  char date[32];
  std::strftime(date, sizeof date, "%Y-%m-%d", std::gmtime(&now));
  return fmt::format(
      "{}, {}, {} hardware threads, single-threaded runs (but the speed section's threads column); `bitstep bench{}` "
      "took {:.0f} s.",
      date, cpu, sysconf(_SC_NPROCESSORS_ONLN), options.quick ? " --quick" : "", seconds);
}

// The headline table from `report`'s CSV files, written into `readme`
// (check: compared with it instead). Returns the exit code; says why on
// stderr when it is not success.
int update_headline(const std::string& command, const std::string& report, const std::string& readme, bool check) {
  const Result<std::string> results = read_text_file(report + "/results.csv");
  const Result<std::string> speed = read_text_file(report + "/speed.csv");
  const Result<std::string> old_text = read_text_file(readme);
  for (const Result<std::string>* read : {&results, &speed, &old_text}) {
    if (!read->ok()) {
      fmt::print(stderr, "{}: {}\n", command, read->error().message());
      return exit_code::bad_input;
    }
  }
  const Result<std::string> block = headline_block(results.value(), speed.value());
  if (!block.ok()) {
    fmt::print(stderr, "{}: {}\n", command, block.error().within(report).message());
    return exit_code::bad_input;
  }
  const Result<std::string> new_text = with_headline(old_text.value(), block.value());
  if (!new_text.ok()) {
    fmt::print(stderr, "{}: {}\n", command, new_text.error().within(readme).message());
    return exit_code::bad_input;
  }
  if (check) {
    if (new_text.value() == old_text.value()) return exit_code::success;
    fmt::print(stderr, "{}: {}: its headline table is not the one {} gives (bitstep bench headline writes it)\n",
               command, readme, report);
    return exit_code::check_failed;
  }
  std::string reason;
  if (!write_file_atomically(readme, new_text.value(), reason)) {
    fmt::print(stderr, "{}: {}\n", command, reason);
    return exit_code::output_failed;
  }
  fmt::print("headline table: {} (from {})\n", readme, report);
  return exit_code::success;
}

// Runs the chosen sections; writes summary.md. Returns the exit code.
int run_bench(const Options& options) {
  Context context(options);
  std::error_code error;
  std::filesystem::create_directories(options.out, error);
  if (error) {
    fmt::print(stderr, "bitstep bench: cannot create {}: {}\n", options.out, error.message());
    return exit_code::output_failed;
  }
  context.plots = gnuplot_available();
  int planned = 0;
  for (const SectionEntry& s : all_sections) planned += context.wants(s.name) ? s.runs(context) : 0;
  ProgressBar progress(planned);
  context.progress = &progress;
  if (!context.peer_note.empty()) progress.note(context.peer_note);
  if (!context.plots) progress.note("plots skipped: gnuplot not found (tools/install_deps.sh bench installs gnuplot-nox)");
  const auto start = std::chrono::steady_clock::now();
  bool ok = true;
  std::string sections;
  for (const SectionEntry& s : all_sections) {
    if (!context.wants(s.name)) continue;
    const Section section = s.run(context);
    ok = section.ok && ok;
    sections += section.markdown;
  }
  const std::chrono::duration<double> elapsed = std::chrono::steady_clock::now() - start;
  progress.finish();
  std::string md = fmt::format("# bitstep bench report\n\n{}\n\n", machine_line(options, elapsed.count()));
  if (!context.peer_note.empty()) md += context.peer_note + ".\n\n";
  ok = context.write("summary.md", md + sections) && ok;
  if (context.write_failed) return exit_code::output_failed;  // its line was printed
  fmt::print("report: {}/summary.md ({:.0f} s)\n", options.out, elapsed.count());
  if (ok && !options.readme.empty()) return update_headline("bitstep bench", options.out, options.readme, false);
  return ok ? exit_code::success : exit_code::check_failed;
}

std::set<std::string> split(const std::string& list) {
  std::set<std::string> items;
  std::stringstream in(list);
  std::string item;
  while (std::getline(in, item, ',')) {
    if (!item.empty()) items.insert(item);
  }
  return items;
}

// The suite's command line into `options`: nullopt, or the exit status
// (--help, a usage error).
std::optional<int> parse_options(int argc, char** argv, Options& options) {
  CLI::App app("the suite: accuracy, stability, work-precision, scale, speed and costs, next to Bullet",
               "bitstep bench");
  CLI::Option* quick = app.add_flag_callback("--quick", [&options] { options.quick = true; }, "the short run");
  CLI::Option* full = app.add_flag_callback("--full", [&options] { options.quick = false; }, "the whole run");
  quick->excludes(full);
  app.footer("one bench alone: bitstep bench fixed|queries|session|sleep [--help]");
  app.add_option("--out", options.out, "the report's folder (default bench-report)")->type_name("DIR");
  app.add_option("--scenes", options.scenes, "the scenes' folder")->type_name("DIR");
  app.add_flag_callback("--no-peer", [&options] { options.peer = false; }, "leave Bullet out");
  app.add_option("--readme", options.readme,
                 "after a full run, write its headline table into FILE (between its headline markers)")
      ->type_name("FILE");
  cli::add_threads(app, options.threads, 2, "the workers of the speed table's threaded column (default 2)");
  cli::add_read(
      app, "--sections", "a list of results, sweep, scale, speed, costs, determinism",
      [&options](const std::string& list) {
        options.sections = split(list);
        for (const std::string& s : options.sections) {
          if (s != "results" && s != "sweep" && s != "scale" && s != "speed" && s != "costs" && s != "determinism") {
            return false;
          }
        }
        return true;
      },
      "the sections to run, comma-separated: results,sweep,scale,speed,costs,determinism")
      ->type_name("LIST");
  cli::add_read(
      app, "--only", "a list of experiments",
      [&options](const std::string& list) {
        options.only = split(list);
        for (const std::string& name : options.only) {
          if (find_experiment(name) == nullptr) cli::refuse("--only", "known experiments", name);
        }
        return true;
      },
      "only these experiments, comma-separated")
      ->type_name("EXPERIMENTS");
  return cli::parse(app, "bench", argc, argv);
}

}  // namespace

int run_bench_headline(int argc, char** argv) {
  std::string report = "tools/report", readme = "README.md";
  bool check = false;
  CLI::App app("the README's headline table, from a report's results.csv and speed.csv", "bitstep bench headline");
  app.add_option("--report", report, "the report's folder (default tools/report)")->type_name("DIR");
  app.add_option("--readme", readme, "the file holding the table (default README.md)")->type_name("FILE");
  app.add_flag("--check", check, "write nothing; exit 1 when the file's table is not the report's");
  if (const std::optional<int> code = cli::parse(app, "bench headline", argc, argv)) return *code;
  return update_headline("bitstep bench headline", report, readme, check);
}

int run_bench_suite(int argc, char** argv) {
  Options options;
  if (const std::optional<int> code = parse_options(argc, argv, options)) return *code;
  try {
    return run_bench(options);
  } catch (const std::exception& error) {
    fmt::print(stderr, "bitstep bench: {}\n", error.what());
    return 1;
  }
}

}  // namespace bitstep
