// The C API (replay/bitstep.h) over the C++ facade (replay/simulation.h).
// No exception crosses into C: each call catches what the facade may throw
// (allocation failure) and returns a status.
#include <cstring>
#include <initializer_list>
#include <new>
#include <optional>
#include <string>
#include <utility>

#include "fixed/decimal.h"
#include "replay/bitstep.h"
#include "replay/render_pose.h"
#include "replay/simulation.h"

struct bitstep_simulation {
  bitstep::Simulation sim;
  std::string last_error;
};

namespace {

using bitstep::Fixed;
using bitstep::Vec3;

Fixed fixed_of(bitstep_fixed raw) { return Fixed::from_raw(raw); }
Vec3 vec3_of(bitstep_vec3 v) { return {fixed_of(v.x), fixed_of(v.y), fixed_of(v.z)}; }
bitstep_vec3 vec3_to_c(Vec3 v) { return {v.x.raw(), v.y.raw(), v.z.raw()}; }
bitstep::BodyId body_of(bitstep_body b) { return {b.index, b.generation}; }
bitstep_body body_to_c(bitstep::BodyId id) { return {id.index, id.generation}; }

void copy_message(const std::string& message, char* error, size_t capacity) {
  if (error == nullptr || capacity == 0) return;
  const size_t n = message.size() < capacity - 1 ? message.size() : capacity - 1;
  std::memcpy(error, message.data(), n);
  error[n] = '\0';
}

bitstep_status fail(bitstep_simulation* sim, bitstep_status status, std::string message) {
  sim->last_error = std::move(message);
  return status;
}

// The one mapping of the facade's Error to a status: every error it returns
// is about the input (a malformed scene, body, joint or image), so
// BITSTEP_INVALID, the message its one line.
bitstep_status status_of(const bitstep::Error& error, std::string& message) {
  message = error.message();
  return BITSTEP_INVALID;
}

bitstep_status fail(bitstep_simulation* sim, const bitstep::Error& error) { return status_of(error, sim->last_error); }

// A NULL where the call needs a pointer: "get_pose: out is NULL".
bitstep_status null_argument(bitstep_simulation* sim, const char* call, const char* argument) {
  return fail(sim, BITSTEP_NULL_ARGUMENT, std::string(call) + ": " + argument + " is NULL");
}

// The first NULL of a call's pointer arguments, or nullptr.
const char* first_null(std::initializer_list<std::pair<const void*, const char*>> arguments) {
  for (const auto& [pointer, name] : arguments) {
    if (pointer == nullptr) return name;
  }
  return nullptr;
}

// Runs `call` (returning a status) with sim checked and exceptions caught.
template <typename Call>
bitstep_status guarded(bitstep_simulation* sim, Call&& call) {
  if (sim == nullptr) return BITSTEP_NULL_ARGUMENT;
  try {
    return call();
  } catch (const std::bad_alloc&) {
    return fail(sim, BITSTEP_OUT_OF_MEMORY, "out of memory");
  } catch (const std::exception& e) {
    return fail(sim, BITSTEP_INVALID, e.what());
  }
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
    std::string message;
    const bitstep_status status = status_of(made.error(), message);
    copy_message(message, error, capacity);
    return status;
  }
  *out = new bitstep_simulation{std::move(made).value(), {}};
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

void bitstep_destroy(bitstep_simulation* sim) { delete sim; }

const char* bitstep_last_error(const bitstep_simulation* sim) { return sim == nullptr ? "" : sim->last_error.c_str(); }

bitstep_status bitstep_find_body(bitstep_simulation* sim, const char* name, bitstep_body* out) {
  return guarded(sim, [&] {
    if (const char* null = first_null({{name, "name"}, {out, "out"}})) return null_argument(sim, "find_body", null);
    const auto id = sim->sim.find_body(name);
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
    const bitstep::Result<bitstep::BodyId> id = sim->sim.add_body(body_json);
    if (!id.ok()) return fail(sim, id.error());
    *out = body_to_c(id.value());
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_remove_body(bitstep_simulation* sim, bitstep_body body) {
  return guarded(sim, [&] { return sim->sim.remove_body(body_of(body)) ? BITSTEP_OK : no_body(sim, body); });
}

bitstep_status bitstep_add_joint(bitstep_simulation* sim, const char* joint_json, bitstep_joint* out) {
  return guarded(sim, [&] {
    if (const char* null = first_null({{joint_json, "joint_json"}, {out, "out"}})) {
      return null_argument(sim, "add_joint", null);
    }
    const bitstep::Result<bitstep::JointId> id = sim->sim.add_joint(joint_json);
    if (!id.ok()) return fail(sim, id.error());
    *out = {id->index, id->generation};
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_remove_joint(bitstep_simulation* sim, bitstep_joint joint) {
  return guarded(sim, [&] {
    if (sim->sim.remove_joint({joint.index, joint.generation})) return BITSTEP_OK;
    return fail(sim, BITSTEP_NOT_FOUND, "no joint in slot " + std::to_string(joint.index) + " of generation " +
                                            std::to_string(joint.generation));
  });
}

bitstep_status bitstep_get_body_type(bitstep_simulation* sim, bitstep_body body, bitstep_body_type* out) {
  return guarded(sim, [&] {
    if (out == nullptr) return null_argument(sim, "get_body_type", "out");
    if (!sim->sim.world().is_alive(body_of(body))) return no_body(sim, body);
    switch (sim->sim.world().body(body_of(body)).type) {
      case bitstep::BodyType::static_body: *out = BITSTEP_STATIC; break;
      case bitstep::BodyType::kinematic: *out = BITSTEP_KINEMATIC; break;
      case bitstep::BodyType::dynamic: *out = BITSTEP_DYNAMIC; break;
    }
    return BITSTEP_OK;
  });
}

uint32_t bitstep_slot_count(const bitstep_simulation* sim) {
  return sim == nullptr ? 0 : static_cast<uint32_t>(sim->sim.world().bodies().size());
}

bitstep_status bitstep_body_in_slot(bitstep_simulation* sim, uint32_t slot, bitstep_body* out) {
  return guarded(sim, [&] {
    if (out == nullptr) return null_argument(sim, "body_in_slot", "out");
    const auto& bodies = sim->sim.world().bodies();
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
    return input_status(sim, sim->sim.apply_impulse(body_of(body), vec3_of(impulse), vec3_of(world_point)),
                        no_body_message(body));
  });
}

bitstep_status bitstep_apply_force(bitstep_simulation* sim, bitstep_body body, bitstep_vec3 force,
                                   bitstep_vec3 world_point) {
  return guarded(sim, [&] {
    return input_status(sim, sim->sim.apply_force(body_of(body), vec3_of(force), vec3_of(world_point)),
                        no_body_message(body));
  });
}

bitstep_status bitstep_set_velocity(bitstep_simulation* sim, bitstep_body body, bitstep_vec3 linear,
                                    bitstep_vec3 angular) {
  return guarded(sim, [&] {
    return input_status(sim, sim->sim.set_velocity(body_of(body), vec3_of(linear), vec3_of(angular)),
                        no_body_message(body));
  });
}

bitstep_status bitstep_wake(bitstep_simulation* sim, bitstep_body body) {
  return guarded(sim, [&] { return sim->sim.wake(body_of(body)) ? BITSTEP_OK : no_body(sim, body); });
}

bitstep_status bitstep_drive(bitstep_simulation* sim, const char* car, bitstep_fixed throttle, bitstep_fixed brake,
                             bitstep_fixed steer) {
  return guarded(sim, [&] {
    if (car == nullptr) return null_argument(sim, "drive", "car");
    return input_status(sim, sim->sim.drive(car, {fixed_of(throttle), fixed_of(brake), fixed_of(steer)}),
                        std::string("no car named \"") + car + "\"");
  });
}

bitstep_status bitstep_step(bitstep_simulation* sim) {
  return guarded(sim, [&] {
    sim->sim.step();
    return BITSTEP_OK;
  });
}

uint64_t bitstep_tick(const bitstep_simulation* sim) { return sim == nullptr ? 0 : sim->sim.tick(); }

uint64_t bitstep_hash(const bitstep_simulation* sim) { return sim == nullptr ? 0 : sim->sim.hash(); }

bitstep_status bitstep_get_pose(bitstep_simulation* sim, bitstep_body body, bitstep_pose* out) {
  return guarded(sim, [&] {
    if (out == nullptr) return null_argument(sim, "get_pose", "out");
    const auto pose = sim->sim.pose(body_of(body));
    if (!pose) return no_body(sim, body);
    const bitstep::Quat& q = pose->orientation;
    *out = {vec3_to_c(pose->position), {q.w.raw(), q.x.raw(), q.y.raw(), q.z.raw()}};
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_get_render_pose(bitstep_simulation* sim, bitstep_body body, bitstep_render_pose* out) {
  return guarded(sim, [&] {
    if (out == nullptr) return null_argument(sim, "get_render_pose", "out");
    const auto pose = sim->sim.pose(body_of(body));
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
    const std::vector<uint8_t> image = sim->sim.save();
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
    if (const bitstep::Result<void> loaded = sim->sim.load({image, size}); !loaded.ok()) {
      return fail(sim, loaded.error().within("load"));
    }
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_save_state(bitstep_simulation* sim, uint8_t* buffer, size_t capacity, size_t* size) {
  return guarded(sim, [&] {
    if (size == nullptr) return null_argument(sim, "save_state", "size");
    if (buffer == nullptr && capacity > 0) return null_argument(sim, "save_state", "buffer (of capacity > 0)");
    *size = sim->sim.save_state({buffer, capacity});
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

uint64_t bitstep_checksum(const bitstep_simulation* sim) { return sim == nullptr ? 0 : sim->sim.checksum(); }

bitstep_status bitstep_load_state(bitstep_simulation* sim, const uint8_t* image, size_t size) {
  return guarded(sim, [&] {
    if (image == nullptr) return null_argument(sim, "load_state", "image");
    if (const bitstep::Result<void> loaded = sim->sim.load_state({image, size}); !loaded.ok()) {
      return fail(sim, loaded.error().within("load_state"));
    }
    return BITSTEP_OK;
  });
}

bitstep_status bitstep_cast_ray(bitstep_simulation* sim, bitstep_vec3 origin, bitstep_vec3 translation,
                                bitstep_ray_hit* out) {
  return guarded(sim, [&] {
    if (out == nullptr) return null_argument(sim, "cast_ray", "out");
    const auto hit = sim->sim.query().cast_ray(vec3_of(origin), vec3_of(translation));
    if (!hit) return fail(sim, BITSTEP_NOT_FOUND, "the ray meets nothing");
    *out = {body_to_c(hit->body), hit->shape, hit->fraction.raw(), vec3_to_c(hit->point), vec3_to_c(hit->normal)};
    return BITSTEP_OK;
  });
}

}  // extern "C"
