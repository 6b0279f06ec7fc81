// Scenes at the world envelope's corners, as a user writes them (scene
// JSON), for the tests that run them through every command and every C API
// call: every shape kind (and a compound) at the smallest and largest size,
// at the lightest mass and the heaviest its density admits, thrown at a
// ground box at 99% of its own speed limits (core/envelope.h,
// speed_limits) about three spin axes; the heaviest on the lightest
// stacked six high; the heaviest and largest meeting head on.
#pragma once

#include <catch2/catch.hpp>

#include <sstream>
#include <string>
#include <utility>
#include <vector>

#include "core/aabb.h"
#include "core/envelope.h"
#include "core/mass.h"
#include "core/world.h"
#include "fixed/decimal.h"

namespace bitstep::test_envelope {

inline std::string num(Fixed v) { return to_string(v); }
inline std::string vec(Vec3 v) {
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

inline Shape box(Fixed h, Vec3 at = {}) { return {ShapeType::box, {h, h, h}, {}, {}, {at, {}}}; }
inline Shape ball(Fixed r) { return {ShapeType::sphere, {}, r, {}, {}}; }
inline Shape capsule(Fixed r, Fixed half_height) { return {ShapeType::capsule, {}, r, half_height, {}}; }
inline std::string json_of(const Shape& s) {
  const std::string at = s.local.position == Vec3{} ? "" : ", \"position\": " + vec(s.local.position);
  switch (s.type) {
    case ShapeType::box: return "{\"type\": \"box\", \"half_extents\": " + vec(s.half_extents) + at + "}";
    case ShapeType::sphere: return "{\"type\": \"sphere\", \"radius\": " + num(s.radius) + at + "}";
    case ShapeType::capsule:
      return "{\"type\": \"capsule\", \"radius\": " + num(s.radius) + ", \"half_height\": " + num(s.half_height) + at +
             "}";
    case ShapeType::plane:
    case ShapeType::hull:
    case ShapeType::mesh:
    case ShapeType::heightfield: break;  // the corners are the primitives'
  }
  return "";
}

// The heaviest mass the density bound admits for these shapes (at most 1e5 kg).
inline Fixed heaviest(const std::vector<Shape>& shapes) {
  Fixed v;
  for (const Shape& s : shapes) v += volume(s);
  if (v > 0.001_fx) return envelope::max_mass;  // 1e8 kg/m^3 x 0.001 m^3
  return min(envelope::max_mass, envelope::max_density * v * 0.999_fx);
}

// The body's own limits, as World computes them.
inline SpeedLimits limits_of(const std::vector<Shape>& shapes, Fixed mass) {
  BodyDef def;
  def.shapes = shapes;
  def.mass = mass;
  World world;
  const Result<BodyId> created = world.create_body(def);
  REQUIRE(created.ok());
  return world.body(created.value()).limits;
}

// Every size and mass corner of one shape list, thrown down and sideways
// at 99% of its limits, spinning about axis k.
inline std::vector<Corner> corners_of(const std::string& kind, const std::vector<std::vector<Shape>>& sizes) {
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
inline std::string throw_scene(const std::vector<Corner>& corners) {
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
inline std::string stack_scene(Fixed light) {
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
inline std::string meeting_scene() {
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

// Every kind's corners: (kind, its shape lists from smallest to largest).
inline std::vector<std::pair<std::string, std::vector<std::vector<Shape>>>> corner_kinds() {
  const Vec3 far{50.0_fx, 50.0_fx, 50.0_fx};
  return {
      {"box", {{box(envelope::min_size)}, {box(envelope::max_size)}}},
      {"sphere", {{ball(envelope::min_size)}, {ball(envelope::max_size)}}},
      {"capsule",
       {{capsule(envelope::min_size, Fixed{})},
        {capsule(envelope::min_size, envelope::max_size)},
        {capsule(envelope::max_size, envelope::max_size)}}},
      {"compound",
       {{box(envelope::min_size, far), box(envelope::min_size, -far)},
        {box(envelope::max_size, far), box(envelope::max_size, -far)}}},
  };
}

}  // namespace bitstep::test_envelope
