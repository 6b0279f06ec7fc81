// The world envelope's corners through every command, written as a user
// writes them. Generated: every shape kind (and a compound) at the smallest
// and largest size, at the lightest mass and the heaviest its density
// admits, thrown at a ground box at its own speed limits (the world's
// 500 m/s and 100 rad/s, lowered for a body whose momentum about its reach
// would leave the envelope: core/envelope.h, speed_limits) about three spin
// axes; the heaviest on the lightest stacked six high; the heaviest and
// largest meeting head on; the largest impulse and force at the farthest
// point, and a velocity set past the clamps. Each scene runs through `run
// --json --events --trace`, `record` with those inputs and `--trace`,
// `verify --trace` and `synctest`: exit 0 and nothing on stderr (the checked
// build, whose binary the checked tests run, aborts on any saturation, and
// its sanitizers report there), the same trace from record and verify, and
// step 0's velocities as written.
#include <catch2/catch.hpp>

#include <cmath>
#include <cstdlib>
#include <fstream>
#include <sstream>
#include <string>
#include <vector>

#include "core/aabb.h"
#include "core/envelope.h"
#include "core/mass.h"
#include "core/world.h"
#include "fixed/decimal.h"
#include "tests/test_support.h"
#include "tests/tools/cli_support.h"

using namespace bitstep;
using namespace bitstep::test_cli;
using bitstep::test::to_double;

namespace {

std::string num(Fixed v) { return to_string(v); }
std::string vec(Vec3 v) {
  std::ostringstream text;
  text << '[' << num(v.x) << ", " << num(v.y) << ", " << num(v.z) << ']';
  return text.str();
}

// One body of the sweep: its shapes as the scene writes them and as the
// world holds them, its mass, and what it is thrown with.
struct Corner {
  std::string name, shapes_json;
  std::vector<Shape> shapes;
  Fixed mass;
  Vec3 velocity, spin;
};

Shape box(Fixed h, Vec3 at = {}) { return {ShapeType::box, {h, h, h}, {}, {}, {at, {}}}; }
Shape ball(Fixed r) { return {ShapeType::sphere, {}, r, {}, {}}; }
Shape capsule(Fixed r, Fixed half_height) { return {ShapeType::capsule, {}, r, half_height, {}}; }
std::string json_of(const Shape& s) {
  const std::string at = s.local.position == Vec3{} ? "" : ", \"position\": " + vec(s.local.position);
  switch (s.type) {
    case ShapeType::box: return "{\"type\": \"box\", \"half_extents\": " + vec(s.half_extents) + at + "}";
    case ShapeType::sphere: return "{\"type\": \"sphere\", \"radius\": " + num(s.radius) + at + "}";
    case ShapeType::capsule:
      return "{\"type\": \"capsule\", \"radius\": " + num(s.radius) + ", \"half_height\": " + num(s.half_height) + at +
             "}";
    case ShapeType::plane: break;
  }
  return "";
}

// The heaviest mass the density bound admits for these shapes (at most 1e5 kg).
Fixed heaviest(const std::vector<Shape>& shapes) {
  Fixed v;
  for (const Shape& s : shapes) v += volume(s);
  if (v > 0.001_fx) return envelope::max_mass;  // 1e8 kg/m^3 x 0.001 m^3
  return min(envelope::max_mass, envelope::max_density * v * 0.999_fx);
}

// The body's own limits, as World computes them.
SpeedLimits limits_of(const std::vector<Shape>& shapes, Fixed mass) {
  BodyDef def;
  def.shapes = shapes;
  def.mass = mass;
  World world;
  const CreateResult created = world.create_body(def);
  REQUIRE(created.ok());
  return world.body(created.id).limits;
}

// Every size and mass corner of one shape list, thrown down and sideways
// at 99% of its limits, spinning about axis k.
std::vector<Corner> corners_of(const std::string& kind, const std::vector<std::vector<Shape>>& sizes) {
  const Vec3 axes[3] = {{Fixed::one(), {}, {}}, {{}, Fixed::one(), {}}, {0.6_fx, {}, 0.8_fx}};
  std::vector<Corner> out;
  for (const std::vector<Shape>& shapes : sizes) {
    for (const Fixed mass : {envelope::min_mass, heaviest(shapes)}) {
      Corner c;
      c.name = kind + "_" + std::to_string(out.size());
      for (const Shape& s : shapes) c.shapes_json += (c.shapes_json.empty() ? "" : ", ") + json_of(s);
      c.shapes = shapes;
      c.mass = mass;
      const SpeedLimits limits = limits_of(shapes, mass);
      const Fixed v = limits.linear * 0.99_fx, w = limits.angular * 0.99_fx;
      c.velocity = {v * 0.6_fx, -(v * 0.8_fx), Fixed{}};
      c.spin = axes[out.size() % 3] * w;
      out.push_back(c);
    }
  }
  return out;
}

// Each corner over a ground box of its own, 400 m apart, its lowest point
// 0.1 m above it.
std::string throw_scene(const std::vector<Corner>& corners) {
  std::ostringstream bodies;
  for (size_t i = 0; i < corners.size(); ++i) {
    const Corner& c = corners[i];
    const Fixed x = Fixed::from_int(static_cast<int32_t>(i) * 400 - 600);
    Fixed lowest;
    for (const Shape& s : c.shapes) lowest = min(lowest, shape_aabb({&s, s.local}).min.y);
    const Fixed height = 0.1_fx - lowest;
    bodies << (i == 0 ? "" : ",\n") << "{\"name\": \"ground_" << c.name << "\", \"type\": \"static\", \"position\": "
           << vec({x, -50.0_fx, Fixed{}}) << ", \"shapes\": [{\"type\": \"box\", \"half_extents\": [50, 50, 50]}]},\n"
           << "{\"name\": \"" << c.name << "\", \"position\": " << vec({x, height, Fixed{}}) << ", \"mass\": " << num(c.mass)
           << ", \"velocity\": " << vec(c.velocity) << ", \"angular_velocity\": " << vec(c.spin) << ", \"shapes\": ["
           << c.shapes_json << "]}";
  }
  return "{\"format\": \"bitstep-scene\", \"version\": 1, \"bodies\": [\n" + bodies.str() + "]}";
}

// Six boxes, the heaviest (1e5 kg, 5 m) on the lightest (10 g, `light` m).
std::string stack_scene(Fixed light) {
  std::ostringstream bodies;
  bodies << "{\"name\": \"ground\", \"type\": \"static\", \"position\": [0, -50, 0], "
            "\"shapes\": [{\"type\": \"box\", \"half_extents\": [50, 50, 50]}]}";
  Fixed y;
  for (int i = 0; i < 6; ++i) {
    const bool heavy = i % 2 == 1;
    const Fixed h = heavy ? 5.0_fx : light;
    bodies << ",\n{\"name\": \"level_" << i << "\", \"position\": " << vec({Fixed{}, y + h, Fixed{}})
           << ", \"mass\": " << num(heavy ? envelope::max_mass : envelope::min_mass) << ", \"shapes\": ["
           << json_of(box(h)) << "]}";
    y += h * 2.0_fx;
  }
  return "{\"format\": \"bitstep-scene\", \"version\": 1, \"bodies\": [\n" + bodies.str() + "]}";
}

// The heaviest largest box and sphere pairs meeting head on at their limits,
// spinning, without gravity.
std::string meeting_scene() {
  std::ostringstream bodies;
  int pair = 0;
  for (const Shape& shape : {box(50.0_fx), ball(50.0_fx)}) {
    const SpeedLimits limits = limits_of({shape}, envelope::max_mass);
    const Fixed v = limits.linear * 0.99_fx, w = limits.angular * 0.99_fx;
    const Fixed z = Fixed::from_int(pair++ * 400);
    const Fixed apart = reach({shape}) + v * 0.05_fx;
    for (const int side : {-1, 1}) {
      const Fixed s = Fixed::from_int(side);
      bodies << (pair == 1 && side < 0 ? "" : ",\n") << "{\"name\": \"meet_" << pair << (side < 0 ? "_a" : "_b")
             << "\", \"position\": " << vec({s * apart, Fixed{}, z}) << ", \"mass\": 100000, \"velocity\": "
             << vec({-(s * v), Fixed{}, Fixed{}}) << ", \"angular_velocity\": " << vec({Fixed{}, s * w, Fixed{}})
             << ", \"shapes\": [" << json_of(shape) << "]}";
    }
  }
  return "{\"format\": \"bitstep-scene\", \"version\": 1, \"settings\": {\"gravity\": [0, 0, 0]}, \"bodies\": [\n" +
         bodies.str() + "]}";
}

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
  const Vec3 far{50.0_fx, 50.0_fx, 50.0_fx};
  const std::vector<std::pair<std::string, std::vector<std::vector<Shape>>>> kinds = {
      {"box", {{box(envelope::min_size)}, {box(envelope::max_size)}}},
      {"sphere", {{ball(envelope::min_size)}, {ball(envelope::max_size)}}},
      {"capsule",
       {{capsule(envelope::min_size, Fixed{})},
        {capsule(envelope::min_size, envelope::max_size)},
        {capsule(envelope::max_size, envelope::max_size)}}},
      {"compound", {{box(envelope::min_size, far), box(envelope::min_size, -far)}, {box(envelope::max_size, far), box(envelope::max_size, -far)}}},
  };
  for (const auto& [kind, sizes] : kinds) {
    const std::vector<Corner> corners = corners_of(kind, sizes);
    sweep(kind, throw_scene(corners), {corners.front().name, corners.back().name}, corners);
  }
  sweep("stack_smallest", stack_scene(envelope::min_size), {"level_0", "level_5"});
  sweep("stack_half_metre", stack_scene(0.5_fx), {"level_2"});
  sweep("meeting", meeting_scene(), {"meet_1_a", "meet_2_b"});
}
