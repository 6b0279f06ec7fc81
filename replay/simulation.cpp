#include "replay/simulation.h"

#include <initializer_list>
#include <utility>

#include "replay/input_bounds.h"
#include "replay/replay.h"
#include "replay/scene_reader.h"
#include "replay/snapshot.h"
#include "replay/state_hash.h"

namespace bitstep {

// A simulation of a read scene, or the scene's error; `name` its file.
Result<Simulation> Simulation::built(Result<Scene> read, const std::string& name) {
  if (!read.ok()) return read.error();
  Scene& scene = read.value();
  World world(scene.settings);
  if (Result<void> made = build_world(scene, world); !made.ok()) return made.error().within(name);
  return Simulation(std::move(scene), std::move(world));
}

Result<Simulation> Simulation::from_file(const std::string& path) { return built(load_scene_file(path), path); }

Result<Simulation> Simulation::from_text(std::string_view scene_json, const std::string& name) {
  return built(parse_scene(scene_json, name), name);
}

// build_world made scene body i slot i and scene car k car k.
Simulation::Simulation(Scene scene, World world) : scene_(std::move(scene)), world_(std::move(world)) {
  for (uint32_t i = 0; i < scene_.bodies.size(); ++i) {
    remember({i, world_.bodies()[i].generation}, scene_.bodies[i].def, scene_.bodies[i].name);
  }
  for (uint32_t k = 0; k < scene_.cars.size(); ++k) cars_.emplace(scene_.cars[k].name, k);
  for (uint32_t k = 0; k < scene_.characters.size(); ++k) characters_.emplace(scene_.characters[k].name, k);
}

// The world moved the body's frame onto its centre of mass and its shapes
// the other way: the first shape's shift is the centre in the defined frame.
void Simulation::remember(BodyId id, const BodyDef& def, const std::string& name) {
  const Body& body = world_.body(id);
  const Vec3 centre = def.shapes.empty() ? Vec3{} : def.shapes[0].local.position - body.shapes[0].local.position;
  defined_[{id.index, id.generation}] = {centre, name};
  if (!name.empty()) names_[name] = id;
}

bool Simulation::valid(BodyId id) const { return world_.is_alive(id); }

std::optional<BodyId> Simulation::find_body(std::string_view name) const {
  const auto found = names_.find(name);
  if (found == names_.end() || !valid(found->second)) return std::nullopt;
  return found->second;
}

Result<BodyId> Simulation::add_body(std::string_view body_json) {
  Result<SceneBody> read = scene_reader::read_json(body_json, "add_body", [&](const json::Node& node) { return read_scene_body(node, scene_); });
  if (!read.ok()) return read.error();
  const SceneBody& body = read.value();
  if (!body.name.empty() && find_body(body.name)) {
    return Error{"add_body: $.name", json::quote(body.name) + " is already taken"};
  }
  const Result<BodyId> created = world_.create_body(body.def);
  if (!created.ok()) return Error{"$." + created.error().place, created.error().reason}.within("add_body");
  remember(created.value(), body.def, body.name);
  return created.value();
}

Result<BodyId> Simulation::create_body(const BodyDef& def, const std::string& name) {
  if (!name.empty() && find_body(name)) return Error{"create_body: name", json::quote(name) + " is already taken"};
  const Result<BodyId> created = world_.create_body(def);
  if (!created.ok()) return created.error().within("create_body");
  remember(created.value(), def, name);
  return created.value();
}

bool Simulation::remove_body(BodyId id) { return valid(id) && world_.remove_body(id); }

Result<JointId> Simulation::add_joint(std::string_view joint_json) {
  std::vector<BodyId> bodies;  // the spec's body numbers index this
  const BodyResolver resolve = [&](const json::Node& node) {
    const std::optional<BodyId> id = find_body(scene_reader::read_string(node));
    if (!id) scene_reader::fail(node, "no body named " + json::quote(node.text));
    bodies.push_back(*id);
    return static_cast<uint32_t>(bodies.size() - 1);
  };
  Result<JointSpec> spec = scene_reader::read_json(joint_json, "add_joint", [&](const json::Node& node) { return read_joint_spec(node, resolve); });
  if (!spec.ok()) return spec.error();
  const BodyId a = bodies[spec->body_a], b = bodies[spec->body_b];
  JointDef def = joint_in_world(spec.value(), *pose(a), *pose(b));
  def.body_a = a;
  def.body_b = b;
  const Result<JointId> created = world_.create_joint(def);
  if (!created.ok()) return created.error().within("add_joint");
  return created.value();
}

Result<JointId> Simulation::create_joint(const JointDef& def) {
  const Result<JointId> created = world_.create_joint(def);
  if (!created.ok()) return created.error().within("create_joint");
  return created.value();
}

bool Simulation::remove_joint(JointId id) { return world_.is_alive(id) && world_.remove_joint(id); }

namespace {

InputResult not_found() { return {InputResult::Status::not_found, {}}; }

// Applied by `apply` unless a check gave a reason, then refused with it
// ("<call>: <reason>") and `apply` not run.
template <typename Apply>
InputResult applied_unless(std::initializer_list<Result<void>> checks, const char* call, Apply&& apply) {
  for (const Result<void>& check : checks) {
    if (!check.ok()) return {InputResult::Status::refused, check.error().within(call)};
  }
  apply();
  return {};
}

// An input the body's type ignores, refused rather than silently dropped:
// impulses and forces move dynamic bodies alone, a velocity is set on a
// dynamic or kinematic body, never a static one.
InputResult unmoved(const Body& body, const char* call, const char* moves) {
  const char* type = body.type == BodyType::static_body ? "static" : "kinematic";
  return {InputResult::Status::refused, Error{std::string(call), std::string("the body is ") + type + ": " + moves}};
}

}  // namespace

InputResult Simulation::apply_impulse(BodyId id, Vec3 impulse, Vec3 world_point) {
  if (!valid(id)) return not_found();
  if (world_.body(id).type != BodyType::dynamic) {
    return unmoved(world_.body(id), "apply_impulse", "impulses move dynamic bodies");
  }
  using namespace input_bounds;
  return applied_unless(
      {check_vec3(impulse, max_impulse, "impulse", "N s"), check_vec3(world_point, max_point, "world_point", "m")},
      "apply_impulse", [&] { world_.apply_impulse(id, impulse, world_point); });
}

InputResult Simulation::apply_force(BodyId id, Vec3 force, Vec3 world_point) {
  if (!valid(id)) return not_found();
  if (world_.body(id).type != BodyType::dynamic) {
    return unmoved(world_.body(id), "apply_force", "forces move dynamic bodies");
  }
  using namespace input_bounds;
  return applied_unless(
      {check_vec3(force, max_force, "force", "N"), check_vec3(world_point, max_point, "world_point", "m")},
      "apply_force", [&] { world_.apply_force(id, force, world_point); });
}

InputResult Simulation::set_velocity(BodyId id, Vec3 linear, Vec3 angular) {
  if (!valid(id)) return not_found();
  if (world_.body(id).type == BodyType::static_body) {
    return unmoved(world_.body(id), "set_velocity", "a static body never moves");
  }
  using namespace input_bounds;
  return applied_unless({check_speed(linear, max_linear_speed, "linear", "m/s"),
                         check_speed(angular, max_angular_speed, "angular", "rad/s")},
                        "set_velocity", [&] { world_.set_velocity(id, linear, angular); });
}

bool Simulation::wake(BodyId id) {
  if (!valid(id)) return false;
  world_.wake(id);
  return true;
}

InputResult Simulation::drive(std::string_view car_name, CarControls controls) {
  const auto found = cars_.find(car_name);
  if (found == cars_.end() || found->second >= world_.cars().size() || !world_.cars()[found->second].alive) {
    return not_found();
  }
  using input_bounds::check_within;
  return applied_unless({check_within(controls.throttle, -Fixed::one(), Fixed::one(), "throttle", ""),
                         check_within(controls.brake, Fixed{}, Fixed::one(), "brake", ""),
                         check_within(controls.steer, -Fixed::one(), Fixed::one(), "steer", "")},
                        "drive", [&] { world_.set_car_controls({found->second}, controls); });
}

InputResult Simulation::move(std::string_view character_name, CharacterControls controls) {
  const Character* c = character(character_name);
  if (c == nullptr) return not_found();
  using input_bounds::check_within;
  const Fixed fastest = 100.0_fx;
  const auto index = static_cast<uint32_t>(c - world_.characters().data());
  return applied_unless({check_within(controls.velocity.x, -fastest, fastest, "velocity.x", "m/s"),
                         check_within(controls.velocity.z, -fastest, fastest, "velocity.z", "m/s")},
                        "move", [&] { world_.set_character_controls({index}, controls); });
}

const Character* Simulation::character(std::string_view name) const {
  const auto found = characters_.find(name);
  if (found == characters_.end() || found->second >= world_.characters().size()) return nullptr;
  const Character& c = world_.characters()[found->second];
  return c.alive ? &c : nullptr;
}

Result<void> Simulation::add_character(std::string_view character_json) {
  Result<SceneCharacter> read = scene_reader::read_json(character_json, "add_character", read_character);
  if (!read.ok()) return read.error();
  if (character(read->name) != nullptr) {
    return Error{"add_character: name", "a live character is named " + json::quote(read->name)};
  }
  const Result<CharacterId> created = world_.create_character(read->def);
  if (!created.ok()) return created.error().within("add_character");
  characters_.insert_or_assign(read->name, created->index);
  return {};
}

bool Simulation::remove_character(std::string_view name) {
  if (character(name) == nullptr) return false;
  world_.remove_character({characters_.find(name)->second});
  return true;
}

void Simulation::step() { world_.step(); }

// The frame's origin sits at -centre from the centre of mass, in the body
// frame: position = com - R centre (exactly the defined position at rest,
// as the world placed the centre at position + R centre).
std::optional<Pose> Simulation::pose(BodyId id) const {
  if (!valid(id)) return std::nullopt;
  const Body& body = world_.body(id);
  const Vec3 centre = frame_offset(id);
  return Pose{body.pose.position - rotate(body.pose.orientation, centre), body.pose.orientation};
}

std::string_view Simulation::name(BodyId id) const {
  const auto found = defined_.find({id.index, id.generation});
  return found == defined_.end() || !valid(id) ? std::string_view{} : std::string_view{found->second.name};
}

Vec3 Simulation::frame_offset(BodyId id) const {
  const auto found = defined_.find({id.index, id.generation});
  return found == defined_.end() ? Vec3{} : found->second.frame_offset;
}

std::vector<uint8_t> Simulation::save() const { return snapshot(world_); }

// The world is replaced by the image's; whether it lists events (not
// state, a choice of the game's) stays as it was.
Result<void> Simulation::load(std::span<const uint8_t> image) {
  const bool events = world_.events_on();
  Result<void> loaded = restore(image, world_);
  world_.set_events(events);
  return loaded;
}

uint64_t Simulation::hash() const { return state_hash(world_); }

uint64_t Simulation::checksum() const { return state_checksum(world_); }

size_t Simulation::save_state(std::span<uint8_t> buffer) { return states_.save(world_, buffer); }

Result<void> Simulation::load_state(std::span<const uint8_t> image) {
  return states_.restore(image, world_);
}

}  // namespace bitstep
