// The bitstep command line's failures: each exits with its code
// (tools/cli/exit_codes.h) and one line on stderr, and leaves no output
// file, whole or partial, behind. The tests run the built binary.
#include <catch2/catch.hpp>
#include <sys/wait.h>

#include <cstdlib>
#include <filesystem>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/tools/cli/cli_support.h"
#include "tools/cli/exit_codes.h"

namespace {

using namespace bitstep::test_cli;

// The files in `dir` other than the captured output.
int files_written(const TempDir& dir) {
  int n = 0;
  for (const auto& entry : std::filesystem::directory_iterator(dir.path)) {
    const std::string name = entry.path().filename().string();
    n += name != "stdout.txt" && name != "stderr.txt" && entry.is_regular_file();
  }
  return n;
}

void copy_scene(const TempDir& dir, const std::string& name) {
  std::filesystem::copy_file(scenes_dir + "/" + name, dir / name);
}

}  // namespace

TEST_CASE("bitstep: an unwritable output fails at once with code 5 and leaves nothing", "[tools][cli]") {
  const TempDir dir("unwritable");
  copy_scene(dir, "bounce.json");
  Run r = run_bitstep(dir, "record bounce.json --steps 10 -o missing/out.replay.json");
  CHECK(r.status == bitstep::exit_code::output_failed);
  CHECK(r.err == "bitstep record: cannot write missing/out.replay.json: No such file or directory\n");
  r = run_bitstep(dir, "run bounce.json --steps 10 --snapshot-at 5 missing/snap.bin");
  CHECK(r.status == bitstep::exit_code::output_failed);
  CHECK(r.err == "bitstep run: --snapshot-at: cannot write missing/snap.bin: No such file or directory\n");
  r = run_bitstep(dir, "run bounce.json --steps 10 --trace missing/trace.csv");
  CHECK(r.status == bitstep::exit_code::output_failed);
  CHECK(r.err == "bitstep run: --trace: cannot write missing/trace.csv: No such file or directory\n");
  r = run_bitstep(dir, "verify '" + scenes_dir + "/bounce.replay.json' --dump-at 3 missing/dump.json");
  CHECK(r.status == bitstep::exit_code::output_failed);
  CHECK(r.err == "bitstep verify: cannot write missing/dump.json: No such file or directory\n");
  r = run_bitstep(dir, "bench fixed --quick --csv missing/fixed.csv");
  CHECK(r.status == bitstep::exit_code::output_failed);
  CHECK(r.err == "bitstep bench fixed: cannot write missing/fixed.csv: No such file or directory\n");
  CHECK(files_written(dir) == 1);  // the scene only
}

TEST_CASE("bitstep: outputs are whole files under their names, never partial ones", "[tools][cli]") {
  const TempDir dir("outputs");
  copy_scene(dir, "bounce.json");
  Run r = run_bitstep(dir, "record bounce.json --steps 20 -o out.replay.json");
  REQUIRE(r.status == 0);
  r = run_bitstep(dir, "verify out.replay.json --dump-at 20 dump.json");
  CHECK(r.status == 0);
  r = run_bitstep(dir, "run bounce.json --steps 20 --snapshot-at 10 snap.bin --trace trace.csv");
  CHECK(r.status == 0);
  r = run_bitstep(dir, "run bounce.json --steps 10 --restore snap.bin");
  CHECK(r.status == 0);
  for (const auto& entry : std::filesystem::directory_iterator(dir.path)) {
    CHECK(entry.path().extension() != ".partial");
  }
  CHECK(files_written(dir) == 5);
  // A snapshot step the run never reaches is a usage error, not silence.
  r = run_bitstep(dir, "run bounce.json --steps 10 --snapshot-at 11 never.bin");
  CHECK(r.status == bitstep::exit_code::usage);
  CHECK(r.err == "bitstep run: --snapshot-at 11: the run has steps 1..10\n");
  CHECK_FALSE(std::filesystem::exists(dir / "never.bin"));
}

TEST_CASE("bitstep: a refused input file exits 4 naming it, a failed check 1", "[tools][cli]") {
  const TempDir dir("inputs");
  copy_scene(dir, "bounce.json");
  copy_scene(dir, "stack20.json");
  // A replay whose scene is not beside it.
  std::filesystem::copy_file(scenes_dir + "/bounce.replay.json", dir / "alone.replay.json");
  std::filesystem::remove(dir / "bounce.json");
  Run r = run_bitstep(dir, "verify alone.replay.json");
  CHECK(r.status == bitstep::exit_code::bad_input);
  CHECK(r.err ==
        "bitstep verify: alone.replay.json: $.scene: bounce.json: cannot read the file (no such regular file)\n");
  copy_scene(dir, "bounce.json");
  CHECK(run_bitstep(dir, "verify alone.replay.json").status == 0);

  // A missing inputs file, a missing scene, a missing snapshot.
  r = run_bitstep(dir, "record bounce.json --inputs none.json --steps 5 -o x.replay.json");
  CHECK(r.status == bitstep::exit_code::bad_input);
  CHECK(r.err == "bitstep record: none.json: cannot read the file (no such regular file)\n");
  r = run_bitstep(dir, "run none.json");
  CHECK(r.status == bitstep::exit_code::bad_input);
  CHECK(r.err == "bitstep run: none.json: cannot read the file (no such regular file)\n");
  r = run_bitstep(dir, "run bounce.json --restore none.bin");
  CHECK(r.status == bitstep::exit_code::bad_input);
  CHECK(r.err == "bitstep run: none.bin: cannot read the file (no such regular file)\n");
  r = run_bitstep(dir, "diff none.json other.json");
  CHECK(r.status == bitstep::exit_code::bad_input);
  CHECK(r.err == "bitstep diff: none.json: cannot read the file (no such regular file)\n");

  // A snapshot of another scene given to run --restore.
  REQUIRE(run_bitstep(dir, "run stack20.json --steps 5 --snapshot-at 5 stack.bin").status == 0);
  r = run_bitstep(dir, "run bounce.json --steps 5 --restore stack.bin");
  CHECK(r.status == bitstep::exit_code::bad_input);
  CHECK(r.err == "bitstep run: stack.bin: not a snapshot of bounce.json: its settings differ from the scene's\n");
  r = run_bitstep(dir, "run stack20.json --settings '{\"velocity_iterations\": 10}' --steps 5 --restore stack.bin");
  CHECK(r.status == 0);
  // Same settings, other bodies: the stack's cubes smaller.
  std::string smaller = read_all(dir / "stack20.json");
  const size_t half = smaller.find("\"half_extents\": [0.5, 0.5, 0.5]");
  REQUIRE(half != std::string::npos);
  smaller.replace(half, 31, "\"half_extents\": [0.4, 0.5, 0.4]");
  std::ofstream(dir / "thin.json", std::ios::binary) << smaller;
  r = run_bitstep(dir, "run thin.json --steps 5 --restore stack.bin");
  CHECK(r.status == bitstep::exit_code::bad_input);
  CHECK(r.err ==
        "bitstep run: stack.bin: not a snapshot of thin.json: slot 1 holds another body than the scene's body 1\n");
  // Fewer slots than the scene fills.
  REQUIRE(run_bitstep(dir, "run bounce.json --steps 1 --snapshot-at 1 bounce.bin").status == 0);
  r = run_bitstep(dir, "run stack20.json --settings '{\"restitution_threshold\": 0.1}' --restore bounce.bin");
  CHECK(r.status == bitstep::exit_code::bad_input);
  CHECK(r.err == "bitstep run: bounce.bin: not a snapshot of stack20.json: it has 2 body slots, the scene 21\n");
  // A damaged snapshot.
  std::ofstream(dir / "bad.bin", std::ios::binary) << "BITSTEPS";
  r = run_bitstep(dir, "run bounce.json --restore bad.bin");
  CHECK(r.status == bitstep::exit_code::bad_input);
  CHECK(r.err == "bitstep run: bad.bin: truncated: 8 bytes is less than a header\n");

  // A failed check keeps code 1: a replay whose chain differs.
  std::string replay = read_all(scenes_dir + "/bounce.replay.json");
  const size_t impulse = replay.find("[300, 0, 0]");
  REQUIRE(impulse != std::string::npos);
  replay.replace(impulse, 11, "[301, 0, 0]");
  std::ofstream(dir / "tampered.replay.json", std::ios::binary) << replay;
  r = run_bitstep(dir, "verify tampered.replay.json");
  CHECK(r.status == bitstep::exit_code::check_failed);
  CHECK(r.out.find("tampered.replay.json: DIFFERS at step 100 of 240") == 0);
}

TEST_CASE("bitstep: usage errors exit 2, and help lists the exit codes", "[tools][cli]") {
  const TempDir dir("usage");
  Run r = run_bitstep(dir, "record --steps 1000001 -o x.replay.json scene.json");
  CHECK(r.status == bitstep::exit_code::usage);
  CHECK(r.err == "bitstep record: --steps needs an integer 0..1000000, got '1000001'\n");
  r = run_bitstep(dir, "verify --frobnicate");
  CHECK(r.status == bitstep::exit_code::usage);
  r = run_bitstep(dir, "help");
  CHECK(r.status == 0);
  CHECK(r.out.find("  4  an input file refused") != std::string::npos);
  CHECK(r.out.find("  5  an output file could not be written") != std::string::npos);
  CHECK(r.out.find("  6  peer: another peer refused our hello") != std::string::npos);
}

TEST_CASE("bitstep: every command's usage error is one line and exit 2, its --help exit 0", "[tools][cli]") {
  const TempDir dir("options");
  for (const char* command : {"run", "record", "verify", "diff", "synctest", "peer", "selftest", "bench",
                              "bench fixed", "bench queries", "bench session", "bench sleep", "version"}) {
    INFO(command);
    Run r = run_bitstep(dir, std::string(command) + " --no-such-option");
    CHECK(r.status == bitstep::exit_code::usage);
    CHECK(lines_of(r.err).size() == 1);
    CHECK(r.err.find("--no-such-option") != std::string::npos);
    r = run_bitstep(dir, std::string(command) + " --help");
    CHECK(r.status == 0);
    CHECK(r.out.find("bitstep " + std::string(command)) != std::string::npos);
    CHECK(r.err.empty());
  }
  // A missing value, a bad number, a missing argument: one line naming what is wrong.
  Run r = run_bitstep(dir, "run scene.json --steps");
  CHECK(r.status == bitstep::exit_code::usage);
  CHECK(lines_of(r.err).size() == 1);
  CHECK(r.err.find("--steps") != std::string::npos);
  r = run_bitstep(dir, "run scene.json --steps 1x");
  CHECK(r.status == bitstep::exit_code::usage);
  CHECK(r.err == "bitstep run: --steps needs a non-negative integer, got '1x'\n");
  r = run_bitstep(dir, "verify --threads 65 a.replay.json");
  CHECK(r.status == bitstep::exit_code::usage);
  CHECK(r.err == "bitstep verify: --threads needs an integer 1..64, got '65'\n");
  r = run_bitstep(dir, "run");
  CHECK(r.status == bitstep::exit_code::usage);
  CHECK(lines_of(r.err).size() == 1);
  CHECK(r.err.find("SCENE") != std::string::npos);
}

namespace {

// A CSV trace row's step (its first column).
long long row_step(const std::string& row) { return std::atoll(row.c_str()); }

}  // namespace

TEST_CASE("bitstep: verify and record --trace write run --trace's rows, and a replay's inputs move them",
          "[tools][cli][trace]") {
  const TempDir dir("trace");
  copy_scene(dir, "incline.json");
  copy_scene(dir, "incline.replay.json");
  // No inputs: record, verify and run trace the same rows.
  Run r = run_bitstep(dir, "record incline.json --steps 30 -o quiet.replay.json --trace record.csv");
  REQUIRE(r.status == 0);
  CHECK(r.out.find("trace written to record.csv") != std::string::npos);
  REQUIRE(run_bitstep(dir, "verify quiet.replay.json --trace verify.csv --trace-every 1").status == 0);
  REQUIRE(run_bitstep(dir, "run incline.json --steps 30 --trace run.csv").status == 0);
  const std::string run_rows = read_all(dir / "run.csv");
  CHECK(lines_of(run_rows).size() == 1 + 31 * 5u);  // the header, then 5 bodies at steps 0..30
  CHECK(read_all(dir / "record.csv") == run_rows);
  CHECK(read_all(dir / "verify.csv") == run_rows);
  // incline.replay.json pushes a cube at step 60: the rows agree before it
  // and differ from it on.
  REQUIRE(run_bitstep(dir, "verify incline.replay.json --trace pushed.jsonl").status == 0);
  REQUIRE(run_bitstep(dir, "verify incline.replay.json --trace pushed.csv").status == 0);
  REQUIRE(run_bitstep(dir, "run incline.json --steps 120 --trace unpushed.csv").status == 0);
  CHECK(lines_of(read_all(dir / "pushed.jsonl")).size() == 121 * 5u);
  const std::vector<std::string> pushed = lines_of(read_all(dir / "pushed.csv"));
  const std::vector<std::string> unpushed = lines_of(read_all(dir / "unpushed.csv"));
  REQUIRE(pushed.size() == unpushed.size());
  size_t differ_before = 0, differ_after = 0;
  for (size_t i = 1; i < pushed.size(); ++i) {
    if (pushed[i] == unpushed[i]) continue;
    (row_step(pushed[i]) < 60 ? differ_before : differ_after) += 1;
  }
  CHECK(differ_before == 0);
  CHECK(differ_after > 60);
  // Usage: one replay, a format.
  r = run_bitstep(dir, "verify incline.replay.json quiet.replay.json --trace x.csv");
  CHECK(r.status == bitstep::exit_code::usage);
  r = run_bitstep(dir, "verify incline.replay.json --trace x.txt");
  CHECK(r.status == bitstep::exit_code::usage);
  CHECK(r.err == "bitstep verify: --trace x.txt: name it .csv or .jsonl, or give --trace-format\n");
}

// Every report of a 2 cm die of 10 g runs (the checked build's binary in
// the checked build: its first report line aborted there).
TEST_CASE("bitstep: a 10 g die runs through every report", "[tools][cli][envelope]") {
  const TempDir dir("die");
  std::ofstream(dir / "die.json") << R"({"format": "bitstep-scene", "version": 1, "bodies": [
    {"name": "table", "type": "static", "position": [0, -0.5, 0], "shapes": [{"type": "box", "half_extents": [1, 0.5, 1]}]},
    {"name": "die", "position": [0, 0.3, 0], "mass": 0.01, "velocity": [2, 0, 0], "angular_velocity": [0, 0, 30],
     "shapes": [{"type": "box", "half_extents": [0.01, 0.01, 0.01]}]}]})";
  Run r = run_bitstep(dir, "run die.json --seconds 2");
  CHECK(r.status == 0);
  CHECK(r.err.empty());
  r = run_bitstep(dir, "run die.json --seconds 2 --json --events --trace die.jsonl");
  CHECK(r.status == 0);
  CHECK(r.out.find("\"kind\": \"contact begin\"") != std::string::npos);
  CHECK(lines_of(read_all(dir / "die.jsonl")).size() == 2 * 121u);
  r = run_bitstep(dir, "record die.json --steps 120 -o die.replay.json --trace die.csv");
  CHECK(r.status == 0);
  r = run_bitstep(dir, "verify die.replay.json --trace die2.csv");
  CHECK(r.status == 0);
  CHECK(read_all(dir / "die.csv") == read_all(dir / "die2.csv"));
}
