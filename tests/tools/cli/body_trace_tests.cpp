// tools/cli/body_trace: the rows `bitstep run --trace` writes, read back.
#include <catch2/catch.hpp>

#include <filesystem>
#include <fstream>
#include <string>
#include <vector>

#include "fixed/decimal.h"
#include "tools/cli/body_trace.h"

namespace bitstep {

namespace {

// A ground and two boxes falling onto it.
World falling_boxes() {
  World world;
  BodyDef ground;
  ground.type = BodyType::static_body;
  ground.pose.position = {Fixed{}, -1.0_fx, Fixed{}};
  ground.shapes.push_back(Shape{});
  ground.shapes.back().type = ShapeType::box;
  ground.shapes.back().half_extents = {10.0_fx, 1.0_fx, 10.0_fx};
  world.create_body(ground);
  for (int i = 0; i < 2; ++i) {
    BodyDef box;
    box.pose.position = {Fixed::from_int(2 * i), 1.0_fx, Fixed{}};
    box.linear_velocity = {1.0_fx, Fixed{}, -0.5_fx};
    box.shapes.push_back(Shape{});
    box.shapes.back().type = ShapeType::box;
    box.shapes.back().half_extents = {0.5_fx, 0.5_fx, 0.5_fx};
    world.create_body(box);
  }
  return world;
}

std::vector<std::string> lines_of(const std::string& path) {
  std::ifstream file(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(file, line);) lines.push_back(line);
  return lines;
}

std::vector<std::string> split(const std::string& line, char separator) {
  std::vector<std::string> fields(1);
  for (const char c : line) {
    if (c == separator) {
      fields.emplace_back();
    } else {
      fields.back() += c;
    }
  }
  return fields;
}

Fixed exact(const std::string& text) {
  const ParseResult parsed = parse_fixed(text);
  REQUIRE(parsed.ok());
  return parsed.value;
}

std::string temporary_path(const std::string& name) {
  return (std::filesystem::temp_directory_path() / ("bitstep_trace_test_" + name)).string();
}

// Runs the world `steps` steps, tracing as `bitstep run --trace` does.
void trace_run(World& world, int steps, BodyTrace& trace, const std::string& path) {
  std::string reason;
  REQUIRE(trace.open(path, reason));
  trace.record_start(world);
  for (int i = 0; i < steps; ++i) {
    world.step();
    trace.record(world);
  }
  REQUIRE(trace.finish(reason));
}

}  // namespace

TEST_CASE("the format comes from --trace-format, else the extension", "[trace]") {
  CHECK(trace_format("", "a/b.csv") == TraceFormat::csv);
  CHECK(trace_format("", "b.jsonl") == TraceFormat::jsonl);
  CHECK(trace_format("jsonl", "b.csv") == TraceFormat::jsonl);
  CHECK_FALSE(trace_format("", "b.txt").has_value());
  CHECK_FALSE(trace_format("xml", "b.csv").has_value());
}

TEST_CASE("a CSV trace has one row per body per traced step, exact values", "[trace]") {
  World world = falling_boxes();
  const std::string path = temporary_path("rows.csv");
  BodyTrace trace(TraceFormat::csv, 3);
  trace_run(world, 9, trace, path);
  CHECK_FALSE(std::filesystem::exists(path + ".partial"));

  const auto lines = lines_of(path);
  REQUIRE(lines.size() == 1 + 3 * 4);  // the header; 3 bodies at steps 0, 3, 6, 9
  CHECK(lines[0] == "step,time,body,asleep,px,py,pz,qw,qx,qy,qz,vx,vy,vz,wx,wy,wz");
  const auto start = split(lines[2], ',');
  REQUIRE(start.size() == 17);
  CHECK(start[0] == "0");
  CHECK(start[1] == "0");
  CHECK(start[2] == "1");
  CHECK(start[3] == "false");
  CHECK(start[5] == "1");
  CHECK(start[11] == "1");
  CHECK(start[13] == "-0.5");

  // The last rows are the world's state now, bit for bit.
  const auto last = split(lines.back(), ',');
  const Body& body = world.bodies()[2];
  CHECK(last[0] == "9");
  CHECK(exact(last[1]) == Fixed::from_raw(world.settings().dt.raw() * 9));
  CHECK(last[2] == "2");
  CHECK(Vec3{exact(last[4]), exact(last[5]), exact(last[6])} == body.pose.position);
  CHECK(Quat{exact(last[7]), exact(last[8]), exact(last[9]), exact(last[10])} == body.pose.orientation);
  CHECK(Vec3{exact(last[11]), exact(last[12]), exact(last[13])} == body.linear_velocity);
  CHECK(Vec3{exact(last[14]), exact(last[15]), exact(last[16])} == body.angular_velocity);
  std::filesystem::remove(path);
}

TEST_CASE("a trace starting mid-way (a restored run) has the start, then every K-th step", "[trace]") {
  World world = falling_boxes();
  for (int i = 0; i < 5; ++i) world.step();
  const std::string path = temporary_path("restored.csv");
  BodyTrace trace(TraceFormat::csv, 4);
  trace_run(world, 6, trace, path);  // steps 5 (the start) and 8
  const auto lines = lines_of(path);
  REQUIRE(lines.size() == 1 + 3 * 2);
  CHECK(split(lines[1], ',')[0] == "5");
  CHECK(split(lines[4], ',')[0] == "8");
  std::filesystem::remove(path);
}

TEST_CASE("a JSON Lines trace has the same columns as keys", "[trace]") {
  World world = falling_boxes();
  const std::string path = temporary_path("rows.jsonl");
  BodyTrace trace(TraceFormat::jsonl, 1);
  trace_run(world, 2, trace, path);
  const auto lines = lines_of(path);
  REQUIRE(lines.size() == 3 * 3);
  CHECK(lines[1] ==
        R"({"step": 0, "time": "0", "body": 1, "asleep": false, "px": "0", "py": "1", "pz": "0", "qw": "1", "qx": "0", )"
        R"("qy": "0", "qz": "0", "vx": "1", "vy": "0", "vz": "-0.5", "wx": "0", "wy": "0", "wz": "0"})");
  CHECK(lines[8].rfind(R"({"step": 2, "time": ")" + to_string(world.settings().dt * 2.0_fx) + R"(", "body": 2, )", 0) == 0);
  std::filesystem::remove(path);
}

TEST_CASE("a trace that cannot be written fails with a reason and leaves nothing", "[trace]") {
  BodyTrace trace(TraceFormat::csv, 1);
  std::string reason;
  const std::string path = temporary_path("no_such_dir") + "/t.csv";
  CHECK_FALSE(trace.open(path, reason));
  CHECK(reason == "cannot write " + path + ": No such file or directory");
  CHECK_FALSE(std::filesystem::exists(path));
}

TEST_CASE("an unfinished trace leaves no file", "[trace]") {
  const std::string path = temporary_path("unfinished.csv");
  {
    World world = falling_boxes();
    BodyTrace trace(TraceFormat::csv, 1);
    std::string reason;
    REQUIRE(trace.open(path, reason));
    trace.record_start(world);
  }
  CHECK_FALSE(std::filesystem::exists(path));
  CHECK_FALSE(std::filesystem::exists(path + ".partial"));
}

TEST_CASE("the time column's range is checked before a run", "[trace]") {
  CHECK(BodyTrace::time_fits(Fixed::from_ratio(1, 60), 100000000));
  CHECK_FALSE(BodyTrace::time_fits(1000.0_fx, 100000000));
}

}  // namespace bitstep
