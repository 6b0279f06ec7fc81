// The world envelope's corners (tests/envelope_corners.h) through every
// command: `run --json --events --trace`, `record` with the largest impulse
// and force at the farthest point and a velocity set past the clamps, and
// `--trace`, `verify --trace`, `synctest` and `bench sleep`: exit 0 and nothing on stderr
// (the checked build, whose binary the checked tests run, aborts on any
// saturation, and its sanitizers report there), the same trace from record
// and verify, and step 0's velocities as written.
#include <catch2/catch.hpp>

#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "tests/envelope_corners.h"
#include "tests/test_support.h"
#include "tests/tools/cli/cli_support.h"

using namespace bitstep;
using namespace bitstep::test_cli;
using namespace bitstep::test_envelope;
using bitstep::test::to_double;

namespace {

// The largest impulse and force at the farthest point the inputs admit,
// and a velocity set at the input bounds (500 m/s, 100 rad/s), which the
// world clamps to the body's limits, on each named body.
std::string inputs_for(const std::vector<std::string>& bodies) {
  std::ostringstream inputs;
  int step = 2;
  for (const std::string& body : bodies) {
    const std::string who = "\"body\": \"" + body + "\"";
    inputs << (step == 2 ? "" : ",\n") << "{\"step\": " << step << ", \"type\": \"impulse\", " << who
           << ", \"impulse\": [1000000, -1000000, 0], \"point\": [16000, 16000, -16000]},\n"
           << "{\"step\": " << step + 1 << ", \"type\": \"force\", " << who
           << ", \"force\": [0, 1000000, 1000000], \"point\": [-16000, 16000, 16000]},\n"
           << "{\"step\": " << step + 2 << ", \"type\": \"set_velocity\", " << who
           << ", \"linear\": [500, 0, 0], \"angular\": [0, 0, 100]}";
    step += 3;
  }
  return "{\"inputs\": [\n" + inputs.str() + "]}";
}

// Step 0's rows of a CSV trace: per body, its six velocity components.
std::vector<std::vector<double>> first_velocities(const std::string& csv) {
  std::vector<std::vector<double>> rows;
  const std::vector<std::string> lines = lines_of(csv);
  for (size_t i = 1; i < lines.size() && lines[i].rfind("0,", 0) == 0; ++i) {
    std::vector<double> fields;
    std::stringstream row(lines[i]);
    for (std::string field; std::getline(row, field, ',');) fields.push_back(std::atof(field.c_str()));
    rows.push_back(std::vector<double>(fields.end() - 6, fields.end()));  // vx vy vz wx wy wz
  }
  return rows;
}

// The scene through every command; `thrown`: the bodies written with a
// velocity (every second body), to compare with the trace's step 0.
void sweep(const std::string& name, const std::string& scene, const std::vector<std::string>& pushed,
           const std::vector<Corner>& thrown = {}) {
  INFO(name);
  const TempDir dir("sweep_" + name);
  std::ofstream(dir / "scene.json") << scene;
  std::ofstream(dir / "inputs.json") << inputs_for(pushed);
  const auto check = [&](const std::string& args) {
    INFO(args);
    const Run r = run_bitstep(dir, args);
    INFO(r.err);
    CHECK(r.status == 0);
    CHECK(r.err.empty());
  };
  check("run scene.json --seconds 1 --json --events --trace run.csv");
  check("record scene.json --inputs inputs.json --steps 60 -o sweep.replay.json --trace record.csv");
  check("verify sweep.replay.json --trace verify.csv");
  CHECK(read_all(dir / "record.csv") == read_all(dir / "verify.csv"));
  check("synctest sweep.replay.json --frames 8");
  // The bench's commands that read a scene of the user's (`bench sleep`
  // reads stack20.json and pyramid20.json from --scenes): the scene
  // stepped awake, then with each sleep method until all sleeps (600 steps
  // at most), the sleepers checked still.
  std::ofstream(dir / "stack20.json") << scene;
  std::ofstream(dir / "pyramid20.json") << scene;
  check("bench sleep --quick --scenes .");
  check("bench sleep --quick --still --scenes .");
  const std::vector<std::vector<double>> written = first_velocities(read_all(dir / "run.csv"));
  for (size_t i = 0; i < thrown.size(); ++i) {
    INFO(thrown[i].name);
    REQUIRE(2 * i + 1 < written.size());
    const Vec3 v = thrown[i].velocity, w = thrown[i].spin;
    const double expected[6] = {to_double(v.x), to_double(v.y), to_double(v.z),
                                to_double(w.x), to_double(w.y), to_double(w.z)};
    for (int k = 0; k < 6; ++k) CHECK(written[2 * i + 1][static_cast<size_t>(k)] == Approx(expected[k]).margin(1e-9));
  }
}

}  // namespace

TEST_CASE("the envelope's corners run through every command", "[tools][cli][envelope]") {
  for (const auto& [kind, sizes] : corner_kinds()) {
    const std::vector<Corner> corners = corners_of(kind, sizes);
    sweep(kind, throw_scene(corners), {corners.front().name, corners.back().name}, corners);
  }
  sweep("stack_smallest", stack_scene(envelope::min_size), {"level_0", "level_5"});
  sweep("stack_half_metre", stack_scene(0.5_fx), {"level_2"});
  sweep("meeting", meeting_scene(), {"meet_1_a", "meet_2_b"});
}
