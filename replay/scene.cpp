#include "replay/scene.h"

#include <algorithm>
#include <climits>
#include <filesystem>
#include <fstream>
#include <iterator>
#include <map>
#include <set>

#include "core/convex_hull.h"
#include "core/envelope.h"
#include "core/height_grid.h"
#include "core/triangle_mesh.h"
#include "replay/generators.h"
#include "replay/json_tree.h"
#include "replay/limits.h"
#include "replay/scene_reader.h"

namespace bitstep {

using json::Kind;
using json::Node;
using namespace scene_reader;

namespace {

constexpr int max_bodies = limits::max_scene_bodies;  // in one scene, all generators included
constexpr int max_joints = limits::max_scene_joints;  // likewise
constexpr Fixed max_distance = 1000.0_fx;  // m: a generator's gap, spacing, spread
constexpr Fixed max_speed = 500.0_fx;      // m/s, as check_envelope
constexpr Fixed max_spin = 100.0_fx;       // rad/s, as check_envelope
constexpr Fixed min_axis_length = 0.001_fx;  // a joint's axis, a chain's direction (as World::create_joint)

// An array of at most `limit` items of `what`, refused before any is read.
void check_count(const Node& array, size_t limit, const char* what) {
  if (array.children.size() > limit) {
    fail(array, std::to_string(array.children.size()) + " " + what + ": more than the limit of " + std::to_string(limit));
  }
}

// A joint's solver passes (JointDef::velocity_iterations,
// position_iterations), 0..1000: absent, as they are.
void read_iterations(ObjectReader& reader, uint16_t& velocity, uint16_t& position) {
  for (const auto& [key, field] : {std::pair{"velocity_iterations", &velocity}, std::pair{"position_iterations", &position}}) {
    int value = *field;
    read_optional(reader, key, value, 0, max_joint_iterations);
    *field = static_cast<uint16_t>(value);
  }
}

MaterialTable read_materials(const Node& node) {
  if (node.kind != Kind::object) fail(node, std::string("expected an object of named materials, got ") + json::describe(node.kind));
  check_count(node, limits::max_materials, "materials");
  MaterialTable table;
  // The keys of a JSON object are unique (json::parse refuses duplicates).
  for (const Node& entry : node.children) table.add(entry.key, read_material_fields(entry));
  return table;
}

// A hull's points, [[x, y, z], ...] in the shape's frame, built into its
// hull (core/convex_hull.h); the builder's refusal names the point.
std::shared_ptr<const ConvexHull> read_hull(const Node& node) {
  if (node.kind != Kind::array)
    fail(node, std::string("expected an array of points, got ") + json::describe(node.kind));
  check_count(node, max_hull_points, "points");
  std::vector<Vec3> points;
  points.reserve(node.children.size());
  for (const Node& point : node.children) points.push_back(read_vec3(point));
  Result<std::shared_ptr<const ConvexHull>> hull = build_convex_hull(points);
  if (!hull.ok()) {
    const std::string& place = hull.error().place;
    const std::string within = place.rfind("points", 0) == 0 ? place.substr(6) : place;  // "points[7].y" -> "[7].y"
    fail(node.path + within, hull.error().reason);
  }
  return std::move(hull.value());
}

// A mesh's "vertices" ([[x, y, z], ...], the shape's frame) and "indices"
// (three per triangle, counter-clockwise seen from its front), built into
// its mesh (core/triangle_mesh.h); a refusal names its place.
std::shared_ptr<const TriangleMesh> read_mesh(const Node& vertices_node, const Node& indices_node) {
  if (vertices_node.kind != Kind::array) {
    fail(vertices_node, std::string("expected an array of points, got ") + json::describe(vertices_node.kind));
  }
  if (indices_node.kind != Kind::array) {
    fail(indices_node, std::string("expected an array of vertex indices, got ") + json::describe(indices_node.kind));
  }
  check_count(vertices_node, max_mesh_vertices, "vertices");
  check_count(indices_node, size_t{3} * max_mesh_triangles, "indices");
  std::vector<Vec3> vertices;
  vertices.reserve(vertices_node.children.size());
  for (const Node& point : vertices_node.children) vertices.push_back(read_vec3(point));
  std::vector<uint32_t> indices;
  indices.reserve(indices_node.children.size());
  for (const Node& index : indices_node.children) {
    indices.push_back(static_cast<uint32_t>(read_int(index, 0, static_cast<int>(max_mesh_vertices) - 1)));
  }
  Result<std::shared_ptr<const TriangleMesh>> mesh = build_triangle_mesh(vertices, indices);
  if (!mesh.ok()) {
    const std::string& place = mesh.error().place;
    // "vertices[2].x" and "indices[5]" lie under their arrays; "triangle 3" under the indices.
    if (place.rfind("vertices", 0) == 0) fail(vertices_node.path + place.substr(8), mesh.error().reason);
    if (place.rfind("indices", 0) == 0) fail(indices_node.path + place.substr(7), mesh.error().reason);
    fail(indices_node.path + (place.empty() ? "" : " (" + place + ")"), mesh.error().reason);
  }
  return std::move(mesh.value());
}

// A heightfield's "columns" and "rows" (samples along x and z),
// "spacing" ([x, z], m), "heights" (row by row, rows x columns) and
// optional "holes" ([[i, j], ...]: cells without ground, in any order),
// built into its mesh (core/height_grid.h); a refusal names its place.
std::shared_ptr<const TriangleMesh> read_heightfield(ObjectReader& reader) {
  HeightGrid grid;
  const Node& columns = reader.require("columns");
  const Node& rows = reader.require("rows");
  grid.columns = static_cast<uint32_t>(read_int(columns, 2, static_cast<int>(max_grid_samples)));
  grid.rows = static_cast<uint32_t>(read_int(rows, 2, static_cast<int>(max_grid_samples)));
  const Node& spacing = reader.require("spacing");
  if (spacing.kind != Kind::array || spacing.children.size() != 2) fail(spacing, "expected [x, z] in m");
  grid.spacing_x = read_fixed_within(spacing.children[0], min_grid_spacing, max_grid_spacing, "m");
  grid.spacing_z = read_fixed_within(spacing.children[1], min_grid_spacing, max_grid_spacing, "m");
  const Node& heights = reader.require("heights");
  if (heights.kind != Kind::array)
    fail(heights, std::string("expected an array of heights, got ") + json::describe(heights.kind));
  const size_t expected = size_t{grid.columns} * grid.rows;
  if (heights.children.size() != expected) {
    fail(heights, std::to_string(heights.children.size()) + " heights, not " + std::to_string(grid.columns) + " x " +
                      std::to_string(grid.rows));
  }
  grid.heights.reserve(expected);
  for (const Node& h : heights.children)
    grid.heights.push_back(read_fixed_within(h, -max_grid_span, max_grid_span, "m"));
  const Node* holes = reader.find("holes");
  if (holes) {
    if (holes->kind != Kind::array)
      fail(*holes, std::string("expected an array of [i, j] cells, got ") + json::describe(holes->kind));
    check_count(*holes, max_grid_cells, "holes");
    for (const Node& hole : holes->children) {
      if (hole.kind != Kind::array || hole.children.size() != 2) fail(hole, "expected a cell [i, j]");
      const auto i = static_cast<uint32_t>(read_int(hole.children[0], 0, static_cast<int>(grid.columns) - 2));
      const auto j = static_cast<uint32_t>(read_int(hole.children[1], 0, static_cast<int>(grid.rows) - 2));
      grid.holes.push_back(j * (grid.columns - 1) + i);
    }
    // (cell, place) ascending: a cell listed twice is two neighbours; the
    // refusal names its second place.
    std::vector<std::pair<uint32_t, size_t>> sorted;
    for (size_t k = 0; k < grid.holes.size(); ++k) sorted.emplace_back(grid.holes[k], k);
    std::sort(sorted.begin(), sorted.end());
    for (size_t k = 1; k < sorted.size(); ++k) {
      if (sorted[k].first == sorted[k - 1].first) fail(holes->children[sorted[k].second], "a cell listed twice");
    }
    for (size_t k = 0; k < sorted.size(); ++k) grid.holes[k] = sorted[k].first;
  }
  Result<std::shared_ptr<const TriangleMesh>> mesh = build_height_grid_mesh(std::move(grid));
  if (!mesh.ok()) {
    const std::string& place = mesh.error().place;
    const Node& at = place == "columns"          ? columns
                     : place == "rows"           ? rows
                     : place == "holes" && holes ? *holes
                                                 : heights;
    fail(at.path + (place.rfind("heights[", 0) == 0 ? place.substr(7) : ""), mesh.error().reason);
  }
  return std::move(mesh.value());
}

Shape read_shape(const Node& node) {
  ObjectReader reader(node);
  Shape shape;
  static const std::vector<std::string_view> names(shape_type_names.begin(), shape_type_names.end());
  shape.type = static_cast<ShapeType>(read_choice(reader.require("type"), names));
  switch (shape.type) {
    case ShapeType::box: shape.half_extents = read_vec3(reader.require("half_extents")); break;
    case ShapeType::sphere: shape.radius = read_fixed(reader.require("radius")); break;
    case ShapeType::capsule:
      shape.radius = read_fixed(reader.require("radius"));
      shape.half_height = read_fixed(reader.require("half_height"));
      break;
    case ShapeType::plane: break;
    case ShapeType::hull: shape.hull = read_hull(reader.require("points")); break;
    case ShapeType::mesh: shape.mesh = read_mesh(reader.require("vertices"), reader.require("indices")); break;
    case ShapeType::heightfield: shape.mesh = read_heightfield(reader); break;
  }
  read_optional(reader, "position", shape.local.position);
  if (const Node* orientation = reader.find("orientation")) shape.local.orientation = read_orientation(*orientation);
  reader.finish();
  return shape;
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

// "layers" and "collides_with": arrays of layer numbers 0..31 (each a bit
// of the body's CollisionFilter, core/body.h); absent, the defaults (layer
// 0, colliding with every layer).
uint32_t read_layer_bits(const Node& node) {
  if (node.kind != Kind::array) fail(node, std::string("expected an array of layer numbers 0..31, got ") + json::describe(node.kind));
  uint32_t bits = 0;
  for (const Node& layer : node.children) bits |= uint32_t{1} << read_int(layer, 0, 31);
  return bits;
}
void read_filter(ObjectReader& reader, CollisionFilter& filter) {
  if (const Node* layers = reader.find("layers")) filter.layers = read_layer_bits(*layers);
  if (const Node* with = reader.find("collides_with")) filter.collides_with = read_layer_bits(*with);
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
  read_filter(reader, def.filter);
  read_optional(reader, "sensor", def.sensor);
  const Node& shapes = reader.require("shapes");
  if (shapes.kind != Kind::array) fail(shapes, std::string("expected an array of shapes, got ") + json::describe(shapes.kind));
  check_count(shapes, limits::max_shapes_per_body, "shapes in a body");
  for (const Node& shape : shapes.children) def.shapes.push_back(read_shape(shape));
  reader.finish();

  check_speed_components(node, def);
  if (const Result<void> envelope = check_envelope(def); !envelope.ok()) {
    fail(node.path + "." + envelope.error().place, envelope.error().reason);
  }
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

// The bodies a generator's parameters ask for, before it makes them.
void check_generated_count(ObjectReader& reader, int64_t bodies) {
  if (bodies > limits::max_generated_bodies) {
    fail(reader.node(), "would make " + std::to_string(bodies) + " bodies: more than the limit of " +
                            std::to_string(limits::max_generated_bodies) + " in a scene");
  }
}

// An overlap must leave boxes with positive height: below the half height.
void check_overlap(ObjectReader& reader, Fixed overlap, Fixed half_height) {
  if (overlap >= half_height) fail(*reader.find("overlap"), "must be less than the boxes' half height");
}

GeneratedStructure read_stack(ObjectReader& reader, const MaterialTable& materials) {
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
  return {generate_stack(p), {}};
}

GeneratedStructure read_pyramid(ObjectReader& reader, const MaterialTable& materials) {
  PyramidParams p;
  read_common(reader, materials, p.name, p.substance);
  read_optional(reader, "base", p.base, 1, 1000);
  read_size(reader, "half_extents", p.half_extents);
  read_place(reader, "position", p.position);
  read_optional_within(reader, "gap", p.gap, Fixed{}, max_distance, "m");
  read_optional_within(reader, "overlap", p.overlap, Fixed{}, envelope::max_size, "m");
  check_overlap(reader, p.overlap, p.half_extents.y);
  check_generated_count(reader, int64_t{p.base} * (p.base + 1) / 2);
  return {generate_pyramid(p), {}};
}

GeneratedStructure read_wall(ObjectReader& reader, const MaterialTable& materials) {
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
  // Rectangle: base bricks a row; triangle: base, base - 1, ... (rows <= base).
  const int64_t bricks = p.shape == WallShape::rectangle
                             ? int64_t{p.base} * p.rows
                             : int64_t{p.rows} * (2 * int64_t{p.base} - p.rows + 1) / 2;
  check_generated_count(reader, bricks);
  return {generate_wall(p), {}};
}

GeneratedStructure read_jenga(ObjectReader& reader, const MaterialTable& materials) {
  JengaParams p;
  read_common(reader, materials, p.name, p.substance);
  read_optional(reader, "levels", p.levels, 1, 10000);
  read_size(reader, "half_extents", p.half_extents);
  read_place(reader, "position", p.position);
  read_optional_within(reader, "overlap", p.overlap, Fixed{}, envelope::max_size, "m");
  check_overlap(reader, p.overlap, p.half_extents.y);
  return {generate_jenga(p), {}};
}

GeneratedStructure read_dominoes(ObjectReader& reader, const MaterialTable& materials) {
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
  return {generate_dominoes(p), {}};
}

GeneratedStructure read_tables(ObjectReader& reader, const MaterialTable& materials) {
  TableParams p;
  read_common(reader, materials, p.name, p.substance);
  read_optional(reader, "count", p.count, 1, 1000);
  read_size(reader, "top_half_extents", p.top_half_extents);
  read_size(reader, "leg_half_extents", p.leg_half_extents);
  read_place(reader, "position", p.position);
  return {generate_tables(p), {}};
}

GeneratedStructure read_throw(ObjectReader& reader, const MaterialTable& materials) {
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
  return {std::move(result.bodies), {}};
}

// A direction or an axis: components within +-1000, at least 0.001 long.
Vec3 read_direction(const Node& node) {
  const Vec3 v = read_vec3_within(node, -max_distance, max_distance, "");
  if (length(v) < min_axis_length) fail(node, "shorter than 0.001");
  return v;
}

GeneratedStructure read_chain(ObjectReader& reader, const MaterialTable& materials) {
  ChainParams p;
  read_common(reader, materials, p.name, p.substance);
  read_optional(reader, "count", p.count, 1, 1000);
  if (const Node* link = reader.find("link")) {
    p.link = read_choice(*link, {"box", "sphere"}) == 0 ? ChainLink::box : ChainLink::sphere;
  }
  // Only the size key of the link's shape is known (as a shape's).
  if (p.link == ChainLink::box) read_size(reader, "half_extents", p.half_extents);
  if (p.link == ChainLink::sphere) {
    read_optional_within(reader, "radius", p.radius, envelope::min_size, envelope::max_size, "m");
  }
  read_optional_within(reader, "gap", p.gap, Fixed{}, max_distance, "m");
  read_place(reader, "position", p.position);
  if (const Node* direction = reader.find("direction")) p.direction = read_direction(*direction);
  if (const Node* anchored = reader.find("anchored")) {
    static constexpr ChainAnchoring modes[] = {ChainAnchoring::none, ChainAnchoring::first, ChainAnchoring::both};
    p.anchored = modes[read_choice(*anchored, {"none", "first", "both"})];
  }
  if (const Node* joint = reader.find("joint")) {
    p.joint = read_choice(*joint, {"point", "hinge"}) == 0 ? JointType::point : JointType::hinge;
  }
  if (p.joint == JointType::hinge) {
    if (const Node* axis = reader.find("axis")) p.axis = read_direction(*axis);
  }
  return generate_chain(p);
}

// Ragdolls: no density or mass keys (each part's mass is its share of
// 75 kg x scale^3), and asleep by default, as JigLib's ragdolls.
GeneratedStructure read_ragdoll(ObjectReader& reader, const MaterialTable& materials) {
  RagdollParams p;
  if (const Node* n = reader.find("name")) p.name = read_string(*n);
  if (const Node* material = reader.find("material")) p.material = read_material(*material, materials);
  read_optional(reader, "asleep", p.asleep);
  read_optional(reader, "linear_damping", p.linear_damping, Bound::non_negative);
  read_optional(reader, "angular_damping", p.angular_damping, Bound::non_negative);
  if (const Node* friction = reader.find("joint_friction")) {
    p.joint_friction = read_fixed_within(*friction, Fixed{}, Fixed::from_int(1000), "N m");
  }
  read_iterations(reader, p.velocity_iterations, p.position_iterations);
  read_optional(reader, "count", p.count, 1, 1000);
  read_place(reader, "position", p.position);
  read_optional_within(reader, "spacing", p.spacing, -max_distance, max_distance, "m");
  // 0.25: the thinnest part (a forearm, radius 4 cm) stays 1 cm thick;
  // 10: the heaviest (the chest, 26.6 kg x scale^3) stays under 1e5 kg.
  read_optional_within(reader, "scale", p.scale, 0.25_fx, 10.0_fx, "");
  if (const Node* orientation = reader.find("orientation")) p.orientation = read_orientation(*orientation);
  return generate_ragdoll(p);
}

GeneratedStructure read_generator(const Node& node, const MaterialTable& materials) {
  ObjectReader reader(node);
  using Reader = GeneratedStructure (*)(ObjectReader&, const MaterialTable&);
  static constexpr Reader readers[] = {read_stack, read_pyramid, read_wall, read_jenga, read_dominoes,
                                       read_tables, read_throw, read_chain, read_ragdoll};
  const size_t type = read_choice(reader.require("type"), {"stack", "pyramid", "wall", "jenga", "dominoes", "tables",
                                                           "throw", "chain", "ragdoll"});
  GeneratedStructure generated = readers[type](reader, materials);
  CollisionFilter filter;
  read_filter(reader, filter);
  for (SceneBody& body : generated.bodies) body.def.filter = filter;
  reader.finish();
  for (const SceneBody& body : generated.bodies) {
    const Result<void> envelope = check_envelope(body.def);
    if (!envelope.ok()) {
      const Error& e = envelope.error();
      fail(node, "generated body " + json::quote(body.name) + ": " + e.place + " " + e.reason);
    }
  }
  return generated;
}

// --- cars -------------------------------------------------------------------

// One car: its chassis (a dynamic body, by name), its wheels, and the
// CarDef fields over their defaults, each within check_car's ranges.

SceneCar read_car(const Node& node, const Scene& scene, const std::map<std::string, uint32_t>& bodies) {
  ObjectReader reader(node);
  SceneCar car;
  car.name = read_string(reader.require("name"));
  const Node& chassis = reader.require("chassis");
  const auto found = bodies.find(read_string(chassis));
  if (found == bodies.end()) fail(chassis, "no body named " + json::quote(read_string(chassis)));
  if (scene.bodies[found->second].def.type != BodyType::dynamic) fail(chassis, "the chassis must be a dynamic body");
  car.chassis = found->second;
  CarDef& def = car.def;
  const Node& wheels = reader.require("wheels");
  if (wheels.kind != Kind::array || wheels.children.empty() || wheels.children.size() > 8) {
    fail(wheels, "expected an array of 1..8 wheels");
  }
  const Fixed reach = envelope::max_size + envelope::max_size;
  for (const Node& wheel_node : wheels.children) {
    ObjectReader wheel(wheel_node);
    WheelDef w;
    w.attachment = read_vec3_within(wheel.require("attachment"), -reach, reach, "m");
    read_optional(wheel, "driven", w.driven);
    read_optional(wheel, "steered", w.steered);
    wheel.finish();
    def.wheels.push_back(w);
  }
  read_optional_within(reader, "wheel_radius", def.wheel_radius, 0.05_fx, 5.0_fx, "m");
  read_optional_within(reader, "rest_length", def.rest_length, Fixed{}, 5.0_fx, "m");
  read_optional_within(reader, "stiffness", def.stiffness, Fixed{}, 10000000.0_fx, "N/m");
  read_optional_within(reader, "damping", def.damping, Fixed{}, 1000000.0_fx, "N s/m");
  read_optional_within(reader, "grip", def.grip, Fixed{}, 10.0_fx, "");
  read_optional_within(reader, "drive_force", def.drive_force, Fixed{}, 1000000.0_fx, "N");
  read_optional_within(reader, "brake_force", def.brake_force, Fixed{}, 1000000.0_fx, "N");
  read_optional_within(reader, "max_steer", def.max_steer, Fixed{}, 1.5_fx, "rad");
  read_optional(reader, "rays_per_wheel", def.rays_per_wheel, 1, 8);
  reader.finish();
  return car;
}

// --- joints ---------------------------------------------------------------

// A joint's point given either in the world ("anchor", "anchor_b") or in its
// body's frame ("local_anchor_a", "local_anchor_b"): exactly one of the two.
// (The keys are literals: the reader keeps views of them.)
Vec3 read_anchor(ObjectReader& reader, std::string_view world_key, std::string_view local_key, bool& local) {
  const Node* in_world = reader.find(world_key);
  const Node* in_body = reader.find(local_key);
  const std::string keys = "\"" + std::string(world_key) + "\" or \"" + std::string(local_key) + "\"";
  if (in_world != nullptr && in_body != nullptr) fail(*in_body, "give " + keys + ", not both");
  if (in_world == nullptr && in_body == nullptr) {
    fail(reader.node(), "missing key \"" + std::string(world_key) + "\" (or \"" + std::string(local_key) + "\")");
  }
  local = in_body != nullptr;
  return read_vec3_within(local ? *in_body : *in_world, -envelope::max_position, envelope::max_position, "m");
}

// "limits": [lower, upper] in degrees, lower in -180..0 and upper in 0..180,
// turned into radians as orientations are: mul_div(d, pi, 180), the exact
// product rounded once (so 180 degrees is pi to the bit).
void read_limits(const Node& node, JointDef& def) {
  if (node.kind != Kind::array) fail(node, std::string("expected [lower, upper] in degrees, got ") + json::describe(node.kind));
  if (node.children.size() != 2) {
    fail(node, "expected [lower, upper] in degrees, got " + std::to_string(node.children.size()) + " numbers");
  }
  const Fixed lower = read_fixed_within(node.children[0], Fixed::from_int(-180), Fixed{}, "degrees");
  const Fixed upper = read_fixed_within(node.children[1], Fixed{}, Fixed::from_int(180), "degrees");
  def.limited = true;
  def.lower_angle = mul_div(lower, pi_q32, Fixed::from_int(180));
  def.upper_angle = mul_div(upper, pi_q32, Fixed::from_int(180));
}

// "motor": {"speed": rad/s (a hinge) or m/s (a slider), and "max_torque"
// (N m, a hinge) or "max_force" (N, a slider)}: the most the motor puts
// into driving b relative to a at that speed. 0: no motor.
void read_motor(const Node& node, JointDef& def, std::string_view max_key, Fixed fastest, std::string_view speed_unit,
                std::string_view max_unit) {
  ObjectReader reader(node);
  def.motor_speed = read_fixed_within(reader.require("speed"), -fastest, fastest, speed_unit);
  def.motor_max = read_fixed_within(reader.require(max_key), Fixed{}, Fixed::from_int(1000000), max_unit);
  reader.finish();
}

// A slider's keys: its axis, its limits in m from the creation pose
// ("lower_translation" -1000..0, "upper_translation" 0..1000; either
// given limits it, the other then 0), a motor, and friction (N, along
// the axis).
void read_slider_keys(ObjectReader& reader, JointDef& def) {
  def.axis = read_direction(reader.require("axis"));
  const Node* lower = reader.find("lower_translation");
  const Node* upper = reader.find("upper_translation");
  def.limited = lower != nullptr || upper != nullptr;
  if (lower != nullptr) def.lower_translation = read_fixed_within(*lower, -max_distance, Fixed{}, "m");
  if (upper != nullptr) def.upper_translation = read_fixed_within(*upper, Fixed{}, max_distance, "m");
  if (const Node* motor = reader.find("motor")) read_motor(*motor, def, "max_force", envelope::max_linear_speed, "m/s", "N");
  if (const Node* friction = reader.find("friction")) {
    def.friction_torque = read_fixed_within(*friction, Fixed{}, Fixed::from_int(1000000), "N");
  }
}

// The keys of a joint's own type, one case per type (no default: a type
// without its case is a -Wswitch error). Only these are known: "axis" on
// a point joint is an unknown key.
void read_type_keys(ObjectReader& reader, JointSpec& spec) {
  JointDef& def = spec.def;
  switch (def.type) {
    case JointType::point: break;
    case JointType::max_distance:
      def.anchor_b = read_anchor(reader, "anchor_b", "local_anchor_b", spec.anchor_b_local);
      if (const Node* length = reader.find("length")) {
        // Absent: the anchors' distance at creation (JointDef::length 0).
        def.length = read_fixed(*length, Bound::positive);
        if (def.length > max_distance) fail(*length, "longer than 1000 m");
      }
      return;  // a rope has no friction
    case JointType::hinge:
      def.axis = read_direction(reader.require("axis"));
      if (const Node* limits = reader.find("limits")) read_limits(*limits, def);
      if (const Node* motor = reader.find("motor")) read_motor(*motor, def, "max_torque", envelope::max_angular_speed, "rad/s", "N m");
      break;
    case JointType::cone: {
      // The twist axis, the swing cone's half angle and the twist limits, in degrees.
      def.axis = read_direction(reader.require("axis"));
      const Node& swing = reader.require("swing");
      def.swing_angle = mul_div(read_fixed_within(swing, Fixed{}, Fixed::from_int(180), "degrees"), pi_q32, Fixed::from_int(180));
      read_limits(reader.require("twist"), def);
      break;
    }
    case JointType::slider:
      read_slider_keys(reader, def);
      return;
  }
  // N m, against the bodies turning relative to each other.
  if (const Node* friction = reader.find("friction")) {
    def.friction_torque = read_fixed_within(*friction, Fixed{}, Fixed::from_int(1000000), "N m");
  }
}

// Reads "joints": each joint's bodies by name, local anchors placed at the
// bodies' scene poses. Names, when given, are unique among all the scene's
// joints (`names` holds the generated ones, read before).
std::vector<SceneJoint> read_joints(const Node& node, const Scene& scene, const std::map<std::string, uint32_t>& bodies,
                                    std::set<std::string>& names) {
  if (node.kind != Kind::array) fail(node, std::string("expected an array of joints, got ") + json::describe(node.kind));
  check_count(node, static_cast<size_t>(max_joints), "joints");
  const BodyResolver resolve = [&](const Node& name) -> uint32_t {
    const auto found = bodies.find(read_string(name));
    if (found == bodies.end()) fail(name, "no body named " + json::quote(name.text));
    return found->second;
  };
  std::vector<SceneJoint> joints;
  for (const Node& entry : node.children) {
    const JointSpec spec = read_joint_spec(entry, resolve);
    if (!spec.name.empty() && !names.insert(spec.name).second) {
      fail(entry.path + ".name", "duplicate joint name " + json::quote(spec.name));
    }
    const Pose& frame_a = scene.bodies[spec.body_a].def.pose;
    const Pose& frame_b = scene.bodies[spec.body_b].def.pose;
    joints.push_back({spec.name, joint_in_world(spec, frame_a, frame_b), spec.body_a, spec.body_b});
  }
  return joints;
}

// --- the file -------------------------------------------------------------

void check_header(ObjectReader& reader) {
  const Node& format = reader.require("format");
  if (read_string(format) != "bitstep-scene") fail(format, "expected \"bitstep-scene\", got " + json::quote(format.text));
  const Node& version = reader.require("version");
  const int number = read_int(version, INT_MIN, INT_MAX);
  if (number != 1) fail(version, "unsupported version " + std::to_string(number) + " (this build reads version 1)");
}

// Names are optional, but those given are unique; `names` maps each to its body's index.
void add_bodies(Scene& scene, std::map<std::string, uint32_t>& names, std::vector<SceneBody> bodies, const Node& source,
                bool one_node_per_body) {
  if (scene.bodies.size() + bodies.size() > static_cast<size_t>(max_bodies)) {
    fail(source, "more than " + std::to_string(max_bodies) + " bodies in the scene");
  }
  for (size_t i = 0; i < bodies.size(); ++i) {
    SceneBody& body = bodies[i];
    if (!body.name.empty() && !names.emplace(body.name, static_cast<uint32_t>(scene.bodies.size())).second) {
      if (one_node_per_body) fail(source.children[i].path + ".name", "duplicate body name " + json::quote(body.name));
      fail(source, "generated body name " + json::quote(body.name) + " is already taken");
    }
    scene.bodies.push_back(std::move(body));
  }
}

// A generator's joints, their bodies moved from the generator's own indices
// to the scene's (its first body is `first`).
void add_generated_joints(std::vector<SceneJoint>& out, std::set<std::string>& names, std::vector<SceneJoint> joints,
                          uint32_t first, const Node& source) {
  if (out.size() + joints.size() > static_cast<size_t>(max_joints)) {
    fail(source, "more than " + std::to_string(max_joints) + " joints in the scene");
  }
  for (SceneJoint& joint : joints) {
    if (!joint.name.empty() && !names.insert(joint.name).second) {
      fail(source, "generated joint name " + json::quote(joint.name) + " is already taken");
    }
    joint.body_a += first;
    joint.body_b += first;
    out.push_back(std::move(joint));
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
  std::map<std::string, uint32_t> names;
  if (const Node* bodies = reader.find("bodies")) {
    if (bodies->kind != Kind::array) fail(*bodies, std::string("expected an array of bodies, got ") + json::describe(bodies->kind));
    check_count(*bodies, max_bodies, "bodies");
    std::vector<SceneBody> read;
    for (const Node& body : bodies->children) read.push_back(read_body(body, materials));
    add_bodies(scene, names, std::move(read), *bodies, true);
  }
  // Generators before "joints", which may name their bodies; the joints'
  // creation order is still "joints" first, then each generator's.
  std::vector<SceneJoint> generated_joints;
  std::set<std::string> joint_names;
  if (const Node* generators = reader.find("generators")) {
    if (generators->kind != Kind::array) {
      fail(*generators, std::string("expected an array of generators, got ") + json::describe(generators->kind));
    }
    check_count(*generators, limits::max_generators, "generators");
    for (const Node& generator : generators->children) {
      GeneratedStructure generated = read_generator(generator, materials);
      const auto first = static_cast<uint32_t>(scene.bodies.size());
      add_bodies(scene, names, std::move(generated.bodies), generator, false);
      add_generated_joints(generated_joints, joint_names, std::move(generated.joints), first, generator);
    }
  }
  if (const Node* joints = reader.find("joints")) {
    scene.joints = read_joints(*joints, scene, names, joint_names);
    if (scene.joints.size() + generated_joints.size() > static_cast<size_t>(max_joints)) {
      fail(*joints, "more than " + std::to_string(max_joints) + " joints in the scene");
    }
  }
  scene.joints.insert(scene.joints.end(), std::make_move_iterator(generated_joints.begin()),
                      std::make_move_iterator(generated_joints.end()));
  if (const Node* cars = reader.find("cars")) {
    if (cars->kind != Kind::array) fail(*cars, std::string("expected an array of cars, got ") + json::describe(cars->kind));
    check_count(*cars, limits::max_scene_cars, "cars");
    std::set<std::string> car_names;
    for (const Node& car : cars->children) {
      scene.cars.push_back(read_car(car, scene, names));
      if (!car_names.insert(scene.cars.back().name).second) {
        fail(*car.member("name"), "duplicate car name " + json::quote(scene.cars.back().name));
      }
    }
  }
  if (const Node* characters = reader.find("characters")) {
    if (characters->kind != Kind::array) {
      fail(*characters, std::string("expected an array of characters, got ") + json::describe(characters->kind));
    }
    check_count(*characters, limits::max_scene_cars, "characters");
    std::set<std::string> character_names;
    for (const Node& character : characters->children) {
      scene.characters.push_back(read_character(character));
      if (!character_names.insert(scene.characters.back().name).second) {
        fail(*character.member("name"), "duplicate character name " + json::quote(scene.characters.back().name));
      }
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
  read_optional(reader, "held_velocity_iterations", s.held_velocity_iterations, 1, 1000);
  read_optional(reader, "substeps", s.substeps, 1, envelope::max_substeps);
  read_optional(reader, "soft_substeps", s.soft_substeps, 0, envelope::max_substeps);
  read_optional_within(reader, "contact_hertz", s.contact_hertz, Fixed{}, envelope::max_contact_hertz, "Hz");
  read_optional_within(reader, "contact_damping_ratio", s.contact_damping_ratio, Fixed{}, envelope::max_damping_ratio,
                       "");
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
  // Each substep's dt stays inside the envelope too; dt and substeps may
  // each come from this object or from the settings it overrides.
  if (s.dt / Fixed::from_int(s.substeps) < envelope::min_dt) {
    const Node* at = reader.find("substeps");
    if (at == nullptr) at = reader.find("dt");
    fail(at != nullptr ? *at : node, "dt / substeps below 0.0001 s (the shortest step of the world envelope)");
  }
  if (s.soft_substeps > 0 && s.dt / Fixed::from_int(s.substeps * s.soft_substeps) < envelope::min_dt) {
    const Node* at = reader.find("soft_substeps");
    if (at == nullptr) at = reader.find("dt");
    fail(at != nullptr ? *at : node,
         "dt / (substeps x soft_substeps) below 0.0001 s (the shortest step of the world envelope)");
  }
  reader.finish();
}

Result<Scene> parse_scene(std::string_view json_text, const std::string& file_name) {
  return read_json(json_text, file_name, [](const Node& root) { return read_scene(root); });
}

Result<std::string> apply_settings_text(std::string_view json_text, const std::string& source, Settings& settings) {
  Settings applied = settings;
  Result<std::string> written = read_json(json_text, source, [&](const Node& node) {
    read_settings_onto(node, applied);
    return json::write(node);
  });
  if (written.ok()) settings = applied;
  return written;
}

Result<void> check_file_size(std::uintmax_t size, std::uintmax_t max_bytes) {
  if (size <= max_bytes) return {};
  return Error{std::to_string(size) + " bytes", "more than the limit of " + std::to_string(max_bytes) + " bytes (" +
                                                    std::to_string(max_bytes >> 20) + " MiB)"};
}

Result<std::string> read_text_file(const std::string& path, std::uintmax_t max_bytes) {
  std::error_code error;
  if (!std::filesystem::is_regular_file(path, error)) return Error{path, "cannot read the file (no such regular file)"};
  // The size first: a file over the limit is refused without reading it.
  const std::uintmax_t size = std::filesystem::file_size(path, error);
  if (error) return Error{path, "cannot read the file (" + error.message() + ")"};
  if (Result<void> fits = check_file_size(size, max_bytes); !fits.ok()) return fits.error().within(path);
  std::string text(static_cast<size_t>(size), '\0');
  std::ifstream file(path, std::ios::binary);
  if (!file.read(text.data(), static_cast<std::streamsize>(size))) return Error{path, "cannot read the file"};
  return text;
}

Result<Scene> load_scene_file(const std::string& path) {
  Result<std::string> text = read_text_file(path);
  if (!text.ok()) return text.error();
  return parse_scene(text.value(), path);
}

SceneBody read_scene_body(const json::Node& node, const Scene& scene) { return read_body(node, scene.materials); }

JointSpec read_joint_spec(const json::Node& node, const BodyResolver& resolve_body) {
  ObjectReader reader(node);
  JointSpec spec;
  JointDef& def = spec.def;
  static constexpr JointType types[] = {JointType::point, JointType::max_distance, JointType::hinge, JointType::cone,
                                        JointType::slider};
  def.type = types[read_choice(reader.require("type"), {"point", "max_distance", "hinge", "cone", "slider"})];
  if (const Node* name = reader.find("name")) spec.name = read_string(*name);
  spec.body_a = resolve_body(reader.require("body_a"));
  const Node& body_b = reader.require("body_b");
  spec.body_b = resolve_body(body_b);
  if (spec.body_b == spec.body_a) fail(body_b, "the same body as body_a");
  // Only the keys of the joint's type are known: "axis" on a point joint is an unknown key.
  def.anchor_a = read_anchor(reader, "anchor", "local_anchor_a", spec.anchor_a_local);
  read_type_keys(reader, spec);
  read_optional(reader, "break_impulse", def.break_impulse, Bound::non_negative);
  read_iterations(reader, def.velocity_iterations, def.position_iterations);
  reader.finish();
  return spec;
}

JointDef joint_in_world(const JointSpec& spec, const Pose& frame_a, const Pose& frame_b) {
  JointDef def = spec.def;
  if (spec.anchor_a_local) def.anchor_a = frame_a.apply(def.anchor_a);
  if (spec.anchor_b_local) def.anchor_b = frame_b.apply(def.anchor_b);
  return def;
}

// A character: "name", "position" (its capsule's centre) and, optional,
// "radius", "half_height", "max_slope" (degrees), "step_height",
// "jump_speed", "air_acceleration", "mass", "max_push_force", "facing"
// (level), "collides_with" (layers).
SceneCharacter read_character(const Node& node) {
  ObjectReader reader(node);
  SceneCharacter character;
  character.name = read_string(reader.require("name"));
  CharacterDef& def = character.def;
  def.position = read_vec3_within(reader.require("position"), -16000.0_fx, 16000.0_fx, "m");
  read_optional_within(reader, "radius", def.radius, 0.05_fx, 5.0_fx, "m");
  read_optional_within(reader, "half_height", def.half_height, Fixed{}, 10.0_fx, "m");
  if (const Node* slope = reader.find("max_slope")) {
    const Fixed degrees = read_fixed_within(*slope, Fixed{}, 89.0_fx, "degrees");
    def.max_slope_cos = cos(mul_div(degrees, pi_q32, Fixed::from_int(180)));
  }
  read_optional_within(reader, "step_height", def.step_height, Fixed{}, 10.0_fx, "m");
  read_optional_within(reader, "jump_speed", def.jump_speed, Fixed{}, 100.0_fx, "m/s");
  read_optional_within(reader, "air_acceleration", def.air_acceleration, Fixed{}, 1000.0_fx, "m/s^2");
  read_optional_within(reader, "mass", def.mass, 0.1_fx, 10000.0_fx, "kg");
  read_optional_within(reader, "max_push_force", def.max_push_force, Fixed{}, 1000000.0_fx, "N");
  if (const Node* facing = reader.find("facing")) {
    const Vec3 f = read_vec3_within(*facing, -Fixed::one(), Fixed::one(), "");
    def.facing = normalize_or({f.x, Fixed{}, f.z}, {});
    if (def.facing == Vec3{}) fail(*facing, "not a level direction");
  }
  if (const Node* layers = reader.find("collides_with")) def.collides_with = read_layer_bits(*layers);
  reader.finish();
  if (Result<void> refused = check_character(def); !refused.ok()) {
    fail(node.path + "." + refused.error().place, refused.error().reason);
  }
  return character;
}

}  // namespace bitstep
