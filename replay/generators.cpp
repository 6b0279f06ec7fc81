#include "replay/generators.h"

#include <algorithm>
#include <unordered_map>

#include "core/convex_hull.h"
#include "fixed/splitmix64.h"
#include "replay/scene_reader.h"

namespace bitstep {

namespace {

std::string body_name(const std::string& prefix, size_t index) { return prefix + "." + std::to_string(index); }

Shape box_shape(Vec3 half_extents, Vec3 local_position = {}) {
  Shape shape;
  shape.type = ShapeType::box;
  shape.half_extents = half_extents;
  shape.local.position = local_position;
  return shape;
}

SceneBody dynamic_body(std::string name, Vec3 position, std::vector<Shape> shapes, const Substance& substance) {
  SceneBody body;
  body.name = std::move(name);
  body.def.type = BodyType::dynamic;
  body.def.pose.position = position;
  body.def.shapes = std::move(shapes);
  body.def.density = substance.density;
  body.def.mass = substance.mass;
  body.def.material = substance.material;
  body.def.asleep = substance.asleep;
  return body;
}

void add_box(std::vector<SceneBody>& out, const std::string& prefix, Vec3 half_extents, Vec3 centre,
             const Substance& substance) {
  out.push_back(dynamic_body(body_name(prefix, out.size()), centre, {box_shape(half_extents)}, substance));
}

// The centre height of level `level` of boxes 2 * half_height tall standing
// on `base_y`, every contact overlapped by `overlap`:
// base_y + half_height - overlap + level (2 half_height - overlap). Integer
// times Fixed and sums are exact: nothing rounds.
Fixed level_centre_y(Fixed base_y, Fixed half_height, Fixed overlap, int level) {
  return base_y + half_height - overlap + Fixed::from_int(level) * (half_height + half_height - overlap);
}

// x, y, z as 0, 1, 2 (StackDirection lists each axis forward, then backward).
int stack_axis(StackDirection direction) { return static_cast<int>(direction) / 2; }
bool grows_forward(StackDirection direction) { return static_cast<int>(direction) % 2 == 0; }

Fixed& component(Vec3& v, int axis) { return axis == 0 ? v.x : (axis == 1 ? v.y : v.z); }
Fixed component(const Vec3& v, int axis) { return axis == 0 ? v.x : (axis == 1 ? v.y : v.z); }

// Offset of slot `index` of a row of `count` slots `pitch` apart, centred
// on 0, moved by `shift_halves` half pitches: (2 index - (count - 1) + shift) / 2 * pitch.
Fixed row_offset(int index, int count, int shift_halves, Fixed pitch) {
  return Fixed::from_ratio(2 * int64_t{index} - (int64_t{count} - 1) + shift_halves, 2) * pitch;
}

// One row of `count` boxes along x, centred on (centre_x, y, z).
void add_row_along_x(std::vector<SceneBody>& out, const std::string& prefix, int count, int shift_halves,
                     Vec3 half_extents, Fixed gap, Vec3 centre, const Substance& substance) {
  const Fixed pitch = half_extents.x + half_extents.x + gap;
  for (int j = 0; j < count; ++j) {
    const Vec3 position{centre.x + row_offset(j, count, shift_halves, pitch), centre.y, centre.z};
    add_box(out, prefix, half_extents, position, substance);
  }
}

// Uniform in [-1, 1) as a raw Q32.32 value: 33 random bits.
Fixed signed_unit(SplitMix64& rng) {
  const auto bits = static_cast<int64_t>(rng.next() >> 31);  // 0 .. 2^33 - 1
  return Fixed::from_raw(bits - (int64_t{1} << 32));
}

Vec3 random_in_box(SplitMix64& rng, Vec3 centre, Vec3 half_size) {
  const Fixed ux = signed_unit(rng), uy = signed_unit(rng), uz = signed_unit(rng);
  return {centre.x + half_size.x * ux, centre.y + half_size.y * uy, centre.z + half_size.z * uz};
}

// A random unit quaternion: four uniform components, redrawn while the
// vector is too short to normalise well (|q|^2 < 1/16), then normalised.
Quat random_orientation(SplitMix64& rng) {
  for (;;) {
    const Quat q{signed_unit(rng), signed_unit(rng), signed_unit(rng), signed_unit(rng)};
    const Fixed norm_sq = dot(q.vector(), q.vector()) + q.w * q.w;
    if (norm_sq >= Fixed::from_ratio(1, 16)) return normalize(q);
  }
}

Shape thrown_shape(const ThrowParams& params, ShapeType type) {
  Shape shape;
  shape.type = type;
  if (type == ShapeType::box) shape.half_extents = params.half_extents;
  if (type == ShapeType::sphere || type == ShapeType::capsule) shape.radius = params.radius;
  if (type == ShapeType::capsule) shape.half_height = params.half_height;
  return shape;
}

Fixed bounding_radius(const Shape& shape) {
  switch (shape.type) {
    case ShapeType::box: return length(shape.half_extents);
    case ShapeType::sphere: return shape.radius;
    case ShapeType::capsule: return shape.radius + shape.half_height;
    case ShapeType::hull: return shape.hull ? shape.hull->extent : Fixed{};  // (the generators make none)
    case ShapeType::plane:
    case ShapeType::mesh:
    case ShapeType::heightfield: break;
  }
  return Fixed{};
}

}  // namespace

Fixed stack_half_height(const StackParams& params) {
  return component(params.half_extents, stack_axis(params.direction));
}

std::vector<SceneBody> generate_stack(const StackParams& params) {
  std::vector<SceneBody> bodies;
  const int axis = stack_axis(params.direction);
  const Fixed half_height = stack_half_height(params);
  for (int i = 0; i < params.count; ++i) {
    Vec3 centre = params.position;
    Fixed& along = component(centre, axis);
    // Growing forward keeps the very expression of the upward stack (its
    // bits are in golden replays); backward subtracts the same exact rise.
    along = grows_forward(params.direction) ? level_centre_y(along, half_height, params.overlap, i)
                                            : along - level_centre_y(Fixed{}, half_height, params.overlap, i);
    add_box(bodies, params.name, params.half_extents, centre, params.substance);
  }
  return bodies;
}

std::vector<SceneBody> generate_pyramid(const PyramidParams& params) {
  std::vector<SceneBody> bodies;
  const Vec3 he = params.half_extents;
  for (int row = 0; row < params.base; ++row) {
    const Vec3 centre{params.position.x, level_centre_y(params.position.y, he.y, params.overlap, row), params.position.z};
    add_row_along_x(bodies, params.name, params.base - row, 0, he, params.gap, centre, params.substance);
  }
  return bodies;
}

std::vector<SceneBody> generate_wall(const WallParams& params) {
  std::vector<SceneBody> bodies;
  const Vec3 he = params.half_extents;
  const int rows = params.rows > 0 ? params.rows : params.base;
  for (int row = 0; row < rows; ++row) {
    const Vec3 centre{params.position.x, level_centre_y(params.position.y, he.y, params.overlap, row), params.position.z};
    const bool triangle = params.shape == WallShape::triangle;
    const int count = triangle ? params.base - row : params.base;
    const int shift_halves = triangle ? 0 : row % 2;
    add_row_along_x(bodies, params.name, count, shift_halves, he, params.gap, centre, params.substance);
  }
  return bodies;
}

std::vector<SceneBody> generate_jenga(const JengaParams& params) {
  std::vector<SceneBody> bodies;
  for (int level = 0; level < params.levels; ++level) {
    const bool along_x = level % 2 == 0;
    const Vec3 he = along_x ? params.half_extents : Vec3{params.half_extents.z, params.half_extents.y, params.half_extents.x};
    const Fixed y = level_centre_y(params.position.y, he.y, params.overlap, level);
    for (int k = -1; k <= 1; ++k) {
      // Side by side across the block: along z on x levels, along x on z levels.
      const Vec3 across = along_x ? Vec3{Fixed{}, Fixed{}, Fixed::from_int(2 * k) * he.z}
                                  : Vec3{Fixed::from_int(2 * k) * he.x, Fixed{}, Fixed{}};
      add_box(bodies, params.name, he, Vec3{params.position.x, y, params.position.z} + across, params.substance);
    }
  }
  return bodies;
}

std::vector<SceneBody> generate_dominoes(const DominoParams& params) {
  std::vector<SceneBody> bodies;
  const bool along_x = params.direction == RowDirection::plus_x || params.direction == RowDirection::minus_x;
  const bool forward = params.direction == RowDirection::plus_x || params.direction == RowDirection::plus_z;
  const Fixed sign = forward ? Fixed::one() : -Fixed::one();
  const Vec3 direction = along_x ? Vec3{sign, Fixed{}, Fixed{}} : Vec3{Fixed{}, Fixed{}, sign};
  const Vec3 he = along_x ? params.half_extents : Vec3{params.half_extents.z, params.half_extents.y, params.half_extents.x};
  const Fixed half_thickness = along_x ? he.x : he.z;
  const Vec3 up{Fixed{}, Fixed::one(), Fixed{}};
  for (int i = 0; i < params.count; ++i) {
    const Vec3 centre = params.position + direction * (Fixed::from_int(i) * params.spacing) + up * he.y;
    add_box(bodies, params.name, he, centre, params.substance);
  }
  if (!bodies.empty() && params.push != Fixed{}) {
    // Rotation about the first domino's front bottom edge: omega = push (up x
    // direction) tips the top forward; the centre moves as omega x r, with
    // r from the edge to the centre.
    const Vec3 omega = cross(up, direction) * params.push;
    const Vec3 edge_to_centre = up * he.y - direction * half_thickness;
    bodies.front().def.angular_velocity = omega;
    bodies.front().def.linear_velocity = cross(omega, edge_to_centre);
  }
  return bodies;
}

std::vector<SceneBody> generate_tables(const TableParams& params) {
  std::vector<SceneBody> bodies;
  const Vec3 top = params.top_half_extents, leg = params.leg_half_extents;
  // Body frame at the middle of the table's bounding box, height 2 (top + leg).
  const Fixed half_height = top.y + leg.y;
  const Fixed leg_x = top.x - leg.x, leg_z = top.z - leg.z;
  for (int i = 0; i < params.count; ++i) {
    const Fixed y = params.position.y + half_height + Fixed::from_int(2 * i) * half_height;
    std::vector<Shape> shapes{box_shape(top, {Fixed{}, leg.y, Fixed{}})};
    for (const Fixed x : {-leg_x, leg_x}) {
      for (const Fixed z : {-leg_z, leg_z}) shapes.push_back(box_shape(leg, {x, -top.y, z}));
    }
    bodies.push_back(dynamic_body(body_name(params.name, bodies.size()), {params.position.x, y, params.position.z},
                                  std::move(shapes), params.substance));
  }
  return bodies;
}

namespace {

// The bodies placed so far, filed by grid cell: a cell is as wide as the
// largest pair reach (twice the largest bounding radius), so a body can
// only overlap bodies in its own cell and the 26 around it, and a free spot
// is found in time linear in the count (the scan over every placed body
// took count^2 x draws: ~2 s for a crowded 10,000).
class PlacedGrid {
 public:
  explicit PlacedGrid(Fixed cell) : inverse_cell_(Fixed::one() / cell) {}

  // Whether a ball of `radius` at `position` clears every placed ball.
  bool free(Vec3 position, Fixed radius) const {
    const Cell c = cell_of(position);
    for (int32_t dx = -1; dx <= 1; ++dx) {
      for (int32_t dy = -1; dy <= 1; ++dy) {
        for (int32_t dz = -1; dz <= 1; ++dz) {
          const auto found = cells_.find(key({c.x + dx, c.y + dy, c.z + dz}));
          if (found == cells_.end()) continue;
          for (const Ball& other : found->second) {
            const Fixed reach = radius + other.radius;
            if (length_sq(position - other.position) < reach * reach) return false;
          }
        }
      }
    }
    return true;
  }

  void add(Vec3 position, Fixed radius) { cells_[key(cell_of(position))].push_back({position, radius}); }

 private:
  struct Cell {
    int32_t x, y, z;
  };
  struct Ball {
    Vec3 position;
    Fixed radius;
  };
  // Positions are within the envelope (+-16 km) and cells at least 0.02 m
  // wide: indices within +-2^20, 21 bits each once offset.
  Cell cell_of(Vec3 p) const {
    const auto index = [this](Fixed x) {
      const int64_t i = floor(x * inverse_cell_).raw() >> 32;
      return static_cast<int32_t>(std::clamp<int64_t>(i, -(int64_t{1} << 20) + 1, (int64_t{1} << 20) - 2));
    };
    return {index(p.x), index(p.y), index(p.z)};
  }
  static uint64_t key(Cell c) {
    const auto bits = [](int32_t i) { return static_cast<uint64_t>(i + (int32_t{1} << 20)); };
    return bits(c.x) << 42 | bits(c.y) << 21 | bits(c.z);
  }

  Fixed inverse_cell_;
  // Only looked up, never iterated: its order cannot reach the result.
  std::unordered_map<uint64_t, std::vector<Ball>> cells_;
};

}  // namespace

ThrowResult generate_throw(const ThrowParams& params) {
  constexpr int max_draws = 1000;
  ThrowResult result;
  SplitMix64 rng{params.seed};
  Fixed largest_radius;
  for (ShapeType type : params.shapes) largest_radius = max(largest_radius, bounding_radius(thrown_shape(params, type)));
  PlacedGrid placed(largest_radius * 2.0_fx);
  for (int i = 0; i < params.count; ++i) {
    const Shape shape = thrown_shape(params, params.shapes[static_cast<size_t>(i) % params.shapes.size()]);
    const Fixed radius = bounding_radius(shape);
    Vec3 position;
    bool free = false;
    for (int draw = 0; draw < max_draws && !free; ++draw) {
      position = random_in_box(rng, params.position, params.spread);
      free = placed.free(position, radius);
    }
    if (!free) {
      result.placed_all = false;
      return result;
    }
    placed.add(position, radius);
    SceneBody body = dynamic_body(body_name(params.name, result.bodies.size()), position, {shape}, params.substance);
    body.def.pose.orientation = random_orientation(rng);
    const Vec3 to_target = params.target - position;
    body.def.linear_velocity = normalize(to_target) * params.speed;
    result.bodies.push_back(std::move(body));
  }
  return result;
}

namespace {

// The distance from a box's centre to its support plane along the unit
// vector: |u.x| h.x + |u.y| h.y + |u.z| h.z (world axes).
Fixed extent_along(Vec3 half_extents, Vec3 unit) {
  return abs(unit.x) * half_extents.x + abs(unit.y) * half_extents.y + abs(unit.z) * half_extents.z;
}

SceneJoint chain_joint(std::string name, JointType type, uint32_t body_a, uint32_t body_b, Vec3 anchor, Vec3 axis) {
  SceneJoint joint;
  joint.name = std::move(name);
  joint.def.type = type;
  joint.def.anchor_a = anchor;
  if (type == JointType::hinge) joint.def.axis = axis;
  joint.body_a = body_a;
  joint.body_b = body_b;
  return joint;
}

}  // namespace

GeneratedStructure generate_chain(const ChainParams& params) {
  GeneratedStructure out;
  if (params.count < 1) return out;
  const Vec3 d = normalize(params.direction);
  Shape link;
  link.type = params.link == ChainLink::box ? ShapeType::box : ShapeType::sphere;
  if (link.type == ShapeType::box) link.half_extents = params.half_extents;
  if (link.type == ShapeType::sphere) link.radius = params.radius;
  const Fixed half_length = link.type == ShapeType::box ? extent_along(params.half_extents, d) : params.radius;
  const Fixed pitch = half_length + half_length + params.gap;
  // Link i's centre; the joint before it sits half a gap beyond link i - 1's surface.
  const auto centre = [&](int i) { return params.position + d * (Fixed::from_int(i) * pitch); };
  const Fixed centre_to_joint = half_length + params.gap * Fixed::from_ratio(1, 2);
  for (int i = 0; i < params.count; ++i) {
    out.bodies.push_back(dynamic_body(body_name(params.name, static_cast<size_t>(i)), centre(i), {link}, params.substance));
  }

  const Vec3 anchor_half_extents{0.05_fx, 0.05_fx, 0.05_fx};
  const Fixed anchor_reach = half_length + params.gap + extent_along(anchor_half_extents, d);
  const auto add_anchor = [&](const char* suffix, Vec3 position) {
    SceneBody anchor;
    anchor.name = params.name + suffix;
    anchor.def.type = BodyType::static_body;
    anchor.def.pose.position = position;
    anchor.def.shapes = {box_shape(anchor_half_extents)};
    anchor.def.material = params.substance.material;
    out.bodies.push_back(std::move(anchor));
    return static_cast<uint32_t>(out.bodies.size() - 1);
  };
  const auto joint_name = [&](int k) { return params.name + ".joint" + std::to_string(k); };
  const auto last = static_cast<uint32_t>(params.count - 1);
  const bool first_anchored = params.anchored != ChainAnchoring::none;
  const bool last_anchored = params.anchored == ChainAnchoring::both;
  const uint32_t anchor0 = first_anchored ? add_anchor(".anchor0", centre(0) - d * anchor_reach) : 0;
  const uint32_t anchor1 = last_anchored ? add_anchor(".anchor1", centre(params.count - 1) + d * anchor_reach) : 0;

  if (first_anchored) {
    out.joints.push_back(chain_joint(joint_name(0), JointType::point, anchor0, 0, centre(0) - d * centre_to_joint, {}));
  }
  for (int k = 1; k < params.count; ++k) {
    out.joints.push_back(chain_joint(joint_name(k), params.joint, static_cast<uint32_t>(k - 1),
                                     static_cast<uint32_t>(k), centre(k) - d * centre_to_joint, params.axis));
  }
  if (last_anchored) {
    out.joints.push_back(chain_joint(joint_name(params.count), JointType::point, last, anchor1,
                                     centre(params.count - 1) + d * centre_to_joint, {}));
  }
  return out;
}

namespace {

// Degrees -> radians as the scene reader turns them: mul_div(d, pi, 180).
Fixed radians(int degrees) { return mul_div(Fixed::from_int(degrees), scene_reader::pi_q32, Fixed::from_int(180)); }

// A ragdoll's part at scale 1, lengths in units of 0.1 mm, in the ragdoll's
// frame: origin at the pelvis centre, y up, facing +z, its left +x. Boxes:
// half extents (a, b, c); spheres: radius a; capsules: radius a, half
// height b (along y: every limb hangs straight down).
struct RagdollPart {
  const char* name;
  ShapeType type;
  int a, b, c;
  int x, y;           // the centre
  int mass_fraction;  // of the whole body, in 1/10000
};

// Proportions from Winter, "Biomechanics and Motor Control of Human
// Movement" (4th ed., 2009), Table 4.1 (Dempster's segment data) and
// Fig. 4.1 (segment lengths as fractions of the height H), for H = 1.8 m:
// sole 0, knee 0.285 H = 0.51, hip 0.530 H = 0.95, shoulder 0.818 H =
// 1.47 m; upper arm 0.186 H = 0.335, forearm + hand (0.146 + 0.108) H =
// 0.457, thigh 0.245 H = 0.44, shank + foot to the sole 0.285 H = 0.51;
// shoulder width 0.259 H = 0.466 m (the shoulder joints here 0.44 apart),
// hip joints 0.18 apart. Mass fractions (Winter Table 4.1): head and neck
// 8.1%, trunk 49.7% (here chest = thorax + abdomen 35.5%, pelvis 14.2%),
// upper arm 2.8%, forearm + hand 2.2%, thigh 10.0%, leg + foot 6.1%: 100%
// in all. Radii and depths are round numbers near a 75 kg man's girths
// (densities 780..1270 kg/m^3). Parts meeting at a joint are 1 cm apart,
// the anchor in the middle of the gap; elsewhere parts are at least 1 cm
// apart too (forearm to thigh 2 cm, thigh to thigh 4 cm), so none overlaps
// at creation. The comments give extents from the pelvis centre, which is
// 1.05 m above the soles (the head's top 1.785 m).
constexpr RagdollPart ragdoll_part_table[ragdoll_parts_count] = {
    {"pelvis", ShapeType::box, 1400, 950, 1000, 0, 0, 1420},             // y -0.095..0.095
    {"chest", ShapeType::box, 1600, 1900, 1100, 0, 2950, 3550},          // y 0.105..0.485
    {"head", ShapeType::sphere, 1200, 0, 0, 0, 6150, 810},               // y 0.495..0.735
    {"upper_arm.l", ShapeType::capsule, 500, 1125, 0, 2200, 2525, 280},  // y 0.09..0.415, x 0.17..0.27
    {"forearm.l", ShapeType::capsule, 400, 1850, 0, 2200, -1450, 220},   // y -0.37..0.08, x 0.18..0.26
    {"upper_arm.r", ShapeType::capsule, 500, 1125, 0, -2200, 2525, 280},
    {"forearm.r", ShapeType::capsule, 400, 1850, 0, -2200, -1450, 220},
    {"thigh.l", ShapeType::capsule, 700, 1450, 0, 900, -3200, 1000},  // y -0.535..-0.105, x 0.02..0.16
    {"shin.l", ShapeType::capsule, 500, 2025, 0, 900, -7975, 610},    // y -1.05..-0.545
    {"thigh.r", ShapeType::capsule, 700, 1450, 0, -900, -3200, 1000},
    {"shin.r", ShapeType::capsule, 500, 2025, 0, -900, -7975, 610},
};

// A ragdoll's joint: parts a (nearer the pelvis) and b, the anchor (0.1 mm,
// ragdoll frame, z = 0) and the axis (unit, ragdoll frame). Cones: swing
// and twist limits; hinges: limits (degrees).
struct RagdollJoint {
  const char* name;
  uint32_t a, b;
  JointType type;
  int ax, ay, az;
  int x, y;
  int swing, lower, upper;
};

// Hinge signs: a hinge's angle is b's turn about the axis relative to a,
// right-handed. A forearm hanging along -y turned about +x swings its hand
// toward -z, backward; so the elbow's axis is -x (forward bends are
// positive, 0..140) and the knee's +x (the foot goes back, 0..140).
// tests/replay/joint_scene_tests.cpp pushes both ways and checks.
constexpr RagdollJoint ragdoll_joint_table[ragdoll_joints_count] = {
    {"waist", 0, 1, JointType::cone, 0, 1, 0, 0, 1000, 30, -30, 30},
    {"neck", 1, 2, JointType::cone, 0, 1, 0, 0, 4900, 40, -60, 60},
    {"shoulder.l", 1, 3, JointType::cone, 0, -1, 0, 2200, 4200, 80, -60, 60},
    {"elbow.l", 3, 4, JointType::hinge, -1, 0, 0, 2200, 850, 0, 0, 140},
    {"shoulder.r", 1, 5, JointType::cone, 0, -1, 0, -2200, 4200, 80, -60, 60},
    {"elbow.r", 5, 6, JointType::hinge, -1, 0, 0, -2200, 850, 0, 0, 140},
    {"hip.l", 0, 7, JointType::cone, 0, -1, 0, 900, -1000, 70, -30, 30},
    {"knee.l", 7, 8, JointType::hinge, 1, 0, 0, 900, -5400, 0, 0, 140},
    {"hip.r", 0, 9, JointType::cone, 0, -1, 0, -900, -1000, 70, -30, 30},
    {"knee.r", 9, 10, JointType::hinge, 1, 0, 0, -900, -5400, 0, 0, 140},
};

}  // namespace

GeneratedStructure generate_ragdoll(const RagdollParams& params) {
  GeneratedStructure out;
  const Fixed s = params.scale;
  // n tenths of a millimetre at scale 1, scaled: rounded once, then once more.
  const auto length_of = [&](int n) { return Fixed::from_ratio(n, 10000) * s; };
  const Fixed whole_mass = Fixed::from_int(75) * s * s * s;  // kg
  const Fixed scale4 = s * s * s * s;
  const Quat q = params.orientation;
  for (int k = 0; k < params.count; ++k) {
    const Vec3 pelvis = params.position + params.spacing * Fixed::from_int(k);
    const Pose frame{pelvis, q};
    const auto base = static_cast<uint32_t>(out.bodies.size());
    const std::string prefix = params.name + "." + std::to_string(k) + ".";
    for (const RagdollPart& part : ragdoll_part_table) {
      Shape shape;
      shape.type = part.type;
      if (part.type == ShapeType::box) shape.half_extents = Vec3{length_of(part.a), length_of(part.b), length_of(part.c)};
      if (part.type != ShapeType::box) shape.radius = length_of(part.a);
      if (part.type == ShapeType::capsule) shape.half_height = length_of(part.b);
      SceneBody body;
      body.name = prefix + part.name;
      body.def.type = BodyType::dynamic;
      body.def.pose = {frame.apply(Vec3{length_of(part.x), length_of(part.y), Fixed{}}), q};
      body.def.shapes = {shape};
      body.def.mass = whole_mass * Fixed::from_ratio(part.mass_fraction, 10000);
      body.def.material = params.material;
      body.def.asleep = params.asleep;
      body.def.linear_damping = params.linear_damping;
      body.def.angular_damping = params.angular_damping;
      out.bodies.push_back(std::move(body));
    }
    for (const RagdollJoint& spec : ragdoll_joint_table) {
      SceneJoint joint;
      joint.name = prefix + spec.name;
      joint.body_a = base + spec.a;
      joint.body_b = base + spec.b;
      JointDef& def = joint.def;
      def.type = spec.type;
      def.anchor_a = frame.apply(Vec3{length_of(spec.x), length_of(spec.y), Fixed{}});
      def.axis = rotate(q, Vec3{Fixed::from_int(spec.ax), Fixed::from_int(spec.ay), Fixed::from_int(spec.az)});
      def.limited = true;
      def.lower_angle = radians(spec.lower);
      def.upper_angle = radians(spec.upper);
      if (spec.type == JointType::cone) def.swing_angle = radians(spec.swing);
      def.friction_torque = params.joint_friction * scale4;
      def.velocity_iterations = params.velocity_iterations;
      def.position_iterations = params.position_iterations;
      out.joints.push_back(std::move(joint));
    }
  }
  return out;
}

}  // namespace bitstep
