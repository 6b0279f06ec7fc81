// The C API (replay/bitstep.h) over the C++ facade (replay/simulation.h).
// No exception crosses into C: each call catches what the facade may throw
// (allocation failure) and returns a status.
#include <cstring>
#include <initializer_list>
#include <new>
#include <optional>
#include <string>
#include <utility>
#include <vector>

#include "core/convex_hull.h"
#include "fixed/decimal.h"
#include "replay/bitstep.h"
#include "replay/bitstep_handle.h"
#include "replay/render_pose.h"
#include "replay/simulation.h"

namespace {

using bitstep::Fixed;
using bitstep::Vec3;
using bitstep::c_api::body_of;
using bitstep::c_api::body_to_c;
using bitstep::c_api::first_null;
using bitstep::c_api::guarded;

Fixed fixed_of(bitstep_fixed raw) { return Fixed::from_raw(raw); }
Vec3 vec3_of(bitstep_vec3 v) { return {fixed_of(v.x), fixed_of(v.y), fixed_of(v.z)}; }
bitstep_vec3 vec3_to_c(Vec3 v) { return {v.x.raw(), v.y.raw(), v.z.raw()}; }
bitstep::Quat quat_of(bitstep_quat q) { return {fixed_of(q.w), fixed_of(q.x), fixed_of(q.y), fixed_of(q.z)}; }
bitstep_quat quat_to_c(const bitstep::Quat& q) { return {q.w.raw(), q.x.raw(), q.y.raw(), q.z.raw()}; }
bitstep_pose pose_to_c(const bitstep::Pose& p) { return {vec3_to_c(p.position), quat_to_c(p.orientation)}; }

void copy_message(const std::string& message, char* error, size_t capacity) {
  if (error == nullptr || capacity == 0) return;
  const size_t n = message.size() < capacity - 1 ? message.size() : capacity - 1;
  std::memcpy(error, message.data(), n);
  error[n] = '\0';
}

bitstep_status fail(bitstep_simulation* sim, bitstep_status status, std::string message) {
  return bitstep::c_api::fail(sim->last_error, status, std::move(message));
}
bitstep_status fail(bitstep_simulation* sim, const bitstep::Error& error) {
  return bitstep::c_api::fail(sim->last_error, error);
}
bitstep_status null_argument(bitstep_simulation* sim, const char* call, const char* argument) {
  return bitstep::c_api::null_argument(sim->last_error, call, argument);
}

// An input call's status: OK; NOT_FOUND for its body (or car, `missing`
// its message); INVALID for a value past its bound, nothing changed.
bitstep_status input_status(bitstep_simulation* sim, const bitstep::InputResult& result, const std::string& missing) {
  switch (result.status) {
    case bitstep::InputResult::Status::applied: return BITSTEP_OK;
    case bitstep::InputResult::Status::not_found: return fail(sim, BITSTEP_NOT_FOUND, missing);
    case bitstep::InputResult::Status::refused: break;
  }
  return fail(sim, result.refusal);
}

std::string no_body_message(bitstep_body body) {
  return "no body in slot " + std::to_string(body.index) + " of generation " + std::to_string(body.generation);
}

bitstep_status no_body(bitstep_simulation* sim, bitstep_body body) {
  return fail(sim, BITSTEP_NOT_FOUND, no_body_message(body));
}

bitstep_status created(bitstep::Result<bitstep::Simulation> made, bitstep_simulation** out, char* error,
                       size_t capacity) {
  if (!made.ok()) {
    copy_message(made.error().message(), error, capacity);
    return BITSTEP_INVALID;
  }
  *out = new bitstep_simulation(std::move(made).value());
  return BITSTEP_OK;
}

// A live body's Body, or nullptr.
const bitstep::Body* live_body(bitstep_simulation* sim, bitstep_body body) {
  const bitstep::World& world = sim->sim->world();
  return world.is_alive(body_of(body)) ? &world.body(body_of(body)) : nullptr;
}

// A getter of one live body: `out` checked, the body found (NOT_FOUND
// naming the handle), then read(body, *out) gives the status.
template <typename Out, typename Read>
bitstep_status read_body(bitstep_simulation* sim, const char* call, bitstep_body body, Out* out, Read&& read) {
  return guarded(sim, [&] {
    if (out == nullptr) return null_argument(sim, call, "out");
    const bitstep::Body* b = live_body(sim, body);
    if (b == nullptr) return no_body(sim, body);
    return read(*b, *out);
  });
}

// `size` bytes needed for a caller's buffer of `capacity` (a NULL buffer of
// capacity 0 asks): BUFFER_TOO_SMALL naming the call, or OK.
bitstep_status fits(bitstep_simulation* sim, const char* call, size_t size, size_t capacity) {
  if (size <= capacity) return BITSTEP_OK;
  return fail(sim, BITSTEP_BUFFER_TOO_SMALL,
              std::string(call) + ": " + std::to_string(size) + " needed, " + std::to_string(capacity) + " given");
}

// A C orientation made unit (the world takes unit quaternions), or an error at `place`.
bitstep::Result<bitstep::Quat> unit_quat(bitstep_quat q, const std::string& place) {
  const bitstep::Quat quat = quat_of(q);
  if (quat == bitstep::Quat{Fixed{}, Fixed{}, Fixed{}, Fixed{}}) return bitstep::Error{place, "a zero quaternion"};
  return bitstep::normalize(quat);
}

bitstep::Result<bitstep::Material> material_of(const bitstep_material& m) {
  const auto within = [](bitstep_fixed v, bool unit) { return v >= 0 && (!unit || v <= (int64_t{1} << 32)); };
  if (!within(m.static_friction, false)) return bitstep::Error{"material.static_friction", "negative"};
  if (!within(m.dynamic_friction, false)) return bitstep::Error{"material.dynamic_friction", "negative"};
  if (!within(m.restitution, true)) return bitstep::Error{"material.restitution", "outside 0..1"};
  if (!within(m.rolling_resistance, true)) return bitstep::Error{"material.rolling_resistance", "outside 0..1"};
  return bitstep::Material{fixed_of(m.static_friction), fixed_of(m.dynamic_friction), fixed_of(m.restitution),
                           fixed_of(m.rolling_resistance)};
}

// A hull shape's points built into its hull; the builder's refusal placed
// under the shape ("shapes[2].points[7].y: outside -50..50 m").
bitstep::Result<std::shared_ptr<const bitstep::ConvexHull>> hull_of(const bitstep_shape& cs, const std::string& place) {
  if (cs.points == nullptr && cs.point_count > 0) {
    return bitstep::Error{place + ".points", "NULL with a point_count of " + std::to_string(cs.point_count)};
  }
  if (cs.point_count > bitstep::max_hull_points) {
    return bitstep::Error{place + ".points", std::to_string(cs.point_count) + " points: a hull needs 4 to 1024"};
  }
  std::vector<Vec3> points;
  for (uint32_t k = 0; k < cs.point_count; ++k) points.push_back(vec3_of(cs.points[k]));
  auto hull = bitstep::build_convex_hull(points);
  if (!hull.ok()) {
    const bitstep::Error& e = hull.error();
    return bitstep::Error{place + (e.place.empty() ? ".points" : "." + e.place), e.reason};
  }
  return std::move(hull.value());
}

// The world's definition of a C body, or the field that makes no sense as
// one (the world checks the rest: core/envelope.h).
bitstep::Result<bitstep::BodyDef> body_def_of(const bitstep_body_def& c) {
  bitstep::BodyDef def;
  if (c.type < BITSTEP_STATIC || c.type > BITSTEP_DYNAMIC) return bitstep::Error{"type", "not a bitstep_body_type"};
  def.type = static_cast<bitstep::BodyType>(c.type);
  def.pose.position = vec3_of(c.pose.position);
  const auto orientation = unit_quat(c.pose.orientation, "pose.orientation");
  if (!orientation.ok()) return orientation.error();
  def.pose.orientation = orientation.value();
  def.linear_velocity = vec3_of(c.linear_velocity);
  def.angular_velocity = vec3_of(c.angular_velocity);
  def.density = fixed_of(c.density);
  def.mass = fixed_of(c.mass);
  if (c.mass < 0) return bitstep::Error{"mass", "negative"};
  const auto material = material_of(c.material);
  if (!material.ok()) return material.error();
  def.material = material.value();
  if (c.linear_damping < 0) return bitstep::Error{"linear_damping", "negative"};
  if (c.angular_damping < 0) return bitstep::Error{"angular_damping", "negative"};
  def.linear_damping = fixed_of(c.linear_damping);
  def.angular_damping = fixed_of(c.angular_damping);
  def.filter = {c.layers, c.collides_with};
  def.asleep = c.asleep != 0;
  def.sensor = c.sensor != 0;
  if (c.shape_count > 0 && c.shapes == nullptr)
    return bitstep::Error{"shapes", "NULL with a shape_count of " + std::to_string(c.shape_count)};
  if (c.shape_count > 256) return bitstep::Error{"shape_count", "more than 256 shapes"};
  for (uint32_t i = 0; i < c.shape_count; ++i) {
    const bitstep_shape& cs = c.shapes[i];
    const std::string place = "shapes[" + std::to_string(i) + "]";
    if (cs.type < BITSTEP_SHAPE_PLANE || cs.type > BITSTEP_SHAPE_HEIGHTFIELD) {
      return bitstep::Error{place + ".type", "not a bitstep_shape_type"};
    }
    if (cs.type == BITSTEP_SHAPE_MESH || cs.type == BITSTEP_SHAPE_HEIGHTFIELD) {
      return bitstep::Error{place + ".type", std::string("a ") +
                                                 bitstep::shape_type_names[static_cast<size_t>(cs.type)] +
                                                 " comes from JSON (bitstep_add_body), not from a struct"};
    }
    bitstep::Shape shape;
    shape.type = static_cast<bitstep::ShapeType>(cs.type);
    shape.half_extents = vec3_of(cs.half_extents);
    shape.radius = fixed_of(cs.radius);
    shape.half_height = fixed_of(cs.half_height);
    shape.local.position = vec3_of(cs.local.position);
    const auto local = unit_quat(cs.local.orientation, place + ".local.orientation");
    if (!local.ok()) return local.error();
    shape.local.orientation = local.value();
    if (shape.type == bitstep::ShapeType::hull) {
      auto hull = hull_of(cs, place);
      if (!hull.ok()) return hull.error();
      shape.hull = std::move(hull.value());
    }
    def.shapes.push_back(shape);
  }
  return def;
}

bitstep::Result<bitstep::JointDef> joint_def_of(const bitstep_joint_def& c) {
  bitstep::JointDef def;
  if (c.type < BITSTEP_JOINT_POINT || c.type > BITSTEP_JOINT_SLIDER) {
    return bitstep::Error{"type", "not a bitstep_joint_type"};
  }
  def.type = static_cast<bitstep::JointType>(c.type);
  def.body_a = body_of(c.body_a);
  def.body_b = body_of(c.body_b);
  def.anchor_a = vec3_of(c.anchor_a);
  def.anchor_b = vec3_of(c.anchor_b);
  def.length = fixed_of(c.length);
  def.axis = vec3_of(c.axis);
  def.limited = c.limited != 0;
  def.lower_angle = fixed_of(c.lower_angle);
  def.upper_angle = fixed_of(c.upper_angle);
  def.swing_angle = fixed_of(c.swing_angle);
  def.lower_translation = fixed_of(c.lower_translation);
  def.upper_translation = fixed_of(c.upper_translation);
  def.motor_speed = fixed_of(c.motor_speed);
  def.motor_max = fixed_of(c.motor_max);
  def.break_impulse = fixed_of(c.break_impulse);
  def.friction_torque = fixed_of(c.friction_torque);
  def.velocity_iterations = c.velocity_iterations;
  def.position_iterations = c.position_iterations;
  return def;
}

bitstep_shape shape_to_c(const bitstep::Shape& shape, Vec3 frame_offset) {
  bitstep_shape c{};
  if (shape.hull) c.point_count = static_cast<uint32_t>(shape.hull->vertices.size());
  c.type = static_cast<int32_t>(shape.type);
  c.half_extents = vec3_to_c(shape.half_extents);
  c.radius = shape.radius.raw();
  c.half_height = shape.half_height.raw();
  c.local = pose_to_c({shape.local.position + frame_offset, shape.local.orientation});
  return c;
}

// Every live body in slot order, written by `write(slot, id, out)` into a
// caller's array of `capacity` (the count needed in *count).
template <typename Out, typename Write>
bitstep_status every_live_body(bitstep_simulation* sim, const char* call, Out* out, size_t capacity, size_t* count,
                               Write&& write) {
  if (count == nullptr) return null_argument(sim, call, "count");
  if (out == nullptr && capacity > 0) return null_argument(sim, call, "out (of capacity > 0)");
  const auto& bodies = sim->sim->world().bodies();
  size_t live = 0;
  for (const bitstep::Body& body : bodies) live += body.alive ? 1 : 0;
  *count = live;
  if (const bitstep_status status = fits(sim, call, live, capacity); status != BITSTEP_OK) return status;
  size_t k = 0;
  for (uint32_t slot = 0; slot < bodies.size(); ++slot) {
    if (bodies[slot].alive) write(bitstep::BodyId{slot, bodies[slot].generation}, out[k++]);
  }
  return BITSTEP_OK;
}

}  // namespace

extern "C" {

bitstep_status bitstep_fixed_parse(const char* text, bitstep_fixed* out) {
  if (text == nullptr || out == nullptr) return BITSTEP_NULL_ARGUMENT;
  const bitstep::ParseResult parsed = bitstep::parse_fixed(text);
  if (!parsed.ok()) return BITSTEP_INVALID;
  *out = parsed.value.raw();
  return BITSTEP_OK;
}

double bitstep_fixed_to_double(bitstep_fixed value) { return static_cast<double>(value) / 4294967296.0; }

bitstep_status bitstep_create_from_file(const char* path, bitstep_simulation** out, char* error,
                                        size_t error_capacity) {
  if (out != nullptr) *out = nullptr;
  if (const char* null = first_null({{path, "path"}, {out, "out"}})) {
    copy_message(std::string("create_from_file: ") + null + " is NULL", error, error_capacity);
    return BITSTEP_NULL_ARGUMENT;
  }
  try {
    return created(bitstep::Simulation::from_file(path), out, error, error_capacity);
  } catch (const std::bad_alloc&) {
    copy_message("out of memory", error, error_capacity);
    return BITSTEP_OUT_OF_MEMORY;
  }
}

bitstep_status bitstep_create_from_text(const char* json, size_t length, const char* name, bitstep_simulation** out,
                                        char* error, size_t error_capacity) {
  if (out != nullptr) *out = nullptr;
  if (const char* null = first_null({{json, "json"}, {name, "name"}, {out, "out"}})) {
    copy_message(std::string("create_from_text: ") + null + " is NULL", error, error_capacity);
    return BITSTEP_NULL_ARGUMENT;
  }
  try {
    return created(bitstep::Simulation::from_text(std::string_view(json, length), name), out, error, error_capacity);
  } catch (const std::bad_alloc&) {
    copy_message("out of memory", error, error_capacity);
    return BITSTEP_OUT_OF_MEMORY;
  }
}

void bitstep_destroy(bitstep_simulation* sim) {
  if (sim != nullptr && sim->owned) delete sim;  // a session's world ends with the session
}

const char* bitstep_last_error(const bitstep_simulation* sim) { return sim == nullptr ? "" : sim->last_error.c_str(); }

bitstep_status bitstep_find_body(bitstep_simulation* sim, const char* name, bitstep_body* out) {
  return guarded(sim, [&] {
    if (const char* null = first_null({{name, "name"}, {out, "out"}})) return null_argument(sim, "find_body", null);
    const auto id = sim->sim->find_body(name);
    if (!id) return fail(sim, BITSTEP_NOT_FOUND, std::string("no body named \"") + name + "\"");
    *out = body_to_c(*id);
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_add_body(bitstep_simulation* sim, const char* body_json, bitstep_body* out) {
  return guarded(sim, [&] {
    if (const char* null = first_null({{body_json, "body_json"}, {out, "out"}})) {
      return null_argument(sim, "add_body", null);
    }
    const bitstep::Result<bitstep::BodyId> id = sim->sim->add_body(body_json);
    if (!id.ok()) return fail(sim, id.error());
    *out = body_to_c(id.value());
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_remove_body(bitstep_simulation* sim, bitstep_body body) {
  return guarded(sim, [&] { return sim->sim->remove_body(body_of(body)) ? BITSTEP_OK : no_body(sim, body); });
}

bitstep_status bitstep_add_joint(bitstep_simulation* sim, const char* joint_json, bitstep_joint* out) {
  return guarded(sim, [&] {
    if (const char* null = first_null({{joint_json, "joint_json"}, {out, "out"}})) {
      return null_argument(sim, "add_joint", null);
    }
    const bitstep::Result<bitstep::JointId> id = sim->sim->add_joint(joint_json);
    if (!id.ok()) return fail(sim, id.error());
    *out = {id->index, id->generation};
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_remove_joint(bitstep_simulation* sim, bitstep_joint joint) {
  return guarded(sim, [&] {
    if (sim->sim->remove_joint({joint.index, joint.generation})) return BITSTEP_OK;
    return fail(sim, BITSTEP_NOT_FOUND, "no joint in slot " + std::to_string(joint.index) + " of generation " +
                                            std::to_string(joint.generation));
  });
}

bitstep_status bitstep_get_body_type(bitstep_simulation* sim, bitstep_body body, bitstep_body_type* out) {
  return read_body(sim, "get_body_type", body, out, [](const bitstep::Body& b, bitstep_body_type& type) {
    type = static_cast<bitstep_body_type>(b.type);  // the same numbers (static_asserts below)
    return BITSTEP_OK;
  });
}

uint32_t bitstep_slot_count(const bitstep_simulation* sim) {
  return sim == nullptr ? 0 : static_cast<uint32_t>(sim->sim->world().bodies().size());
}

bitstep_status bitstep_body_in_slot(bitstep_simulation* sim, uint32_t slot, bitstep_body* out) {
  return guarded(sim, [&] {
    if (out == nullptr) return null_argument(sim, "body_in_slot", "out");
    const auto& bodies = sim->sim->world().bodies();
    if (slot >= bodies.size() || !bodies[slot].alive) {
      return fail(sim, BITSTEP_NOT_FOUND, "slot " + std::to_string(slot) + " is empty");
    }
    *out = {slot, bodies[slot].generation};
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_apply_impulse(bitstep_simulation* sim, bitstep_body body, bitstep_vec3 impulse,
                                     bitstep_vec3 world_point) {
  return guarded(sim, [&] {
    return input_status(sim, sim->sim->apply_impulse(body_of(body), vec3_of(impulse), vec3_of(world_point)),
                        no_body_message(body));
  });
}

bitstep_status bitstep_apply_force(bitstep_simulation* sim, bitstep_body body, bitstep_vec3 force,
                                   bitstep_vec3 world_point) {
  return guarded(sim, [&] {
    return input_status(sim, sim->sim->apply_force(body_of(body), vec3_of(force), vec3_of(world_point)),
                        no_body_message(body));
  });
}

bitstep_status bitstep_set_velocity(bitstep_simulation* sim, bitstep_body body, bitstep_vec3 linear,
                                    bitstep_vec3 angular) {
  return guarded(sim, [&] {
    return input_status(sim, sim->sim->set_velocity(body_of(body), vec3_of(linear), vec3_of(angular)),
                        no_body_message(body));
  });
}

bitstep_status bitstep_wake(bitstep_simulation* sim, bitstep_body body) {
  return guarded(sim, [&] { return sim->sim->wake(body_of(body)) ? BITSTEP_OK : no_body(sim, body); });
}

bitstep_status bitstep_drive(bitstep_simulation* sim, const char* car, bitstep_fixed throttle, bitstep_fixed brake,
                             bitstep_fixed steer) {
  return guarded(sim, [&] {
    if (car == nullptr) return null_argument(sim, "drive", "car");
    return input_status(sim, sim->sim->drive(car, {fixed_of(throttle), fixed_of(brake), fixed_of(steer)}),
                        std::string("no car named \"") + car + "\"");
  });
}

bitstep_status bitstep_move_character(bitstep_simulation* sim, const char* character, bitstep_vec3 velocity,
                                      int32_t jump) {
  return guarded(sim, [&] {
    if (character == nullptr) return null_argument(sim, "move_character", "character");
    return input_status(sim, sim->sim->move(character, {vec3_of(velocity), jump != 0}),
                        std::string("no character named \"") + character + "\"");
  });
}

bitstep_status bitstep_add_character(bitstep_simulation* sim, const char* character_json) {
  return guarded(sim, [&] {
    if (character_json == nullptr) return null_argument(sim, "add_character", "character_json");
    const bitstep::Result<void> added = sim->sim->add_character(character_json);
    if (!added.ok()) return fail(sim, added.error());
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_remove_character(bitstep_simulation* sim, const char* character) {
  return guarded(sim, [&] {
    if (character == nullptr) return null_argument(sim, "remove_character", "character");
    if (sim->sim->remove_character(character)) return BITSTEP_OK;
    return fail(sim, BITSTEP_NOT_FOUND, std::string("no character named \"") + character + "\"");
  });
}

bitstep_status bitstep_get_character(bitstep_simulation* sim, const char* character, bitstep_character_state* out) {
  return guarded(sim, [&] {
    if (const char* null = first_null({{character, "character"}, {out, "out"}})) {
      return null_argument(sim, "get_character", null);
    }
    const bitstep::Character* c = sim->sim->character(character);
    if (c == nullptr) return fail(sim, BITSTEP_NOT_FOUND, std::string("no character named \"") + character + "\"");
    out->position = vec3_to_c(c->position);
    out->velocity = vec3_to_c(c->velocity);
    out->facing = vec3_to_c(c->facing);
    out->ground = static_cast<int32_t>(c->ground);
    out->ground_body =
        c->ground == bitstep::GroundState::in_air ? bitstep_body{UINT32_MAX, 0} : body_to_c(c->ground_body);
    out->ground_normal = vec3_to_c(c->ground_normal);
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_step(bitstep_simulation* sim) {
  return guarded(sim, [&] {
    sim->sim->step();
    return BITSTEP_OK;
  });
}

uint64_t bitstep_tick(const bitstep_simulation* sim) { return sim == nullptr ? 0 : sim->sim->tick(); }

uint64_t bitstep_hash(const bitstep_simulation* sim) { return sim == nullptr ? 0 : sim->sim->hash(); }

bitstep_status bitstep_get_pose(bitstep_simulation* sim, bitstep_body body, bitstep_pose* out) {
  return guarded(sim, [&] {
    if (out == nullptr) return null_argument(sim, "get_pose", "out");
    const auto pose = sim->sim->pose(body_of(body));
    if (!pose) return no_body(sim, body);
    const bitstep::Quat& q = pose->orientation;
    *out = {vec3_to_c(pose->position), {q.w.raw(), q.x.raw(), q.y.raw(), q.z.raw()}};
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_get_render_pose(bitstep_simulation* sim, bitstep_body body, bitstep_render_pose* out) {
  return guarded(sim, [&] {
    if (out == nullptr) return null_argument(sim, "get_render_pose", "out");
    const auto pose = sim->sim->pose(body_of(body));
    if (!pose) return no_body(sim, body);
    const bitstep::RenderPose r = bitstep::render_pose(*pose);
    std::memcpy(out->position, r.position, sizeof r.position);
    std::memcpy(out->orientation, r.orientation, sizeof r.orientation);
    return BITSTEP_OK;
  });
}

void bitstep_interpolate(const bitstep_render_pose* from, const bitstep_render_pose* to, float alpha,
                         bitstep_render_pose* out) {
  if (from == nullptr || to == nullptr || out == nullptr) return;
  bitstep::RenderPose a{}, b{};
  std::memcpy(a.position, from->position, sizeof a.position);
  std::memcpy(a.orientation, from->orientation, sizeof a.orientation);
  std::memcpy(b.position, to->position, sizeof b.position);
  std::memcpy(b.orientation, to->orientation, sizeof b.orientation);
  const bitstep::RenderPose r = bitstep::interpolate(a, b, alpha);
  std::memcpy(out->position, r.position, sizeof r.position);
  std::memcpy(out->orientation, r.orientation, sizeof r.orientation);
}

bitstep_status bitstep_save(bitstep_simulation* sim, uint8_t* buffer, size_t capacity, size_t* size) {
  return guarded(sim, [&] {
    if (size == nullptr) return null_argument(sim, "save", "size");
    if (buffer == nullptr && capacity > 0) return null_argument(sim, "save", "buffer (of capacity > 0)");
    const std::vector<uint8_t> image = sim->sim->save();
    *size = image.size();
    if (image.size() > capacity) {
      return fail(sim, BITSTEP_BUFFER_TOO_SMALL,
                  "save: " + std::to_string(image.size()) + " bytes needed, " + std::to_string(capacity) + " given");
    }
    std::memcpy(buffer, image.data(), image.size());
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_load(bitstep_simulation* sim, const uint8_t* image, size_t size) {
  return guarded(sim, [&] {
    if (image == nullptr) return null_argument(sim, "load", "image");
    if (const bitstep::Result<void> loaded = sim->sim->load({image, size}); !loaded.ok()) {
      return fail(sim, loaded.error().within("load"));
    }
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_save_state(bitstep_simulation* sim, uint8_t* buffer, size_t capacity, size_t* size) {
  return guarded(sim, [&] {
    if (size == nullptr) return null_argument(sim, "save_state", "size");
    if (buffer == nullptr && capacity > 0) return null_argument(sim, "save_state", "buffer (of capacity > 0)");
    *size = sim->sim->save_state({buffer, capacity});
    if (*size > capacity) {
      return fail(sim, BITSTEP_BUFFER_TOO_SMALL,
                  "save_state: " + std::to_string(*size) + " bytes needed, " + std::to_string(capacity) + " given");
    }
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_state_checksum(const uint8_t* image, size_t size, uint64_t* checksum) {
  if (image == nullptr || checksum == nullptr) return BITSTEP_NULL_ARGUMENT;
  const std::optional<uint64_t> carried = bitstep::RollbackStates::checksum({image, size});
  if (!carried) return BITSTEP_INVALID;
  *checksum = *carried;
  return BITSTEP_OK;
}

uint64_t bitstep_checksum(const bitstep_simulation* sim) { return sim == nullptr ? 0 : sim->sim->checksum(); }

bitstep_status bitstep_load_state(bitstep_simulation* sim, const uint8_t* image, size_t size) {
  return guarded(sim, [&] {
    if (image == nullptr) return null_argument(sim, "load_state", "image");
    if (const bitstep::Result<void> loaded = sim->sim->load_state({image, size}); !loaded.ok()) {
      return fail(sim, loaded.error().within("load_state"));
    }
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_cast_ray(bitstep_simulation* sim, bitstep_vec3 origin, bitstep_vec3 translation,
                                bitstep_ray_hit* out) {
  return guarded(sim, [&] {
    if (out == nullptr) return null_argument(sim, "cast_ray", "out");
    const auto hit = sim->sim->query().cast_ray(vec3_of(origin), vec3_of(translation));
    if (!hit) return fail(sim, BITSTEP_NOT_FOUND, "the ray meets nothing");
    *out = {body_to_c(hit->body), hit->shape, hit->fraction.raw(), vec3_to_c(hit->point), vec3_to_c(hit->normal)};
    return BITSTEP_OK;
  });
}

bitstep_fixed bitstep_fixed_from_int(int32_t value) { return Fixed::from_int(value).raw(); }

bitstep_status bitstep_fixed_from_ratio(int64_t numerator, int64_t denominator, bitstep_fixed* out) {
  if (out == nullptr) return BITSTEP_NULL_ARGUMENT;
  if (denominator == 0) return BITSTEP_INVALID;
  // |n| / |d| below 2^31 - 1: the rounded quotient fits Q32.32 (no saturation).
  const auto magnitude = [](int64_t v) {
    return v < 0 ? uint64_t{0} - static_cast<uint64_t>(v) : static_cast<uint64_t>(v);
  };
  if (magnitude(numerator) / magnitude(denominator) >= (uint64_t{1} << 31) - 1) return BITSTEP_INVALID;
  *out = Fixed::from_ratio(numerator, denominator).raw();
  return BITSTEP_OK;
}

int64_t bitstep_fixed_round(bitstep_fixed value) { return bitstep::round(fixed_of(value)).raw() >> 32; }

bitstep_body_def bitstep_default_body_def(void) {
  const bitstep::BodyDef d;
  bitstep_body_def c{};
  c.type = BITSTEP_DYNAMIC;
  c.pose = pose_to_c(d.pose);
  c.density = d.density.raw();
  c.material = {d.material.static_friction.raw(), d.material.dynamic_friction.raw(), d.material.restitution.raw(),
                d.material.rolling_resistance.raw()};
  c.layers = d.filter.layers;
  c.collides_with = d.filter.collides_with;
  return c;
}

bitstep_joint_def bitstep_default_joint_def(void) {
  bitstep_joint_def c{};
  c.type = BITSTEP_JOINT_POINT;
  return c;
}

bitstep_status bitstep_create_body(bitstep_simulation* sim, const bitstep_body_def* def, bitstep_body* out) {
  return guarded(sim, [&] {
    if (const char* null = first_null({{def, "def"}, {out, "out"}})) return null_argument(sim, "create_body", null);
    const bitstep::Result<bitstep::BodyDef> made = body_def_of(*def);
    if (!made.ok()) return fail(sim, made.error().within("create_body"));
    const bitstep::Result<bitstep::BodyId> id =
        sim->sim->create_body(made.value(), def->name == nullptr ? "" : def->name);
    if (!id.ok()) return fail(sim, id.error());
    *out = body_to_c(id.value());
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_create_joint(bitstep_simulation* sim, const bitstep_joint_def* def, bitstep_joint* out) {
  return guarded(sim, [&] {
    if (const char* null = first_null({{def, "def"}, {out, "out"}})) return null_argument(sim, "create_joint", null);
    const bitstep::Result<bitstep::JointDef> made = joint_def_of(*def);
    if (!made.ok()) return fail(sim, made.error().within("create_joint"));
    const bitstep::Result<bitstep::JointId> id = sim->sim->create_joint(made.value());
    if (!id.ok()) return fail(sim, id.error());
    *out = {id->index, id->generation};
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_get_velocity(bitstep_simulation* sim, bitstep_body body, bitstep_vec3* linear,
                                    bitstep_vec3* angular) {
  return guarded(sim, [&] {
    if (const char* null = first_null({{linear, "linear"}, {angular, "angular"}})) {
      return null_argument(sim, "get_velocity", null);
    }
    const bitstep::Body* b = live_body(sim, body);
    if (b == nullptr) return no_body(sim, body);
    *linear = vec3_to_c(b->linear_velocity);
    *angular = vec3_to_c(b->angular_velocity);
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_is_asleep(bitstep_simulation* sim, bitstep_body body, int32_t* out) {
  return read_body(sim, "is_asleep", body, out, [](const bitstep::Body& b, int32_t& asleep) {
    asleep = b.type == bitstep::BodyType::dynamic && b.asleep ? 1 : 0;
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_get_body_name(bitstep_simulation* sim, bitstep_body body, char* buffer, size_t capacity,
                                     size_t* size) {
  return guarded(sim, [&] {
    if (size == nullptr) return null_argument(sim, "get_body_name", "size");
    if (buffer == nullptr && capacity > 0) return null_argument(sim, "get_body_name", "buffer (of capacity > 0)");
    if (live_body(sim, body) == nullptr) return no_body(sim, body);
    const std::string_view name = sim->sim->name(body_of(body));
    *size = name.size() + 1;
    if (const bitstep_status status = fits(sim, "get_body_name", *size, capacity); status != BITSTEP_OK) return status;
    std::memcpy(buffer, name.data(), name.size());
    buffer[name.size()] = '\0';
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_get_shape_count(bitstep_simulation* sim, bitstep_body body, uint32_t* out) {
  return read_body(sim, "get_shape_count", body, out, [](const bitstep::Body& b, uint32_t& count) {
    count = static_cast<uint32_t>(b.shapes.size());
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_get_shape(bitstep_simulation* sim, bitstep_body body, uint32_t index, bitstep_shape* out) {
  return read_body(sim, "get_shape", body, out, [&](const bitstep::Body& b, bitstep_shape& shape) {
    if (index >= b.shapes.size()) {
      return fail(sim, BITSTEP_NOT_FOUND,
                  "get_shape: shape " + std::to_string(index) + " of " + std::to_string(b.shapes.size()));
    }
    shape = shape_to_c(b.shapes[index], sim->sim->frame_offset(body_of(body)));
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_get_hull_points(bitstep_simulation* sim, bitstep_body body, uint32_t index, bitstep_vec3* out,
                                       size_t capacity, size_t* count) {
  return guarded(sim, [&] {
    if (count == nullptr) return null_argument(sim, "get_hull_points", "count");
    if (out == nullptr && capacity > 0) return null_argument(sim, "get_hull_points", "out (of capacity > 0)");
    const bitstep::Body* live = live_body(sim, body);
    if (live == nullptr) return no_body(sim, body);
    const bitstep::Body& b = *live;
    if (index >= b.shapes.size()) {
      return fail(sim, BITSTEP_NOT_FOUND,
                  "get_hull_points: shape " + std::to_string(index) + " of " + std::to_string(b.shapes.size()));
    }
    const bitstep::Shape& shape = b.shapes[index];
    if (!shape.hull)
      return fail(sim, BITSTEP_INVALID, "get_hull_points: shape " + std::to_string(index) + " is no hull");
    const size_t n = shape.hull->vertices.size();
    *count = n;
    if (const bitstep_status status = fits(sim, "get_hull_points", n, capacity); status != BITSTEP_OK) return status;
    for (size_t k = 0; k < n; ++k) out[k] = vec3_to_c(shape.hull->vertices[k]);
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_get_poses(bitstep_simulation* sim, bitstep_body_pose* out, size_t capacity, size_t* count) {
  return guarded(sim, [&] {
    return every_live_body(sim, "get_poses", out, capacity, count, [&](bitstep::BodyId id, bitstep_body_pose& o) {
      o = {body_to_c(id), pose_to_c(*sim->sim->pose(id))};
    });
  });
}

bitstep_status bitstep_get_render_poses(bitstep_simulation* sim, bitstep_body_render_pose* out, size_t capacity,
                                        size_t* count) {
  return guarded(sim, [&] {
    return every_live_body(sim, "get_render_poses", out, capacity, count,
                           [&](bitstep::BodyId id, bitstep_body_render_pose& o) {
                             const bitstep::RenderPose r = bitstep::render_pose(*sim->sim->pose(id));
                             o.body = body_to_c(id);
                             std::memcpy(o.pose.position, r.position, sizeof r.position);
                             std::memcpy(o.pose.orientation, r.orientation, sizeof r.orientation);
                           });
  });
}

bitstep_status bitstep_set_events(bitstep_simulation* sim, int32_t on) {
  return guarded(sim, [&] {
    sim->sim->world().set_events(on != 0);
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_get_events(bitstep_simulation* sim, bitstep_event* out, size_t capacity, size_t* count) {
  return guarded(sim, [&] {
    if (count == nullptr) return null_argument(sim, "get_events", "count");
    if (out == nullptr && capacity > 0) return null_argument(sim, "get_events", "out (of capacity > 0)");
    const bitstep::World& world = sim->sim->world();
    const std::vector<bitstep::WorldEvent>& events = world.events();
    *count = events.size();
    if (const bitstep_status status = fits(sim, "get_events", events.size(), capacity); status != BITSTEP_OK) {
      return status;
    }
    // A slot's generation is its last body's (a removed body's slot keeps
    // it until reused): the handle the game holds.
    const auto handle = [&](uint32_t slot) { return bitstep_body{slot, world.bodies()[slot].generation}; };
    for (size_t i = 0; i < events.size(); ++i) {
      const bitstep::WorldEvent& e = events[i];
      out[i] = {
          static_cast<int32_t>(e.kind), handle(e.key.body_a), handle(e.key.body_b), e.key.shape_a, e.key.shape_b, {}};
      if (e.kind == bitstep::EventKind::joint_broken) out[i].joint = {e.joint, world.joints()[e.joint].generation};
    }
    return BITSTEP_OK;
  });
}

}  // extern "C"

// The C enumerations are the engine's, number for number.
static_assert(BITSTEP_STATIC == static_cast<int>(bitstep::BodyType::static_body));
static_assert(BITSTEP_DYNAMIC == static_cast<int>(bitstep::BodyType::dynamic));
static_assert(BITSTEP_KINEMATIC == static_cast<int>(bitstep::BodyType::kinematic));
static_assert(BITSTEP_SHAPE_PLANE == static_cast<int>(bitstep::ShapeType::plane));
static_assert(BITSTEP_SHAPE_BOX == static_cast<int>(bitstep::ShapeType::box));
static_assert(BITSTEP_SHAPE_CAPSULE == static_cast<int>(bitstep::ShapeType::capsule));
static_assert(BITSTEP_SHAPE_SPHERE == static_cast<int>(bitstep::ShapeType::sphere));
static_assert(BITSTEP_SHAPE_HULL == static_cast<int>(bitstep::ShapeType::hull));
static_assert(BITSTEP_SHAPE_MESH == static_cast<int>(bitstep::ShapeType::mesh));
static_assert(BITSTEP_SHAPE_HEIGHTFIELD == static_cast<int>(bitstep::ShapeType::heightfield));
static_assert(BITSTEP_IN_AIR == static_cast<int>(bitstep::GroundState::in_air));
static_assert(BITSTEP_ON_STEEP_SLOPE == static_cast<int>(bitstep::GroundState::on_steep_slope));
static_assert(BITSTEP_JOINT_MAX_DISTANCE == static_cast<int>(bitstep::JointType::max_distance));
static_assert(BITSTEP_JOINT_HINGE == static_cast<int>(bitstep::JointType::hinge));
static_assert(BITSTEP_JOINT_CONE == static_cast<int>(bitstep::JointType::cone));
static_assert(BITSTEP_JOINT_SLIDER == static_cast<int>(bitstep::JointType::slider));
static_assert(BITSTEP_SENSOR_END == static_cast<int>(bitstep::EventKind::sensor_end));
static_assert(BITSTEP_LEFT_WORLD == static_cast<int>(bitstep::EventKind::left_world));
static_assert(BITSTEP_JOINT_BROKEN == static_cast<int>(bitstep::EventKind::joint_broken));
