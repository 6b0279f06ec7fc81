#include "replay/replay.h"

#include <algorithm>
#include <climits>
#include <filesystem>
#include <map>
#include <string_view>

#include "replay/input_bounds.h"
#include "replay/limits.h"
#include "replay/scene_reader.h"
#include "replay/snapshot.h"
#include "replay/state_dump.h"
#include "replay/state_hash.h"

namespace bitstep {

using json::Kind;
using json::Node;
using namespace scene_reader;

namespace {

// The inputs' bounds, shared with the facade and the C API.
using input_bounds::max_force;
using input_bounds::max_impulse;
constexpr int max_steps = limits::max_replay_steps;

uint64_t read_hash(const Node& node) {
  const std::string& text = read_string(node);
  if (text.size() != 16) fail(node, "expected 16 hex digits, got " + json::quote(text));
  uint64_t value = 0;
  for (const char c : text) {
    int digit = -1;
    if (c >= '0' && c <= '9') digit = c - '0';
    if (c >= 'a' && c <= 'f') digit = c - 'a' + 10;
    if (digit < 0) fail(node, "expected 16 lowercase hex digits, got " + json::quote(text));
    value = (value << 4) | static_cast<uint64_t>(digit);
  }
  return value;
}

// The scene's body names -> slots (the first body of a name, as a scan in
// creation order would find), built when a name is first asked for: n inputs
// naming bodies of a scene of m cost O((n + m) log m), not O(n m).
class BodyNames {
 public:
  explicit BodyNames(const Scene& scene) : scene_(scene) {}

  const uint32_t* find(std::string_view name) {
    if (!built_) build();
    const auto found = slots_.find(name);
    return found == slots_.end() ? nullptr : &found->second;
  }

 private:
  void build() {
    for (size_t i = 0; i < scene_.bodies.size(); ++i) slots_.emplace(scene_.bodies[i].name, static_cast<uint32_t>(i));
    built_ = true;
  }

  const Scene& scene_;
  std::map<std::string_view, uint32_t> slots_;  // views of the names in scene_, which outlives this
  bool built_ = false;
};

uint32_t read_body_ref(const Node& node, BodyNames& names) {
  if (node.kind == Kind::string) {
    if (const uint32_t* slot = names.find(node.text)) return *slot;
    fail(node, "no body named " + json::quote(node.text) + " in the scene");
  }
  return static_cast<uint32_t>(read_int(node, 0, INT_MAX));
}

Vec3 read_point(const Node& node) {
  return read_vec3_within(node, -input_bounds::max_point, input_bounds::max_point, "m");
}

// A set_velocity value: components within the clamp (so that the length
// stays in range), then the length, as a scene body's velocity.
Vec3 read_speed(const Node& node, Fixed limit, const char* unit) {
  const Vec3 v = read_vec3_within(node, -limit, limit, unit);
  if (length(v) > limit) fail(node, input_bounds::faster_than(limit, unit));
  return v;
}

// A joint's motor from this step on (World::set_joint_motor): "joint" by
// name, "speed" (rad/s for a hinge, m/s for a slider) and "max_torque" (N
// m) or "max_force" (N), 0 turning it off. A joint that has no motor, or
// settings outside its type's range, leave it as it is.
void read_motor_input(ObjectReader& reader, Input& input) {
  input.joint.name = read_string(reader.require("joint"));
  input.motor_speed = read_fixed_within(reader.require("speed"), -envelope::max_linear_speed, envelope::max_linear_speed, "");
  const Node* torque = reader.find("max_torque");
  const Node* force = reader.find("max_force");
  if ((torque == nullptr) == (force == nullptr)) fail(reader.node(), "give \"max_torque\" or \"max_force\", one of them");
  input.motor_max = read_fixed_within(torque != nullptr ? *torque : *force, Fixed{}, Fixed::from_int(1000000), "");
}

Input read_input(const Node& node, const Scene& scene, BodyNames& names) {
  ObjectReader reader(node);
  Input input;
  input.source = node;
  input.step = read_int(reader.require("step"), 1, max_steps);
  using K = Input::Kind;
  static constexpr Input::Kind kinds[] = {K::impulse, K::force,         K::set_velocity,    K::spawn, K::remove,
                                          K::wake,    K::add_joint,     K::remove_joint,    K::drive, K::motor,
                                          K::move,    K::add_character, K::remove_character};
  input.kind = kinds[read_choice(reader.require("type"),
                                 {"impulse", "force", "set_velocity", "spawn", "remove", "wake", "add_joint",
                                  "remove_joint", "drive", "motor", "move", "add_character", "remove_character"})];
  const auto body = [&] { return read_body_ref(reader.require("body"), names); };
  switch (input.kind) {
    case Input::Kind::impulse:
      input.body = body();
      input.vector = read_vec3_within(reader.require("impulse"), -max_impulse, max_impulse, "N s");
      input.point = read_point(reader.require("point"));
      break;
    case Input::Kind::force:
      input.body = body();
      input.vector = read_vec3_within(reader.require("force"), -max_force, max_force, "N");
      input.point = read_point(reader.require("point"));
      break;
    case Input::Kind::set_velocity:
      input.body = body();
      if (const Node* linear = reader.find("linear")) {
        input.vector = read_speed(*linear, input_bounds::max_linear_speed, "m/s");
      }
      if (const Node* angular = reader.find("angular")) {
        input.point = read_speed(*angular, input_bounds::max_angular_speed, "rad/s");
      }
      break;
    case Input::Kind::spawn:
      input.spawned = read_scene_body(reader.require("body"), scene);
      break;
    case Input::Kind::remove:
    case Input::Kind::wake:
      input.body = body();
      break;
    case Input::Kind::add_joint:
      input.joint = read_joint_spec(reader.require("joint"), [&](const Node& ref) { return read_body_ref(ref, names); });
      break;
    case Input::Kind::remove_joint:
      input.joint.name = read_string(reader.require("joint"));
      break;
    case Input::Kind::drive: {
      const Node& car = reader.require("car");
      const std::string& name = read_string(car);
      const auto found = std::find_if(scene.cars.begin(), scene.cars.end(), [&](const SceneCar& c) { return c.name == name; });
      if (found == scene.cars.end()) fail(car, "no car named " + json::quote(name) + " in the scene");
      input.car = static_cast<uint32_t>(found - scene.cars.begin());
      if (const Node* n = reader.find("throttle")) input.controls.throttle = read_fixed_within(*n, -Fixed::one(), Fixed::one(), "");
      if (const Node* n = reader.find("brake")) input.controls.brake = read_fixed_within(*n, Fixed{}, Fixed::one(), "");
      if (const Node* n = reader.find("steer")) input.controls.steer = read_fixed_within(*n, -Fixed::one(), Fixed::one(), "");
      break;
    }
    case Input::Kind::motor: read_motor_input(reader, input); break;
    case Input::Kind::move: {
      input.added.name = read_string(reader.require("character"));  // numbered by number_characters
      // "velocity": [x, z], level, m/s; "jump": true or false.
      const Node& velocity = reader.require("velocity");
      if (velocity.kind != Kind::array || velocity.children.size() != 2) fail(velocity, "expected [x, z] in m/s");
      const Fixed fastest = 100.0_fx;
      input.moving.velocity = {read_fixed_within(velocity.children[0], -fastest, fastest, "m/s"), Fixed{},
                               read_fixed_within(velocity.children[1], -fastest, fastest, "m/s")};
      read_optional(reader, "jump", input.moving.jump);
      break;
    }
    case Input::Kind::add_character: input.added = read_character(reader.require("character")); break;
    case Input::Kind::remove_character: input.added.name = read_string(reader.require("character")); break;
  }
  reader.finish();
  return input;
}

// Numbers the characters that inputs name, as the world numbers them: the
// scene's 0..n-1, then each add_character's in input order. Names are
// unique across the scene's and add_character's; a move or a
// remove_character names one of the scene or of an add_character before it.
void number_characters(std::vector<Input>& inputs, const Scene& scene) {
  std::map<std::string_view, uint32_t> numbers;  // views of names in `scene` and `inputs`, which outlive it
  for (size_t k = 0; k < scene.characters.size(); ++k)
    numbers.emplace(scene.characters[k].name, static_cast<uint32_t>(k));
  auto next = static_cast<uint32_t>(scene.characters.size());
  for (Input& input : inputs) {
    const std::string& name = input.added.name;
    if (input.kind == Input::Kind::add_character) {
      input.character = next++;
      if (!numbers.emplace(name, input.character).second) {
        fail(input.source.path + ".character.name", "duplicate character name " + json::quote(name));
      }
    } else if (input.kind == Input::Kind::move || input.kind == Input::Kind::remove_character) {
      const auto found = numbers.find(name);
      if (found == numbers.end()) {
        fail(input.source.path + ".character",
             "no character named " + json::quote(name) + " in the scene or added by an add_character before it");
      }
      input.character = found->second;
    }
  }
}

// Numbers the joints that inputs name, as InputRun::joints does: the
// scene's 0..n-1, then each add_joint in input order. Names are unique
// across the scene's joints and add_joint's; a remove_joint names one of
// the scene or of an add_joint before it.
void number_joints(std::vector<Input>& inputs, const Scene& scene) {
  std::map<std::string_view, uint32_t> numbers;  // views of names in `scene` and `inputs`, which outlive it
  for (size_t k = 0; k < scene.joints.size(); ++k) {
    if (!scene.joints[k].name.empty()) numbers.emplace(scene.joints[k].name, static_cast<uint32_t>(k));
  }
  auto next = static_cast<uint32_t>(scene.joints.size());
  for (Input& input : inputs) {
    const std::string& name = input.joint.name;
    if (input.kind == Input::Kind::add_joint) {
      input.joint_number = next++;
      if (!name.empty() && !numbers.emplace(name, input.joint_number).second) {
        fail(input.source.path + ".joint.name", "duplicate joint name " + json::quote(name));
      }
    } else if (input.kind == Input::Kind::remove_joint || input.kind == Input::Kind::motor) {
      const auto found = numbers.find(name);
      if (found == numbers.end()) {
        fail(input.source.path + ".joint",
             "no joint named " + json::quote(name) + " in the scene or added by an add_joint before it");
      }
      input.joint_number = found->second;
    }
  }
}

std::vector<Input> read_inputs(const Node& node, const Scene& scene) {
  if (node.kind != Kind::array) fail(node, std::string("expected an array of inputs, got ") + json::describe(node.kind));
  if (node.children.size() > static_cast<size_t>(limits::max_replay_inputs)) {
    fail(node, std::to_string(node.children.size()) + " inputs: more than the limit of " +
                   std::to_string(limits::max_replay_inputs));
  }
  std::vector<Input> inputs;
  BodyNames names(scene);
  for (const Node& input : node.children) inputs.push_back(read_input(input, scene, names));
  // Step order; within a step, file order.
  std::stable_sort(inputs.begin(), inputs.end(), [](const Input& a, const Input& b) { return a.step < b.step; });
  number_joints(inputs, scene);
  number_characters(inputs, scene);
  return inputs;
}

// The file's text read by `read` (scene_reader::read_json); never throws.
template <class Read>
auto parse_file(const std::string& path, Read read) -> Result<decltype(read(std::declval<const Node&>()))> {
  Result<std::string> text = read_text_file(path);
  if (!text.ok()) return text.error();
  return read_json(text.value(), path, read);
}

// A replay's scene (`node`, its "scene"): inline, or a file relative to
// the replay's folder. An error inside an inline scene names the replay and
// "$.scene..."; one inside a scene file names that file; a scene file that
// cannot be read is named at "$.scene" of the replay that needs it.
Result<Scene> read_replay_scene(const Node& node, const std::string& path, Replay& replay) {
  if (node.kind == Kind::object) {
    replay.inline_scene = json::write(node);
    Result<Scene> loaded = parse_scene(replay.inline_scene, "");
    if (loaded.ok()) return loaded;
    Error error = loaded.error();
    if (error.place.rfind('$', 0) == 0) error.place = "$.scene" + error.place.substr(1);
    return error.within(path);
  }
  replay.scene_file = read_string(node);
  const std::string file = (std::filesystem::path(path).parent_path() / replay.scene_file).string();
  Result<std::string> text = read_text_file(file);
  if (!text.ok()) return text.error().within(node.path).within(path);
  return parse_scene(text.value(), file);
}

}  // namespace

Result<std::vector<Input>> parse_inputs(std::string_view json_array, const Scene& scene, const std::string& name) {
  return read_json(json_array, name, [&](const Node& root) { return read_inputs(root, scene); });
}

Result<Replay> load_replay_file(const std::string& path, bool require_hashes) {
  Result<std::string> text = read_text_file(path);
  if (!text.ok()) return text.error();
  return parse_replay(text.value(), path, require_hashes);
}

Result<Replay> parse_replay(std::string_view json_text, const std::string& path, bool require_hashes) {
  // The scene is loaded in the middle of reading the replay; its error, if
  // any, is the one reported, as its own file names it.
  std::optional<Error> scene_error;
  auto read = [&](const Node& root) {
    ObjectReader reader(root);
    const Node& format = reader.require("format");
    if (read_string(format) != "bitstep-replay") fail(format, "expected \"bitstep-replay\", got " + json::quote(format.text));
    const Node& version = reader.require("version");
    const int number = read_int(version, INT_MIN, INT_MAX);
    if (number != 1) fail(version, "unsupported version " + std::to_string(number) + " (this build reads version 1)");
    if (const Node* engine = reader.find("engine")) read_string(*engine);
    if (const Node* description = reader.find("description")) read_string(*description);
    Replay replay;
    // The scene: a file relative to the replay's folder, or inline.
    const Node& scene = reader.require("scene");
    Result<Scene> loaded = read_replay_scene(scene, path, replay);
    if (!loaded.ok()) {
      scene_error = loaded.error();
      return replay;
    }
    replay.scene = std::move(loaded).value();
    if (const Node* settings = reader.find("settings")) {
      read_settings_onto(*settings, replay.scene.settings);
      replay.settings_override = json::write(*settings);
    }
    replay.scene_hash = read_hash(reader.require("scene_hash"));
    replay.steps = read_int(reader.require("steps"), 0, max_steps);
    // The chain's length before the inputs: a replay claiming more steps
    // than it has hashes is refused before anything else is read or run.
    const Node* hashes = reader.find("hashes");
    if (hashes != nullptr) {
      if (hashes->kind != Kind::array) fail(*hashes, std::string("expected an array of hashes, got ") + json::describe(hashes->kind));
      if (static_cast<int64_t>(hashes->children.size()) != replay.steps) {
        fail(*hashes, std::to_string(hashes->children.size()) + " hashes for " + std::to_string(replay.steps) + " steps");
      }
    } else if (require_hashes) {
      fail(root, "missing key \"hashes\" (the hash chain to verify against)");
    }
    if (const Node* inputs = reader.find("inputs")) replay.inputs = read_inputs(*inputs, replay.scene);
    if (!replay.inputs.empty() && replay.inputs.back().step > replay.steps) {
      fail(replay.inputs.back().source.path + ".step", "after the last step (" + std::to_string(replay.steps) + ")");
    }
    if (hashes != nullptr) {
      replay.hashes.reserve(hashes->children.size());
      for (const Node& h : hashes->children) replay.hashes.push_back(read_hash(h));
    }
    reader.finish();
    return replay;
  };
  Result<Replay> result = read_json(json_text, path, read);
  if (scene_error) return *scene_error;
  return result;
}

Result<InputsFile> load_inputs_file(const std::string& path, const Scene& scene) {
  return parse_file(path, [&](const Node& root) {
    ObjectReader reader(root);
    InputsFile file;
    file.inputs = read_inputs(reader.require("inputs"), scene);
    // A replay may serve as the inputs file (to record it again): its
    // settings override is kept, its other keys are known and ignored.
    if (const Node* format = reader.find("format"); format != nullptr && format->text == "bitstep-replay") {
      for (const char* key : {"version", "engine", "description", "scene", "scene_hash", "steps", "hashes"}) {
        reader.find(key);
      }
      if (const Node* settings = reader.find("settings")) {
        Settings checked = scene.settings;
        read_settings_onto(*settings, checked);
        file.settings_override = json::write(*settings);
      }
    }
    reader.finish();
    return file;
  });
}

Result<void> build_world(const Scene& scene, World& world) {
  std::vector<BodyId> ids;
  ids.reserve(scene.bodies.size());
  for (size_t i = 0; i < scene.bodies.size(); ++i) {
    const Result<BodyId> created = world.create_body(scene.bodies[i].def);
    if (!created.ok()) return created.error().within("body " + std::to_string(i));
    ids.push_back(created.value());
  }
  for (size_t k = 0; k < scene.cars.size(); ++k) {
    CarDef def = scene.cars[k].def;
    def.chassis = scene.cars[k].chassis < ids.size() ? ids[scene.cars[k].chassis] : BodyId{};
    if (const Result<CarId> created = world.create_car(def); !created.ok()) {
      return created.error().within("car " + std::to_string(k) + " (" + json::quote(scene.cars[k].name) + ")");
    }
  }
  for (size_t k = 0; k < scene.characters.size(); ++k) {
    if (const Result<CharacterId> created = world.create_character(scene.characters[k].def); !created.ok()) {
      return created.error().within("character " + std::to_string(k) + " (" + json::quote(scene.characters[k].name) +
                                    ")");
    }
  }
  for (size_t k = 0; k < scene.joints.size(); ++k) {
    const SceneJoint& joint = scene.joints[k];
    JointDef def = joint.def;
    // A scene made in code may name a body it does not have: the world refuses the handle.
    def.body_a = joint.body_a < ids.size() ? ids[joint.body_a] : BodyId{};
    def.body_b = joint.body_b < ids.size() ? ids[joint.body_b] : BodyId{};
    const Result<JointId> created = world.create_joint(def);
    if (!created.ok()) {
      return created.error().within("joint " + std::to_string(k) + (joint.name.empty() ? "" : " (" + json::quote(joint.name) + ")"));
    }
  }
  return {};
}

namespace {

// The body in the slot now, or a handle no body has.
BodyId occupant(const World& world, uint32_t slot) {
  const bool occupied = slot < world.bodies().size() && world.bodies()[slot].alive;
  return {slot, occupied ? world.bodies()[slot].generation : 0};
}

constexpr JointId no_joint{UINT32_MAX, 0};

void add_joint(World& world, const Input& input, InputRun& run) {
  const JointSpec& spec = input.joint;
  const BodyId a = occupant(world, spec.body_a), b = occupant(world, spec.body_b);
  const auto frame = [&](BodyId id) { return world.is_alive(id) ? world.body(id).pose : Pose{}; };
  JointDef def = joint_in_world(spec, frame(a), frame(b));
  def.body_a = a;
  def.body_b = b;
  const Result<JointId> created = world.create_joint(def);
  if (run.joints.size() <= input.joint_number) run.joints.resize(input.joint_number + size_t{1}, no_joint);
  run.joints[input.joint_number] = created.ok() ? created.value() : no_joint;
}

}  // namespace

InputRun::InputRun(const World& world_at_step_0) {
  const std::vector<Joint>& slots = world_at_step_0.joints();
  for (uint32_t k = 0; k < slots.size(); ++k) joints.push_back(slots[k].alive ? JointId{k, slots[k].generation} : no_joint);
}

void apply_inputs(World& world, const std::vector<Input>& inputs, int64_t step, InputRun& run) {
  for (; run.next < inputs.size() && inputs[run.next].step <= step; ++run.next) {
    const Input& input = inputs[run.next];
    if (input.step < step) continue;
    const BodyId id = occupant(world, input.body);
    switch (input.kind) {
      case Input::Kind::impulse: world.apply_impulse(id, input.vector, input.point); break;
      case Input::Kind::force: world.apply_force(id, input.vector, input.point); break;
      case Input::Kind::set_velocity: world.set_velocity(id, input.vector, input.point); break;
      case Input::Kind::spawn: world.create_body(input.spawned.def); break;  // checked against the envelope when read
      case Input::Kind::remove: world.remove_body(id); break;
      case Input::Kind::wake: world.wake(id); break;
      case Input::Kind::add_joint: add_joint(world, input, run); break;
      case Input::Kind::remove_joint:
        if (input.joint_number < run.joints.size()) world.remove_joint(run.joints[input.joint_number]);
        break;
      case Input::Kind::drive: world.set_car_controls({input.car}, input.controls); break;
      case Input::Kind::move: world.set_character_controls({input.character}, input.moving); break;
      // Checked when read (read_character): the world takes it, as the
      // character numbered input.character.
      case Input::Kind::add_character: world.create_character(input.added.def); break;
      case Input::Kind::remove_character: world.remove_character({input.character}); break;
      case Input::Kind::motor:
        if (input.joint_number < run.joints.size()) {
          world.set_joint_motor(run.joints[input.joint_number], input.motor_speed, input.motor_max);
        }
        break;
    }
  }
}

void run_inputs(World& world, const std::vector<Input>& inputs, int64_t steps, std::vector<uint64_t>& hashes,
                int64_t dump_step, std::string* dump, const StepWatch& watch) {
  if (dump != nullptr && dump_step == 0) *dump = dump_state(world);
  if (watch) watch(world);
  InputRun run(world);
  for (int64_t step = 1; step <= steps; ++step) {
    apply_inputs(world, inputs, step, run);
    world.step();
    hashes.push_back(state_hash(world));
    if (dump != nullptr && step == dump_step) *dump = dump_state(world);
    if (watch) watch(world);
  }
}

Verification verify_replay(const Replay& replay, int64_t dump_step, std::string* dump, Executor* executor,
                           const StepWatch& watch) {
  Verification v;
  World world(replay.scene.settings);
  world.set_executor(executor);
  v.built = build_world(replay.scene, world);
  if (!v.built.ok()) return v;
  v.scene_hash = state_hash(world);
  v.scene_matches = v.scene_hash == replay.scene_hash;
  if (!v.scene_matches) return v;
  run_inputs(world, replay.inputs, replay.steps, v.hashes, dump_step, dump, watch);
  v.divergent_step = first_divergent_step(replay.hashes, v.hashes);
  const std::vector<uint8_t> image = snapshot(world);
  for (size_t i = 0; i < 8; ++i) v.snapshot_checksum |= static_cast<uint64_t>(image[image.size() - 8 + i]) << (8 * i);
  return v;
}

std::string replay_json(const Replay& replay, const std::string& engine_version) {
  std::string out = "{\n  \"format\": \"bitstep-replay\",\n  \"version\": 1,\n";
  out += "  \"engine\": " + json::write(Node{Kind::string, false, engine_version, {}, {}, {}}) + ",\n";
  out += "  \"scene\": ";
  out += replay.inline_scene.empty() ? json::write(Node{Kind::string, false, replay.scene_file, {}, {}, {}})
                                     : replay.inline_scene;
  out += ",\n";
  if (!replay.settings_override.empty()) out += "  \"settings\": " + replay.settings_override + ",\n";
  out += "  \"scene_hash\": \"" + hex16(replay.scene_hash) + "\",\n";
  out += "  \"steps\": " + std::to_string(replay.steps) + ",\n";
  out += "  \"inputs\": [";
  for (size_t i = 0; i < replay.inputs.size(); ++i) {
    out += (i == 0 ? "\n    " : ",\n    ") + json::write(replay.inputs[i].source);
  }
  out += replay.inputs.empty() ? "],\n" : "\n  ],\n";
  out += "  \"hashes\": [";
  for (size_t i = 0; i < replay.hashes.size(); ++i) {
    out += i == 0 ? "\n    " : (i % 6 == 0 ? ",\n    " : ", ");
    out += "\"" + hex16(replay.hashes[i]) + "\"";
  }
  out += replay.hashes.empty() ? "]\n}\n" : "\n  ]\n}\n";
  return out;
}

int64_t first_divergent_step(const std::vector<uint64_t>& recorded, const std::vector<uint64_t>& replayed) {
  const size_t common = std::min(recorded.size(), replayed.size());
  for (size_t i = 0; i < common; ++i) {
    if (recorded[i] != replayed[i]) return static_cast<int64_t>(i) + 1;
  }
  return recorded.size() == replayed.size() ? 0 : static_cast<int64_t>(common) + 1;
}

std::string hex16(uint64_t value) {
  static constexpr char digits[] = "0123456789abcdef";
  std::string out(16, '0');
  for (int i = 15; i >= 0; --i, value >>= 4) out[static_cast<size_t>(i)] = digits[value & 15];
  return out;
}

}  // namespace bitstep
