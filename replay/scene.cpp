#include "replay/scene.h"

#include <climits>
#include <filesystem>
#include <fstream>
#include <set>

#include "core/envelope.h"
#include "replay/generators.h"
#include "replay/json_tree.h"
#include "replay/scene_reader.h"

namespace bitstep {

using json::Kind;
using json::Node;
using namespace scene_reader;

namespace {

constexpr int max_bodies = 1000000;  // in one scene, all generators included
constexpr std::uintmax_t max_file_bytes = std::uintmax_t{1} << 30;
constexpr Fixed max_distance = 1000.0_fx;  // m: a generator's gap, spacing, spread
constexpr Fixed max_speed = 500.0_fx;      // m/s, as check_envelope
constexpr Fixed max_spin = 100.0_fx;       // rad/s, as check_envelope

MaterialTable read_materials(const Node& node) {
  if (node.kind != Kind::object) fail(node, std::string("expected an object of named materials, got ") + json::describe(node.kind));
  MaterialTable table;
  // The keys of a JSON object are unique (json::parse refuses duplicates).
  for (const Node& entry : node.children) table.add(entry.key, read_material_fields(entry));
  return table;
}

Shape read_shape(const Node& node) {
  ObjectReader reader(node);
  Shape shape;
  static constexpr ShapeType types[] = {ShapeType::box, ShapeType::sphere, ShapeType::capsule, ShapeType::plane};
  shape.type = types[read_choice(reader.require("type"), {"box", "sphere", "capsule", "plane"})];
  switch (shape.type) {
    case ShapeType::box: shape.half_extents = read_vec3(reader.require("half_extents")); break;
    case ShapeType::sphere: shape.radius = read_fixed(reader.require("radius")); break;
    case ShapeType::capsule:
      shape.radius = read_fixed(reader.require("radius"));
      shape.half_height = read_fixed(reader.require("half_height"));
      break;
    case ShapeType::plane: break;
  }
  read_optional(reader, "position", shape.local.position);
  if (const Node* orientation = reader.find("orientation")) shape.local.orientation = read_orientation(*orientation);
  reader.finish();
  return shape;
}

// "field" or "shapes[2].field" of an envelope error, relative to its body.
std::string envelope_field(const EnvelopeError& error) {
  std::string field = error.field != nullptr ? error.field : "";
  if (error.shape_index >= 0) field = "shapes[" + std::to_string(error.shape_index) + "]." + field;
  return field;
}

// check_envelope refuses |v| > 500 m/s and |omega| > 100 rad/s; a component
// beyond that fails it anyway, and refusing it first keeps the length that
// check_envelope computes inside Q32.32 (a checked build aborts on saturation).
void check_speed_components(const Node& body_node, const BodyDef& def) {
  auto beyond = [](Vec3 v, Fixed limit) { return abs(v.x) > limit || abs(v.y) > limit || abs(v.z) > limit; };
  if (beyond(def.linear_velocity, max_speed)) fail(body_node.path + ".velocity", "faster than 500 m/s");
  if (beyond(def.angular_velocity, max_spin)) fail(body_node.path + ".angular_velocity", "faster than 100 rad/s");
}

// A body's (or a generator's bodies') "density" and "mass": at most one.
struct MassKeys {
  const Node* density;
  const Node* mass;
};
MassKeys find_density_or_mass(ObjectReader& reader) {
  const MassKeys keys{reader.find("density"), reader.find("mass")};
  if (keys.density != nullptr && keys.mass != nullptr) fail(*keys.mass, "give \"mass\" or \"density\", not both");
  return keys;
}

SceneBody read_body(const Node& node, const MaterialTable& materials) {
  ObjectReader reader(node);
  SceneBody body;
  BodyDef& def = body.def;
  if (const Node* name = reader.find("name")) body.name = read_string(*name);
  if (const Node* type = reader.find("type")) {
    static constexpr BodyType types[] = {BodyType::static_body, BodyType::kinematic, BodyType::dynamic};
    def.type = types[read_choice(*type, {"static", "kinematic", "dynamic"})];
  }
  read_optional(reader, "position", def.pose.position);
  if (const Node* orientation = reader.find("orientation")) def.pose.orientation = read_orientation(*orientation);
  read_optional(reader, "velocity", def.linear_velocity);
  read_optional(reader, "angular_velocity", def.angular_velocity);
  const MassKeys keys = find_density_or_mass(reader);
  if (keys.density != nullptr) def.density = read_fixed(*keys.density, Bound::positive);
  if (keys.mass != nullptr) def.mass = read_fixed(*keys.mass, Bound::positive);
  if (const Node* material = reader.find("material")) def.material = read_material(*material, materials);
  read_optional(reader, "linear_damping", def.linear_damping, Bound::non_negative);
  read_optional(reader, "angular_damping", def.angular_damping, Bound::non_negative);
  read_optional(reader, "asleep", def.asleep);
  const Node& shapes = reader.require("shapes");
  if (shapes.kind != Kind::array) fail(shapes, std::string("expected an array of shapes, got ") + json::describe(shapes.kind));
  for (const Node& shape : shapes.children) def.shapes.push_back(read_shape(shape));
  reader.finish();

  check_speed_components(node, def);
  const EnvelopeError envelope = check_envelope(def);
  if (!envelope.ok()) fail(node.path + "." + envelope_field(envelope), envelope.reason);
  return body;
}

// --- generators: their JSON keys are the fields of the *Params structs ----

// Generator inputs are bounded before any arithmetic, so that no sum or
// product inside a generator leaves Q32.32 (a checked build would abort):
// sizes as the envelope's, places within +-16 km, distances up to 1 km.
// A structure too big for the world is then refused by check_envelope.

void read_size(ObjectReader& reader, std::string_view key, Vec3& field) {
  read_optional_within(reader, key, field, envelope::min_size, envelope::max_size, "m");
}
void read_place(ObjectReader& reader, std::string_view key, Vec3& field) {
  read_optional_within(reader, key, field, -envelope::max_position, envelope::max_position, "m");
}

// Keys every generator has: name, material, density or mass, asleep. A mass
// is per body and bounded here as the envelope bounds it, so that the error
// names the generator's key.
void read_common(ObjectReader& reader, const MaterialTable& materials, std::string& name, Substance& substance) {
  if (const Node* n = reader.find("name")) name = read_string(*n);
  if (const Node* material = reader.find("material")) substance.material = read_material(*material, materials);
  const MassKeys keys = find_density_or_mass(reader);
  if (keys.density != nullptr) substance.density = read_fixed(*keys.density, Bound::positive);
  if (keys.mass != nullptr) substance.mass = read_fixed_within(*keys.mass, envelope::min_mass, envelope::max_mass, "kg");
  read_optional(reader, "asleep", substance.asleep);
}

// An overlap must leave boxes with positive height: below the half height.
void check_overlap(ObjectReader& reader, Fixed overlap, Fixed half_height) {
  if (overlap >= half_height) fail(*reader.find("overlap"), "must be less than the boxes' half height");
}

std::vector<SceneBody> read_stack(ObjectReader& reader, const MaterialTable& materials) {
  StackParams p;
  read_common(reader, materials, p.name, p.substance);
  read_optional(reader, "count", p.count, 1, 10000);
  read_size(reader, "half_extents", p.half_extents);
  read_place(reader, "position", p.position);
  read_optional_within(reader, "overlap", p.overlap, Fixed{}, envelope::max_size, "m");
  if (const Node* direction = reader.find("direction")) {
    static constexpr StackDirection directions[] = {StackDirection::plus_x, StackDirection::minus_x,
                                                    StackDirection::plus_y, StackDirection::minus_y,
                                                    StackDirection::plus_z, StackDirection::minus_z};
    p.direction = directions[read_choice(*direction, {"+x", "-x", "+y", "-y", "+z", "-z"})];
  }
  check_overlap(reader, p.overlap, stack_half_height(p));
  return generate_stack(p);
}

std::vector<SceneBody> read_pyramid(ObjectReader& reader, const MaterialTable& materials) {
  PyramidParams p;
  read_common(reader, materials, p.name, p.substance);
  read_optional(reader, "base", p.base, 1, 1000);
  read_size(reader, "half_extents", p.half_extents);
  read_place(reader, "position", p.position);
  read_optional_within(reader, "gap", p.gap, Fixed{}, max_distance, "m");
  read_optional_within(reader, "overlap", p.overlap, Fixed{}, envelope::max_size, "m");
  check_overlap(reader, p.overlap, p.half_extents.y);
  return generate_pyramid(p);
}

std::vector<SceneBody> read_wall(ObjectReader& reader, const MaterialTable& materials) {
  WallParams p;
  read_common(reader, materials, p.name, p.substance);
  read_optional(reader, "base", p.base, 1, 1000);
  read_optional(reader, "rows", p.rows, 1, 1000);
  if (const Node* shape = reader.find("shape")) {
    p.shape = read_choice(*shape, {"triangle", "rectangle"}) == 0 ? WallShape::triangle : WallShape::rectangle;
  }
  if (p.shape == WallShape::triangle && p.rows > p.base) fail(*reader.find("rows"), "a triangle wall has at most base rows");
  read_size(reader, "half_extents", p.half_extents);
  read_place(reader, "position", p.position);
  read_optional_within(reader, "gap", p.gap, Fixed{}, max_distance, "m");
  read_optional_within(reader, "overlap", p.overlap, Fixed{}, envelope::max_size, "m");
  check_overlap(reader, p.overlap, p.half_extents.y);
  return generate_wall(p);
}

std::vector<SceneBody> read_jenga(ObjectReader& reader, const MaterialTable& materials) {
  JengaParams p;
  read_common(reader, materials, p.name, p.substance);
  read_optional(reader, "levels", p.levels, 1, 10000);
  read_size(reader, "half_extents", p.half_extents);
  read_place(reader, "position", p.position);
  read_optional_within(reader, "overlap", p.overlap, Fixed{}, envelope::max_size, "m");
  check_overlap(reader, p.overlap, p.half_extents.y);
  return generate_jenga(p);
}

std::vector<SceneBody> read_dominoes(ObjectReader& reader, const MaterialTable& materials) {
  DominoParams p;
  read_common(reader, materials, p.name, p.substance);
  read_optional(reader, "count", p.count, 1, 100000);
  read_size(reader, "half_extents", p.half_extents);
  read_optional_within(reader, "spacing", p.spacing, envelope::min_size, max_distance, "m");
  read_place(reader, "position", p.position);
  if (const Node* direction = reader.find("direction")) {
    static constexpr RowDirection directions[] = {RowDirection::plus_x, RowDirection::minus_x, RowDirection::plus_z,
                                                  RowDirection::minus_z};
    p.direction = directions[read_choice(*direction, {"+x", "-x", "+z", "-z"})];
  }
  read_optional_within(reader, "push", p.push, -max_spin, max_spin, "rad/s");
  return generate_dominoes(p);
}

std::vector<SceneBody> read_tables(ObjectReader& reader, const MaterialTable& materials) {
  TableParams p;
  read_common(reader, materials, p.name, p.substance);
  read_optional(reader, "count", p.count, 1, 1000);
  read_size(reader, "top_half_extents", p.top_half_extents);
  read_size(reader, "leg_half_extents", p.leg_half_extents);
  read_place(reader, "position", p.position);
  return generate_tables(p);
}

std::vector<SceneBody> read_throw(ObjectReader& reader, const MaterialTable& materials) {
  ThrowParams p;
  read_common(reader, materials, p.name, p.substance);
  read_optional(reader, "count", p.count, 1, 10000);
  if (const Node* seed = reader.find("seed")) p.seed = read_u64(*seed);
  read_place(reader, "position", p.position);
  read_optional_within(reader, "spread", p.spread, Fixed{}, max_distance, "m");
  read_place(reader, "target", p.target);
  read_optional_within(reader, "speed", p.speed, Fixed{}, max_speed, "m/s");
  if (const Node* shapes = reader.find("shapes")) {
    if (shapes->kind != Kind::array || shapes->children.empty()) {
      fail(*shapes, "expected a non-empty array of \"box\", \"sphere\" or \"capsule\"");
    }
    static constexpr ShapeType types[] = {ShapeType::box, ShapeType::sphere, ShapeType::capsule};
    p.shapes.clear();
    for (const Node& shape : shapes->children) p.shapes.push_back(types[read_choice(shape, {"box", "sphere", "capsule"})]);
  }
  read_size(reader, "half_extents", p.half_extents);
  read_optional_within(reader, "radius", p.radius, envelope::min_size, envelope::max_size, "m");
  read_optional_within(reader, "half_height", p.half_height, Fixed{}, envelope::max_size, "m");
  ThrowResult result = generate_throw(p);
  if (!result.placed_all) {
    fail(reader.node(), "no free spot for body " + std::to_string(result.bodies.size()) +
                            " after 1000 draws: make \"spread\" larger or \"count\" smaller");
  }
  return std::move(result.bodies);
}

std::vector<SceneBody> read_generator(const Node& node, const MaterialTable& materials) {
  ObjectReader reader(node);
  using Reader = std::vector<SceneBody> (*)(ObjectReader&, const MaterialTable&);
  static constexpr Reader readers[] = {read_stack, read_pyramid, read_wall, read_jenga,
                                       read_dominoes, read_tables, read_throw};
  const size_t type =
      read_choice(reader.require("type"), {"stack", "pyramid", "wall", "jenga", "dominoes", "tables", "throw"});
  std::vector<SceneBody> bodies = readers[type](reader, materials);
  reader.finish();
  for (const SceneBody& body : bodies) {
    const EnvelopeError envelope = check_envelope(body.def);
    if (!envelope.ok()) {
      fail(node, "generated body " + json::quote(body.name) + ": " + envelope_field(envelope) + " " + envelope.reason);
    }
  }
  return bodies;
}

// --- the file -------------------------------------------------------------

void check_header(ObjectReader& reader) {
  const Node& format = reader.require("format");
  if (read_string(format) != "bitstep-scene") fail(format, "expected \"bitstep-scene\", got " + json::quote(format.text));
  const Node& version = reader.require("version");
  const int number = read_int(version, INT_MIN, INT_MAX);
  if (number != 1) fail(version, "unsupported version " + std::to_string(number) + " (this build reads version 1)");
}

// Names are optional, but those given are unique.
void add_bodies(Scene& scene, std::set<std::string>& names, std::vector<SceneBody> bodies, const Node& source,
                bool one_node_per_body) {
  if (scene.bodies.size() + bodies.size() > static_cast<size_t>(max_bodies)) {
    fail(source, "more than " + std::to_string(max_bodies) + " bodies in the scene");
  }
  for (size_t i = 0; i < bodies.size(); ++i) {
    SceneBody& body = bodies[i];
    if (!body.name.empty() && !names.insert(body.name).second) {
      if (one_node_per_body) fail(source.children[i].path + ".name", "duplicate body name " + json::quote(body.name));
      fail(source, "generated body name " + json::quote(body.name) + " is already taken");
    }
    scene.bodies.push_back(std::move(body));
  }
}

Scene read_scene(const Node& root) {
  ObjectReader reader(root);
  check_header(reader);
  if (const Node* description = reader.find("description")) read_string(*description);
  Scene scene;
  if (const Node* settings = reader.find("settings")) read_settings_onto(*settings, scene.settings);
  MaterialTable& materials = scene.materials;
  if (const Node* table = reader.find("materials")) materials = read_materials(*table);
  std::set<std::string> names;
  if (const Node* bodies = reader.find("bodies")) {
    if (bodies->kind != Kind::array) fail(*bodies, std::string("expected an array of bodies, got ") + json::describe(bodies->kind));
    std::vector<SceneBody> read;
    for (const Node& body : bodies->children) read.push_back(read_body(body, materials));
    add_bodies(scene, names, std::move(read), *bodies, true);
  }
  if (const Node* generators = reader.find("generators")) {
    if (generators->kind != Kind::array) {
      fail(*generators, std::string("expected an array of generators, got ") + json::describe(generators->kind));
    }
    for (const Node& generator : generators->children) {
      add_bodies(scene, names, read_generator(generator, materials), generator, false);
    }
  }
  reader.finish();
  return scene;
}

}  // namespace

void read_settings_onto(const Node& node, Settings& s) {
  ObjectReader reader(node);
  read_optional_within(reader, "dt", s.dt, envelope::min_dt, envelope::max_dt, "s");
  read_optional_within(reader, "gravity", s.gravity, -envelope::max_gravity, envelope::max_gravity, "m/s^2");
  read_optional(reader, "velocity_iterations", s.velocity_iterations, 1, 1000);
  read_optional(reader, "position_iterations", s.position_iterations, 0, 1000);
  read_optional_within(reader, "penetration_slop", s.penetration_slop, Fixed{}, envelope::max_size, "m");
  read_optional(reader, "split_impulse_factor", s.split_impulse_factor, Bound::unit_interval);
  read_optional_within(reader, "max_push_out_speed", s.max_push_out_speed, Fixed{}, envelope::max_linear_speed, "m/s");
  read_optional(reader, "baumgarte", s.baumgarte);
  read_optional(reader, "baumgarte_factor", s.baumgarte_factor, Bound::unit_interval);
  read_optional_within(reader, "restitution_threshold", s.restitution_threshold, Fixed{}, envelope::max_linear_speed,
                       "m/s");
  read_optional_within(reader, "speculative_distance", s.speculative_distance, Fixed{}, envelope::max_size, "m");
  // Clamps: positive, and no faster than the envelope lets every product fit.
  read_optional(reader, "max_linear_speed", s.max_linear_speed, Bound::positive);
  read_optional(reader, "max_angular_speed", s.max_angular_speed, Bound::positive);
  read_optional_within(reader, "max_linear_speed", s.max_linear_speed, Fixed{}, envelope::max_linear_speed, "m/s");
  read_optional_within(reader, "max_angular_speed", s.max_angular_speed, Fixed{}, envelope::max_angular_speed, "rad/s");
  read_optional(reader, "warm_starting", s.warm_starting);
  read_optional(reader, "shock_propagation", s.shock_propagation);
  read_optional(reader, "shock_iterations", s.shock_iterations, 1, 1000);
  if (const Node* pipeline = reader.find("pipeline")) {
    static constexpr Pipeline pipelines[] = {Pipeline::standard, Pipeline::guendelman};
    s.pipeline = pipelines[read_choice(*pipeline, {"standard", "guendelman"})];
  }
  if (const Node* sleep = reader.find("sleep")) {
    static constexpr SleepMethod methods[] = {SleepMethod::off, SleepMethod::motion, SleepMethod::still};
    s.sleep_method = methods[read_choice(*sleep, {"off", "motion", "still"})];
  }
  // Bounded so that 10 epsilon and time / dt stay inside Q32.32.
  read_optional_within(reader, "sleep_epsilon", s.sleep_epsilon, 0.0_fx, 1000.0_fx, "m^2/s^2");
  read_optional(reader, "sleep_bias", s.sleep_bias, Bound::unit_interval);
  read_optional_within(reader, "sleep_min_time", s.sleep_min_time, 0.0_fx, 1000.0_fx, "s");
  read_optional_within(reader, "sleep_time", s.sleep_time, 0.0_fx, 1000.0_fx, "s");
  read_optional_within(reader, "sleep_linear_tolerance", s.sleep_linear_tolerance, 0.0_fx, 1000.0_fx, "m");
  read_optional_within(reader, "sleep_angular_tolerance", s.sleep_angular_tolerance, 0.0_fx, 4.0_fx, "rad");
  reader.finish();
}

std::string SceneError::message() const {
  if (path.empty()) return file + ": " + reason;
  return file + ": " + path + ": " + reason;
}

std::variant<Scene, SceneError> parse_scene(std::string_view json_text, const std::string& file_name) {
  try {
    auto tree = json::parse(json_text);
    if (const auto* error = std::get_if<json::SyntaxError>(&tree)) return SceneError{file_name, error->where, error->reason};
    return read_scene(std::get<json::Node>(tree));
  } catch (const ReadFailure& failure) {
    return SceneError{file_name, failure.path, failure.reason};
  } catch (const std::exception& e) {  // allocation failure
    return SceneError{file_name, "$", std::string("cannot load: ") + e.what()};
  }
}

std::variant<std::string, SceneError> apply_settings_text(std::string_view json_text, const std::string& source,
                                                          Settings& settings) {
  try {
    auto tree = json::parse(json_text);
    if (const auto* error = std::get_if<json::SyntaxError>(&tree)) return SceneError{source, error->where, error->reason};
    const Node& node = std::get<Node>(tree);
    Settings applied = settings;
    read_settings_onto(node, applied);
    settings = applied;
    return json::write(node);
  } catch (const ReadFailure& failure) {
    return SceneError{source, failure.path, failure.reason};
  } catch (const std::exception& e) {  // allocation failure
    return SceneError{source, "$", std::string("cannot load: ") + e.what()};
  }
}

bool read_text_file(const std::string& path, std::string& text, std::string& reason) {
  std::error_code ignored;
  if (!std::filesystem::is_regular_file(path, ignored)) {
    reason = "cannot read the file (no such regular file)";
    return false;
  }
  const std::uintmax_t size = std::filesystem::file_size(path, ignored);
  if (ignored || size > max_file_bytes) {
    reason = "cannot read the file (unreadable or over 1 GiB)";
    return false;
  }
  text.assign(static_cast<size_t>(size), '\0');
  std::ifstream file(path, std::ios::binary);
  if (!file.read(text.data(), static_cast<std::streamsize>(size))) {
    reason = "cannot read the file";
    return false;
  }
  return true;
}

std::variant<Scene, SceneError> load_scene_file(const std::string& path) {
  std::string text, reason;
  if (!read_text_file(path, text, reason)) return SceneError{path, "", reason};
  return parse_scene(text, path);
}

SceneBody read_scene_body(const json::Node& node, const Scene& scene) { return read_body(node, scene.materials); }

}  // namespace bitstep
