// The world's state, described once: every field that influences the
// future, in its canonical order, with its name. Three visitors walk this
// one description: state_hash.cpp writes it as little-endian bytes (the
// state hash, and the snapshot's payload), snapshot.cpp reads those bytes
// back, and state_dump.cpp writes it as exact JSON for `verify --dump-at`
// and `diff`. A field added here is hashed, saved, restored and dumped at
// once: none can be hashed and not dumped, and `diff` can name every
// desync the hash sees (tests/replay/state_description_tests.cpp flips
// every byte of an image to show it).
//
// The bytes: integers unsigned little-endian of the width given, a Fixed as
// its raw int64, a vector x y z, a quaternion w x y z, a matrix row by row,
// a list as its count (u32) then its items; no padding. What a visitor may
// be asked (V is the visitor; `name` is the JSON key, null for a list's bare
// items):
//   V::reading                               true for the reader, which fills the state
//   integer(name, value, bytes, lo, hi)      an integer (or a count) in lo..hi
//   choice(name, value, names, first)        an enum as one byte, first..names.size()-1
//   flags(name, bits, names)                 a byte of named bits
//   fixed / vec / quat / mat(name, value)
//   fixeds(name, values, n)                  n Fixed as one array
//   integers(name, a, b, bytes, hi)          two integers in 0..hi as one array
//   object(name, describe)                   a group of fields (a JSON object; no bytes of its own)
//   list(name, items, item_bytes, hi, index_key, describe(item))
//                                            a counted vector; the reader refuses a count
//                                            above hi or above what the bytes left could hold
//   items(name, count, describe(i))          `count` items whose count was given before
//   require(test, reason)                    the reader refuses a state where test() is false
//   marks(n)                                 (reader) n zeroed bytes of scratch the reader keeps
//   trailing(present, in_dump, describe)     a block at the end that the writer writes when
//                                            `present` and the reader reads when bytes are left;
//                                            the dump shows it when present or `in_dump`
//   statics(describe)                        fields a body keeps while it lives (type, mass
//                                            properties, material, damping, shapes, filter):
//                                            a step's state alone (rollback_state.h) leaves them out
//   identity(body)                           where a live body's serial goes in a step's state
//                                            (not state: the other visitors do nothing)
#pragma once

#include <array>
#include <cstdint>
#include <string>
#include <type_traits>
#include <vector>

#include "core/body.h"
#include "core/car.h"
#include "core/character.h"
#include "core/contact.h"
#include "core/convex_hull.h"
#include "core/envelope.h"
#include "core/height_grid.h"
#include "core/joint.h"
#include "core/settings.h"
#include "core/triangle_mesh.h"
#include "core/world.h"
#include "replay/limits.h"

namespace bitstep {

// What the reader checks of a body's motion and shapes (a restored world
// steps: a state no world holds is refused, not stepped). Raw comparisons
// only, so that no value, however corrupt, reaches arithmetic that
// saturates.
namespace state_checks {

inline bool within(Fixed f, Fixed limit) { return f >= -limit && f <= limit; }
inline bool within(Vec3 v, Fixed limit) { return within(v.x, limit) && within(v.y, limit) && within(v.z, limit); }

// A rotation as a world keeps them: each component within +-2 and the norm
// squared within 2^-10 of 1 (worlds normalise; a restored quaternion of norm
// 10^9 scaled every shape it turned and overflowed the broadphase).
inline bool unit_quaternion(Quat q) {
  const Fixed two = Fixed::from_raw(int64_t{1} << 33);
  if (!within(q.w, two) || !within(q.x, two) || !within(q.y, two) || !within(q.z, two)) return false;
  const Fixed norm2 = q.w * q.w + q.x * q.x + q.y * q.y + q.z * q.z;
  return within(norm2 - Fixed::one(), Fixed::from_raw(int64_t{1} << 22));
}

// Positions within 2^20 m: 65 times the envelope's 16 km, so that a body
// that left the envelope still restores, and far from where sums of
// positions and sizes leave the range.
inline constexpr Fixed max_position = Fixed::from_raw(int64_t{1} << 52);

// Velocities, each component: twice the envelope's clamps (a world clamps
// the length, to within a rounding of them).
inline constexpr Fixed max_linear_speed = envelope::max_linear_speed + envelope::max_linear_speed;
inline constexpr Fixed max_angular_speed = envelope::max_angular_speed + envelope::max_angular_speed;

// A shape of the envelope (check_shape), with a unit local orientation.
inline bool shape_inside(const Shape& shape) {
  return within(shape.local.position, max_position) && unit_quaternion(shape.local.orientation) &&
         check_shape(shape, 0).ok();
}

}  // namespace state_checks

// The parts of a world's state: references to a world's own (const) for
// writing, to the pieces a world will be made from for reading.
template <bool Reading>
struct StateParts {
  template <class T>
  using Ref = std::conditional_t<Reading, T&, const T&>;
  Ref<uint64_t> step_count;
  Ref<Settings> settings;
  Ref<std::vector<Body>> bodies;
  Ref<std::vector<uint32_t>> free_slots;
  Ref<std::vector<Contact>> contacts;
  Ref<std::vector<Joint>> joints;
  Ref<std::vector<uint32_t>> free_joint_slots;
  Ref<std::vector<SensorOverlap>> sensor_overlaps;
  Ref<std::vector<Car>> cars;
  Ref<std::vector<Character>> characters;
};

// A world's parts, to write (`step`: its step count, held by the caller).
inline StateParts<false> state_parts_of(const World& world, const uint64_t& step) {
  return {step,           world.settings(),         world.bodies(),          world.free_slots(), world.contacts(),
          world.joints(), world.free_joint_slots(), world.sensor_overlaps(), world.cars(),       world.characters()};
}

// A world's state parts of its own, to read a state into before it
// becomes (snapshot.cpp) or replaces (rollback_state.cpp) a world's.
struct OwnedStateParts {
  uint64_t step_count = 0;
  Settings settings;
  std::vector<Body> bodies;
  std::vector<uint32_t> free_slots;
  std::vector<Contact> contacts;
  std::vector<Joint> joints;
  std::vector<uint32_t> free_joint_slots;
  std::vector<SensorOverlap> sensor_overlaps;
  std::vector<Car> cars;
  std::vector<Character> characters;
  StateParts<true> refs() {
    return {step_count, settings,         bodies,          free_slots, contacts,
            joints,     free_joint_slots, sensor_overlaps, cars,       characters};
  }
};

namespace state_description {

inline constexpr uint64_t max_iterations = 1000;  // as the scene format
inline constexpr std::array<const char*, 8> setting_flags = {"baumgarte",  "warm_starting", "shock_propagation",
                                                              "sleep",      "guendelman",    "substeps",
                                                              "held_passes", "soft_step"};
inline constexpr int default_held_passes = Settings{}.held_velocity_iterations;
inline constexpr std::array<const char*, 3> sleep_methods = {"off", "motion", "still"};
inline constexpr std::array<const char*, 3> body_types = {"static", "kinematic", "dynamic"};
inline constexpr auto shape_types = shape_type_names;  // core/shape.h
inline constexpr std::array<const char*, 5> joint_types = {"point", "max_distance", "hinge", "cone", "slider"};
inline constexpr std::array<const char*, 2> joint_flags = {"limited", "motor"};

template <class V, class S>
void describe_settings(V& v, S& s) {
  v.fixed("dt", s.dt);
  v.vec("gravity", s.gravity);
  v.integer("velocity_iterations", s.velocity_iterations, 4, 1, max_iterations);
  v.integer("position_iterations", s.position_iterations, 4, 0, max_iterations);
  v.fixed("penetration_slop", s.penetration_slop);
  v.fixed("split_impulse_factor", s.split_impulse_factor);
  v.fixed("max_push_out_speed", s.max_push_out_speed);
  v.fixed("baumgarte_factor", s.baumgarte_factor);
  v.fixed("restitution_threshold", s.restitution_threshold);
  v.fixed("speculative_distance", s.speculative_distance);
  v.fixed("max_linear_speed", s.max_linear_speed);
  v.fixed("max_angular_speed", s.max_angular_speed);
  // Seven switches in one byte. Sleep's block follows only when it is on
  // (bit 8), so a world without sleep has the bytes it had before sleep
  // existed; bit 16: the guendelman pipeline; bit 32: more than one
  // substep, whose count follows shock_iterations (a world of one substep
  // has the bytes it had before substeps existed); bit 64: held islands'
  // velocity passes other than the default, their count after that; bit
  // 128: the soft step, its substeps and contact spring after those.
  uint8_t bits = 0;
  if constexpr (!V::reading) {
    bits = static_cast<uint8_t>((s.baumgarte ? 1 : 0) | (s.warm_starting ? 2 : 0) | (s.shock_propagation ? 4 : 0) |
                                (s.sleep_method != SleepMethod::off ? 8 : 0) |
                                (s.pipeline == Pipeline::guendelman ? 16 : 0) | (s.substeps != 1 ? 32 : 0) |
                                (s.held_velocity_iterations != default_held_passes ? 64 : 0) |
                                (s.soft_substeps != 0 ? 128 : 0));
  }
  v.flags("flags", bits, setting_flags);
  if constexpr (V::reading) {
    s.baumgarte = (bits & 1) != 0;
    s.warm_starting = (bits & 2) != 0;
    s.shock_propagation = (bits & 4) != 0;
    s.pipeline = (bits & 16) != 0 ? Pipeline::guendelman : Pipeline::standard;
  }
  v.integer("shock_iterations", s.shock_iterations, 4, 1, max_iterations);
  if ((bits & 32) != 0) {
    v.integer("substeps", s.substeps, 1, 2, static_cast<uint64_t>(envelope::max_substeps));
  } else if constexpr (V::reading) {
    s.substeps = 1;
  }
  if ((bits & 64) != 0) {
    v.integer("held_velocity_iterations", s.held_velocity_iterations, 4, 1, max_iterations);
  } else if constexpr (V::reading) {
    s.held_velocity_iterations = default_held_passes;
  }
  if ((bits & 128) != 0) {
    v.integer("soft_substeps", s.soft_substeps, 1, 1, static_cast<uint64_t>(envelope::max_substeps));
    v.fixed("contact_hertz", s.contact_hertz);
    v.fixed("contact_damping_ratio", s.contact_damping_ratio);
  } else if constexpr (V::reading) {
    s.soft_substeps = 0;
    s.contact_hertz = Settings{}.contact_hertz;
    s.contact_damping_ratio = Settings{}.contact_damping_ratio;
  }
  v.require([&] { return check_settings(s).ok(); },
            [&] {
              const Error refused = check_settings(s).error();
              return refused.place + " " + refused.reason;  // "dt outside the world envelope"
            });
  if ((bits & 8) != 0) {
    v.choice("sleep_method", s.sleep_method, sleep_methods, 1);
    v.fixed("sleep_epsilon", s.sleep_epsilon);
    v.fixed("sleep_bias", s.sleep_bias);
    v.fixed("sleep_min_time", s.sleep_min_time);
    v.fixed("sleep_time", s.sleep_time);
    v.fixed("sleep_linear_tolerance", s.sleep_linear_tolerance);
    v.fixed("sleep_angular_tolerance", s.sleep_angular_tolerance);
  }
  v.require([&] { return s.dt > Fixed{}; }, [] { return std::string("dt not positive"); });
}

// A hull's corners (its faces and mass are built from them again: the
// builder gives the same hull for them, core/convex_hull.h).
template <class V, class Sh>
void describe_hull_points(V& v, Sh& shape) {
  constexpr size_t point_bytes = 8 * 3;
  const auto describe_point = [&](auto& point) { v.vec(nullptr, point); };
  if constexpr (V::reading) {
    std::vector<Vec3> points;
    v.list("points", points, point_bytes, max_hull_vertices, nullptr, describe_point);
    Result<std::shared_ptr<const ConvexHull>> hull = build_convex_hull(points);
    const bool same = hull.ok() && hull.value()->vertices == points;
    v.require([&] { return same; }, [] { return std::string("hull points that are not the corners of a hull"); });
    if (same) shape.hull = std::move(hull.value());
  } else {
    v.list("points", shape.hull->vertices, point_bytes, max_hull_vertices, nullptr, describe_point);
  }
}

// A mesh's vertices and triangles (its planes, edges and tree are built
// from them again, core/triangle_mesh.h). A step's state alone leaves a
// body's shapes out (rollback_state.h): static geometry is not copied per
// step; the hash and a snapshot hold all of it.
template <class V, class Sh>
void describe_mesh_arrays(V& v, Sh& shape) {
  constexpr size_t vertex_bytes = 8 * 3, index_bytes = 4;
  const auto describe_vertex = [&](auto& vertex) { v.vec(nullptr, vertex); };
  const auto describe_index = [&](auto& index) { v.integer(nullptr, index, 4, 0, max_mesh_vertices - 1); };
  if constexpr (V::reading) {
    std::vector<Vec3> vertices;
    std::vector<uint32_t> indices;
    v.list("vertices", vertices, vertex_bytes, max_mesh_vertices, nullptr, describe_vertex);
    v.list("indices", indices, index_bytes, uint64_t{3} * max_mesh_triangles, nullptr, describe_index);
    Result<std::shared_ptr<const TriangleMesh>> mesh = build_triangle_mesh(vertices, indices);
    v.require([&] { return mesh.ok(); }, [] { return std::string("mesh arrays that do not build a mesh"); });
    if (mesh.ok()) shape.mesh = std::move(mesh.value());
  } else {
    std::vector<uint32_t> indices;
    indices.reserve(shape.mesh->triangles.size() * 3);
    for (const TriangleMesh::Triangle& t : shape.mesh->triangles)
      indices.insert(indices.end(), t.corners.begin(), t.corners.end());
    v.list("vertices", shape.mesh->vertices, vertex_bytes, max_mesh_vertices, nullptr, describe_vertex);
    v.list("indices", indices, index_bytes, uint64_t{3} * max_mesh_triangles, nullptr, describe_index);
  }
}

// A heightfield's grid (its mesh is built from it again,
// core/height_grid.h): the sizes, the heights and the holes. G is
// HeightGrid, or const HeightGrid for a writer.
template <class V, class G>
void describe_grid_fields(V& v, G& grid) {
  constexpr size_t height_bytes = 8, hole_bytes = 4;
  v.integer("columns", grid.columns, 2, 2, max_grid_samples);
  v.integer("rows", grid.rows, 2, 2, max_grid_samples);
  v.fixed("spacing_x", grid.spacing_x);
  v.fixed("spacing_z", grid.spacing_z);
  v.list("heights", grid.heights, height_bytes, uint64_t{max_grid_samples} * max_grid_samples, nullptr,
         [&](auto& height) { v.fixed(nullptr, height); });
  v.list("holes", grid.holes, hole_bytes, max_grid_cells, nullptr,
         [&](auto& hole) { v.integer(nullptr, hole, 4, 0, max_grid_cells - 1); });
}

template <class V, class Sh>
void describe_height_grid(V& v, Sh& shape) {
  if constexpr (V::reading) {
    HeightGrid grid;
    describe_grid_fields(v, grid);
    Result<std::shared_ptr<const TriangleMesh>> mesh = build_height_grid_mesh(std::move(grid));
    v.require([&] { return mesh.ok(); }, [] { return std::string("a grid that does not build a heightfield"); });
    if (mesh.ok()) shape.mesh = std::move(mesh.value());
  } else {
    describe_grid_fields(v, *shape.mesh->source_grid);
  }
}

template <class V, class Sh>
void describe_shape(V& v, Sh& shape) {
  v.choice("type", shape.type, shape_types, 0);
  v.vec("half_extents", shape.half_extents);
  v.fixed("radius", shape.radius);
  v.fixed("half_height", shape.half_height);
  v.vec("position", shape.local.position);
  v.quat("orientation", shape.local.orientation);
  if (shape.type == ShapeType::hull) describe_hull_points(v, shape);
  if (shape.type == ShapeType::mesh) describe_mesh_arrays(v, shape);
  if (shape.type == ShapeType::heightfield) describe_height_grid(v, shape);
  v.require([&] { return state_checks::shape_inside(shape); },
            [] { return std::string("a shape outside the envelope (size, position or orientation)"); });
}

template <class V, class B>
void describe_body(V& v, B& body, bool sleep) {
  v.integer("alive", body.alive, 1, 0, 1);
  v.integer("generation", body.generation, 4, 0, UINT32_MAX);
  if (!body.alive) return;
  v.identity(body);
  v.statics([&] { v.choice("type", body.type, body_types, 0); });
  v.vec("position", body.pose.position);
  v.quat("orientation", body.pose.orientation);
  v.vec("linear_velocity", body.linear_velocity);
  v.vec("angular_velocity", body.angular_velocity);
  v.vec("force", body.force);
  v.vec("torque", body.torque);
  v.require(
      [&] {
        return state_checks::within(body.pose.position, state_checks::max_position) &&
               state_checks::unit_quaternion(body.pose.orientation) &&
               state_checks::within(body.linear_velocity, state_checks::max_linear_speed) &&
               state_checks::within(body.angular_velocity, state_checks::max_angular_speed);
      },
      [] { return std::string("a body's position, orientation or velocity no world holds"); });
  // What the body is made of (a spawned body is part of the state too).
  v.statics([&] {
    v.fixed("inverse_mass", body.inverse_mass);
    v.mat("inertia_local", body.inertia_local);
    v.mat("inverse_inertia_local", body.inverse_inertia_local);
  });
  // Refreshed at the start of a step, from the pose before it moved: an
  // impulse applied between steps uses this one.
  v.mat("inverse_inertia_world", body.inverse_inertia_world);
  v.statics([&] {
    v.object("material", [&] {
      v.fixed("static_friction", body.material.static_friction);
      v.fixed("dynamic_friction", body.material.dynamic_friction);
      v.fixed("restitution", body.material.restitution);
      v.fixed("rolling_resistance", body.material.rolling_resistance);
    });
    v.fixed("linear_damping", body.linear_damping);
    v.fixed("angular_damping", body.angular_damping);
  });
  if (sleep) {
    v.integer("asleep", body.asleep, 1, 0, 1);
    v.require([&] { return !body.asleep || body.type == BodyType::dynamic; },
              [] { return std::string("only a dynamic body sleeps"); });
    v.fixed("sleep_motion", body.sleep_motion);
    v.integer("sleepy_steps", body.sleepy_steps, 4, 0, UINT32_MAX);
    v.object("sleep_reference", [&] {
      v.vec("position", body.sleep_reference.position);
      v.quat("orientation", body.sleep_reference.orientation);
      v.require(
          [&] {
            return state_checks::within(body.sleep_reference.position, state_checks::max_position) &&
                   state_checks::unit_quaternion(body.sleep_reference.orientation);
          },
          [] { return std::string("a sleep reference no world holds"); });
    });
  }
  v.statics([&] {
    constexpr size_t shape_bytes = 1 + 8 * 12;
    v.list("shapes", body.shapes, shape_bytes, UINT16_MAX, nullptr, [&](auto& shape) { describe_shape(v, shape); });
    v.require([&] { return !body.shapes.empty(); }, [] { return std::string("a body needs 1..65535 shapes"); });
  });
}

template <class V, class C, class Bodies, class Before>
void describe_contact(V& v, C& c, const Bodies& bodies, Before* before) {
  v.integers("bodies", c.key.body_a, c.key.body_b, 4, UINT32_MAX);
  v.integers("shapes", c.key.shape_a, c.key.shape_b, 4, UINT16_MAX);
  v.require(
      [&] {
        const ContactKey& k = c.key;
        return k.body_a < k.body_b && k.body_b < bodies.size() && bodies[k.body_a].alive && bodies[k.body_b].alive &&
               k.shape_a < bodies[k.body_a].shapes.size() && k.shape_b < bodies[k.body_b].shapes.size();
      },
      [] { return std::string("a contact refers to a body or shape that does not exist"); });
  v.require([&] { return before == nullptr || before->key < c.key; },
            [] { return std::string("contacts out of order"); });
  v.integer("point_count", c.manifold.point_count, 1, 0, max_manifold_points);
  v.vec("normal", c.manifold.normal);
  v.fixeds("friction_impulse", c.manifold.friction_impulse, 2);
  v.fixed("twist_impulse", c.manifold.twist_impulse);
  v.fixeds("rolling_impulse", c.manifold.rolling_impulse, 2);
  v.items("points", static_cast<size_t>(c.manifold.point_count), [&](size_t i) {
    auto& p = c.manifold.points[i];
    v.integer("feature", p.feature, 4, 0, UINT32_MAX);
    v.vec("position", p.position);  // warm starting matches old points by position too
    v.fixed("depth", p.depth);
    v.fixed("normal_impulse", p.normal_impulse);
  });
}

template <class V, class C, class Bodies>
void describe_car(V& v, C& car, const Bodies& bodies) {
  v.integer("alive", car.alive, 1, 0, 1);
  if (!car.alive) return;
  auto& def = car.def;
  v.integer("chassis", def.chassis.index, 4, 0, UINT32_MAX);
  v.integer("chassis_generation", def.chassis.generation, 4, 0, UINT32_MAX);
  v.require([&] { return def.chassis.index < bodies.size() && bodies[def.chassis.index].alive &&
                         bodies[def.chassis.index].generation == def.chassis.generation; },
            [] { return std::string("a car's chassis is not a live body"); });
  v.fixed("wheel_radius", def.wheel_radius);
  v.fixed("rest_length", def.rest_length);
  v.fixed("stiffness", def.stiffness);
  v.fixed("damping", def.damping);
  v.fixed("grip", def.grip);
  v.fixed("drive_force", def.drive_force);
  v.fixed("brake_force", def.brake_force);
  v.fixed("max_steer", def.max_steer);
  v.integer("rays_per_wheel", def.rays_per_wheel, 1, 1, 8);
  v.list("wheels", def.wheels, 3 * 8 + 2, 8, nullptr, [&](auto& wheel) {
    v.vec("attachment", wheel.attachment);
    v.integer("driven", wheel.driven, 1, 0, 1);
    v.integer("steered", wheel.steered, 1, 0, 1);
  });
  v.require([&] { return check_car(def, bodies).ok(); },
            [&] { return "a car: " + check_car(def, bodies).error().message(); });
  v.object("controls", [&] {
    v.fixed("throttle", car.controls.throttle);
    v.fixed("brake", car.controls.brake);
    v.fixed("steer", car.controls.steer);
  });
  v.list("tyre_impulses", car.tyre_impulses, 3 * 8, 8, nullptr, [&](auto& tyre) {
    v.fixed("suspension", tyre.suspension);
    v.fixed("forward", tyre.forward);
    v.fixed("side", tyre.side);
  });
  v.require([&] { return car.tyre_impulses.size() == def.wheels.size(); },
            [] { return std::string("a car's tyre impulses do not match its wheels"); });
}

// A character (core/character.h): its definition, where it is and how it
// moves, what it was asked, and what it stands on (a body since removed
// stays named: riding checks its generation).
template <class V, class C>
void describe_character(V& v, C& c) {
  v.integer("alive", c.alive, 1, 0, 1);
  if (!c.alive) return;
  auto& def = c.def;
  v.vec("start", def.position);
  v.fixed("radius", def.radius);
  v.fixed("half_height", def.half_height);
  v.fixed("max_slope_cos", def.max_slope_cos);
  v.fixed("step_height", def.step_height);
  v.fixed("jump_speed", def.jump_speed);
  v.fixed("air_acceleration", def.air_acceleration);
  v.fixed("mass", def.mass);
  v.fixed("max_push_force", def.max_push_force);
  v.integer("collides_with", def.collides_with, 4, 0, UINT32_MAX);
  v.vec("start_facing", def.facing);
  v.require([&] { return check_character(def).ok(); },
            [&] { return "a character: " + check_character(def).error().message(); });
  v.vec("position", c.position);
  v.vec("velocity", c.velocity);
  v.vec("facing", c.facing);
  v.require(
      [&] {
        return state_checks::within(c.position, state_checks::max_position) &&
               state_checks::within(c.velocity, state_checks::max_position);
      },
      [] { return std::string("a character outside the world"); });
  v.object("controls", [&] {
    v.vec("velocity", c.controls.velocity);
    v.integer("jump", c.controls.jump, 1, 0, 1);
  });
  v.choice("ground", c.ground, ground_state_names, 0);
  v.integer("ground_body", c.ground_body.index, 4, 0, UINT32_MAX);
  v.integer("ground_generation", c.ground_body.generation, 4, 0, UINT32_MAX);
  v.vec("ground_normal", c.ground_normal);
  v.vec("ground_position", c.ground_pose.position);
  v.quat("ground_orientation", c.ground_pose.orientation);
}

// The fields of a joint's own type beyond those every joint has, one case
// per type (no default: a type without its case is a -Wswitch error).
template <class V, class J>
void describe_joint_type(V& v, J& joint) {
  switch (joint.type) {
    case JointType::point:
    case JointType::max_distance:
    case JointType::hinge:
    case JointType::cone:
      if constexpr (V::reading) {  // read in place (a rollback state): none of a slider's values
        joint.lower_translation = joint.upper_translation = Fixed{};
        joint.angular_impulse = Vec3{};
      }
      return;
    case JointType::slider:
      v.fixed("lower_translation", joint.lower_translation);
      v.fixed("upper_translation", joint.upper_translation);
      v.vec("angular_impulse", joint.angular_impulse);
      return;
  }
}

template <class V, class J, class Bodies>
void describe_joint(V& v, J& joint, const Bodies& bodies) {
  v.integer("alive", joint.alive, 1, 0, 1);
  v.integer("generation", joint.generation, 4, 0, UINT32_MAX);
  if (!joint.alive) return;
  v.choice("type", joint.type, joint_types, 0);
  v.integers("bodies", joint.body_a, joint.body_b, 4, UINT32_MAX);
  v.require(
      [&] {
        return joint.body_a != joint.body_b && joint.body_a < bodies.size() && joint.body_b < bodies.size() &&
               bodies[joint.body_a].alive && bodies[joint.body_b].alive;
      },
      [] { return std::string("a joint refers to a body that does not exist"); });
  v.vec("local_anchor_a", joint.local_anchor_a);
  v.vec("local_anchor_b", joint.local_anchor_b);
  v.vec("local_axis_a", joint.local_axis_a);
  v.vec("local_axis_b", joint.local_axis_b);
  v.vec("local_reference_a", joint.local_reference_a);
  v.vec("local_reference_b", joint.local_reference_b);
  v.fixed("length", joint.length);
  // Two switches in one byte: limited (bit 1, the byte these joints had
  // before motors), a motor (bit 2), whose block follows only when it is
  // on, so a joint without one keeps its bytes.
  uint8_t bits = 0;
  if constexpr (!V::reading) bits = static_cast<uint8_t>((joint.limited ? 1 : 0) | (joint.motor_max > Fixed{} ? 2 : 0));
  v.flags("flags", bits, joint_flags);
  if constexpr (V::reading) joint.limited = (bits & 1) != 0;
  v.fixed("lower_angle", joint.lower_angle);
  v.fixed("upper_angle", joint.upper_angle);
  v.fixed("swing_angle", joint.swing_angle);
  v.fixed("break_impulse", joint.break_impulse);
  v.fixed("friction_torque", joint.friction_torque);
  v.integer("velocity_iterations", joint.velocity_iterations, 2, 0, max_joint_iterations);
  v.integer("position_iterations", joint.position_iterations, 2, 0, max_joint_iterations);
  // The impulses accumulated last step, which warm-start the next.
  v.vec("point_impulse", joint.point_impulse);
  v.fixed("distance_impulse", joint.distance_impulse);
  v.fixeds("hinge_impulse", joint.hinge_impulse, 2);
  v.fixed("limit_impulse", joint.limit_impulse);
  describe_joint_type(v, joint);
  if constexpr (V::reading) {
    // A rollback state is read into the joint in place: a joint without a
    // motor has none of one's values (last step's may be there).
    if ((bits & 2) == 0) joint.motor_speed = joint.motor_max = joint.motor_impulse = Fixed{};
  }
  if ((bits & 2) != 0) {
    v.fixed("motor_speed", joint.motor_speed);
    v.fixed("motor_max", joint.motor_max);
    v.fixed("motor_impulse", joint.motor_impulse);
    v.require(
        [&] {
          return joint.motor_max > Fixed{} && check_joint_motor(joint.type, joint.motor_speed, joint.motor_max).ok();
        },
        [] { return std::string("a joint's motor outside its type's range"); });
  }
  // Every field within what World::create_joint makes (its own checks,
  // core/joint.h): a forged frame or impulse would saturate the step.
  if constexpr (V::reading) {
    Result<void> checked;
    v.require([&] { return (checked = check_joint_state(joint, bodies[joint.body_a], bodies[joint.body_b])).ok(); },
              [&] { return "a joint's " + checked.error().message(); });
  }
}

// A list of the dead slots of `items`, each once (free_slots, free_joint_slots).
template <class V, class Slots, class Items>
void describe_free_slots(V& v, const char* name, Slots& slots, const Items& items) {
  // The reader marks each listed slot in a scratch of its own (kept: a
  // rollback state restores without allocating).
  std::vector<uint8_t> none;
  std::vector<uint8_t>& listed = [&]() -> std::vector<uint8_t>& {
    if constexpr (V::reading) {
      return v.marks(items.size());
    } else {
      return none;
    }
  }();
  v.list(name, slots, 4, UINT32_MAX, nullptr, [&](auto& slot) {
    v.integer(nullptr, slot, 4, 0, UINT32_MAX);
    if constexpr (V::reading) {
      v.require([&] { return slot < items.size() && !items[slot].alive && listed[slot]++ == 0; },
                [&] { return std::string(name) + " do not match the dead slots"; });
    }
  });
  if constexpr (V::reading) {
    for (size_t i = 0; i < items.size(); ++i) {
      v.require([&] { return items[i].alive || listed[i] != 0; },
                [&] { return std::string(name) + " do not match the dead slots"; });
    }
  }
}

}  // namespace state_description

// Everything that influences the future: the step counter, the settings,
// every body slot (alive, generation, type, pose, velocities, pending
// forces, mass properties, material, damping, sleep, shapes), the free-slot
// list, every contact (key, normal, points with feature ids, positions,
// depths and accumulated impulses, which warm-start the next step), and
// every joint slot (bodies, frames, limits, accumulated impulses) with the
// free joint slots, every body's collision filter and sensor flag, what
// overlaps the sensors, and the cars.
template <class V, bool Reading>
void describe_state(V& v, const StateParts<Reading>& state) {
  using namespace state_description;
  v.integer("step", state.step_count, 8, 0, UINT64_MAX);
  v.object("settings", [&] { describe_settings(v, state.settings); });
  const bool sleep = state.settings.sleep_method != SleepMethod::off;
  constexpr size_t body_bytes = 5;  // a dead slot: alive, generation
  v.list("bodies", state.bodies, body_bytes, limits::max_world_bodies, "slot", [&](auto& body) { describe_body(v, body, sleep); });
  // Free slots: exactly the dead slots, each once.
  describe_free_slots(v, "free_slots", state.free_slots, state.bodies);
  // Contacts: between live bodies and existing shapes, strictly in key order.
  constexpr size_t contact_bytes = 4 * 4 + 1;
  v.list("contacts", state.contacts, contact_bytes, limits::max_world_contacts, nullptr, [&](auto& contact) {
    const size_t i = static_cast<size_t>(&contact - state.contacts.data());
    describe_contact(v, contact, state.bodies, i == 0 ? nullptr : &contact - 1);
  });
  // Joints, then collision filters and sensors, last and only in a world
  // that has them (a live body off the default layers or a sensor): a world
  // without has the bytes (and the hash) it had before they existed. The
  // filters are written after the joints' block, empty or not.
  const bool moved = !state.cars.empty() || !state.characters.empty();
  bool filtered = !state.sensor_overlaps.empty() || moved;
  for (const Body& body : state.bodies) {
    filtered = filtered || (body.alive && (body.filter != CollisionFilter{} || body.sensor));
  }
  // (The reader notes which blocks it read: a block the writer would not
  // have written, e.g. an empty joints block, is refused at the end, so that
  // every state has one image.)
  bool joints_read = false, filters_read = false, cars_read = false, characters_read = false;
  constexpr size_t joint_bytes = 5;  // a dead slot: alive, generation
  v.trailing(!state.joints.empty() || !state.free_joint_slots.empty() || filtered, true, [&] {
    joints_read = true;
    v.list("joints", state.joints, joint_bytes, limits::max_world_joints, "slot",
           [&](auto& joint) { describe_joint(v, joint, state.bodies); });
    describe_free_slots(v, "free_joint_slots", state.free_joint_slots, state.joints);
  });
  v.trailing(filtered, false, [&] {
    filters_read = true;
    v.items("filters", state.bodies.size(), [&](size_t i) {
      auto& body = state.bodies[i];
      const auto describe_filter = [&] {
        v.integer("layers", body.filter.layers, 4, 0, UINT32_MAX);
        v.integer("collides_with", body.filter.collides_with, 4, 0, UINT32_MAX);
        v.integer("sensor", body.sensor, 1, 0, 1);
      };
      // A live body's are static fields (its serial brings them back); a
      // dead slot keeps its last body's (remove_body leaves them, and the
      // hash covers them), which no serial names: a step's state carries
      // them, else a slot freed before a save and filled after it kept the
      // new body's sensor flag when the save was restored.
      if (body.alive) {
        v.statics(describe_filter);
      } else {
        describe_filter();
      }
    });
    // What overlaps the sensors: between a live sensor's and a live
    // non-sensor's existing shapes, strictly in key order.
    constexpr size_t overlap_bytes = 4 * 4;
    v.list("sensor_overlaps", state.sensor_overlaps, overlap_bytes, UINT32_MAX, nullptr, [&](auto& overlap) {
      const ContactKey& k = overlap.key;
      v.integers("bodies", overlap.key.body_a, overlap.key.body_b, 4, UINT32_MAX);
      v.integers("shapes", overlap.key.shape_a, overlap.key.shape_b, 4, UINT16_MAX);
      v.require(
          [&] {
            const auto& bodies = state.bodies;
            return k.body_a < k.body_b && k.body_b < bodies.size() && bodies[k.body_a].alive &&
                   bodies[k.body_b].alive && bodies[k.body_a].sensor != bodies[k.body_b].sensor &&
                   k.shape_a < bodies[k.body_a].shapes.size() && k.shape_b < bodies[k.body_b].shapes.size();
          },
          [] { return std::string("a sensor overlap refers to a body or shape that does not exist, or no sensor"); });
      const size_t i = static_cast<size_t>(&overlap - state.sensor_overlaps.data());
      v.require([&] { return i == 0 || state.sensor_overlaps[i - 1].key < k; },
                [] { return std::string("sensor overlaps out of order"); });
    });
  });
  // Cars, in a world that has had a car or a character (core/car.h): the
  // definitions, the controls and the tyres' impulses (what the wheels
  // found is found again each step). Characters last, in a world that has
  // had one.
  constexpr size_t car_bytes = 1;  // a dead car: alive
  v.trailing(moved, false, [&] {
    cars_read = true;
    v.list("cars", state.cars, car_bytes, UINT32_MAX, nullptr, [&](auto& car) { describe_car(v, car, state.bodies); });
  });
  constexpr size_t character_bytes = 1;  // a dead character: alive
  v.trailing(!state.characters.empty(), false, [&] {
    characters_read = true;
    v.list("characters", state.characters, character_bytes, UINT32_MAX, nullptr,
           [&](auto& character) { describe_character(v, character); });
  });
  if constexpr (Reading) {
    // A block the image does not have holds nothing: a step's state is read
    // into a copy of the world, whose joints, sensor overlaps or cars (made
    // since the save) would otherwise stay.
    if (!joints_read) {
      state.joints.clear();
      state.free_joint_slots.clear();
    }
    if (!filters_read) state.sensor_overlaps.clear();
    if (!cars_read) state.cars.clear();
    if (!characters_read) state.characters.clear();
    const bool moved_read = !state.cars.empty() || !state.characters.empty();
    bool filtered_read = !state.sensor_overlaps.empty() || moved_read;
    for (const Body& body : state.bodies) {
      filtered_read = filtered_read || (body.alive && (body.filter != CollisionFilter{} || body.sensor));
    }
    v.require(
        [&] {
          return joints_read == (!state.joints.empty() || !state.free_joint_slots.empty() || filtered_read) &&
                 filters_read == filtered_read && cars_read == moved_read &&
                 characters_read == !state.characters.empty();
        },
        [] { return std::string("a joints, filters, cars or characters block that this state does not have"); });
  }
}

}  // namespace bitstep
