// The character controller's step (core/character.h).
#include "core/character.h"

#include <optional>
#include <vector>

#include "core/collide.h"
#include "core/manifold.h"
#include "core/query.h"
#include "core/world.h"

namespace bitstep {

namespace character_motion {

// m: the gap the character keeps from what it touches, so that each cast
// starts outside every shape (a cast that starts touching meets it at 0).
constexpr Fixed skin = 0.01_fx;
constexpr int max_slides = 4;
// m: moves shorter than this are not cast.
constexpr Fixed least_move = 0.0001_fx;

struct Hit {
  Fixed distance;  // m travelled before touching, skin not yet taken off
  Vec3 normal;     // the surface's, toward the character
  Vec3 point;
  BodyId body;
};

// The first non-sensor body the character's capsule meets moving from
// `from` by `move`, or none.
std::optional<Hit> cast(const Character& c, const WorldQuery& query, const World& world, Vec3 from, Vec3 move) {
  const Fixed length_of_move = length(move);
  if (length_of_move < least_move) return std::nullopt;
  std::vector<QueryHit> hits;
  query.cast_shape_all(character_shape(c.def), {from, {}}, move, hits, {c.def.collides_with, {}});
  for (const QueryHit& h : hits) {
    const Body& body = world.bodies()[h.body.index];
    if (body.sensor) continue;
    return Hit{h.fraction * length_of_move, h.normal, h.point, h.body};
  }
  return std::nullopt;
}

bool walkable(const Character& c, Vec3 normal) { return normal.y >= c.def.max_slope_cos; }

// A steep surface met on the ground acts as a wall: its normal made level.
Vec3 as_met(const Character& c, Vec3 normal, bool grounded) {
  if (!grounded || walkable(c, normal) || normal.y <= Fixed{}) return normal;
  return normalize_or({normal.x, Fixed{}, normal.z}, normal);
}

// v without its part into the surface of normal n (none if it leaves it).
Vec3 without_into(Vec3 v, Vec3 n) {
  const Fixed into = dot(v, n);
  return into < Fixed{} ? v - n * into : v;
}

// Pushes a dynamic body met along the move: the impulse that would stop
// the character's approach, at most max_push_force dt.
void push(const Character& c, World& world, const Hit& hit, Vec3 velocity, Fixed dt) {
  const Body& body = world.bodies()[hit.body.index];
  if (body.type != BodyType::dynamic) return;
  const Fixed approach = -dot(velocity, hit.normal);
  if (approach <= Fixed{}) return;
  const Fixed impulse = min(c.def.mass * approach, c.def.max_push_force * dt);
  world.apply_impulse(hit.body, hit.normal * -impulse, hit.point);
}

// The walkable top beyond an edge the capsule's round bottom rests on (its
// normal leans there, though the ground is level): a ray down 10 cm from
// 5 cm above `point`, 2 cm past it along the level direction `toward`.
std::optional<QueryHit> top_beyond(const Character& c, const WorldQuery& query, Vec3 point, Vec3 toward) {
  const Vec3 level = normalize_or({toward.x, Fixed{}, toward.z}, {});
  if (level == Vec3{}) return std::nullopt;
  const Vec3 from = Vec3{point.x, point.y + 0.05_fx, point.z} + level * 0.02_fx;
  std::optional<QueryHit> top = query.cast_ray(from, {Fixed{}, -0.1_fx, Fixed{}}, {c.def.collides_with, {}});
  if (!top || !walkable(c, top->normal)) return std::nullopt;
  return top;
}

// Whether `hit`, met on the ground by the capsule centred at `centre`
// moving along `move`, is the edge of a step it can walk up: above the
// feet by at most step_height, with a walkable top beyond whose normal is
// not the one met (an edge under the round bottom, not a ramp's face).
bool step_up_edge(const Character& c, const WorldQuery& query, const Hit& hit, Vec3 centre, Vec3 move) {
  const Fixed feet = centre.y - c.def.half_height - c.def.radius;
  const Fixed highest = feet + c.def.step_height + skin;
  if (hit.point.y <= feet + skin || hit.point.y > highest) return false;
  const std::optional<QueryHit> top = top_beyond(c, query, hit.point, move);
  return top && dot(top->normal, hit.normal) < 0.999_fx && top->point.y <= highest;
}

// Moves the character by `move`, sliding along what it meets: where it
// ends, its velocity without the parts into what it met, and whether a wall
// (as met) stopped part of the move.
struct Slide {
  Vec3 position;
  Vec3 velocity;
  bool blocked = false;  // a wall (as met) stopped part of the move
};

Slide slide(const Character& c, const WorldQuery& query, World& world, Vec3 from, Vec3 move, Vec3 velocity,
            bool grounded, Fixed dt, bool pushes) {
  Slide s{from, velocity, false};
  for (int i = 0; i < max_slides; ++i) {
    const std::optional<Hit> hit = cast(c, query, world, s.position, move);
    if (!hit) {
      s.position = s.position + move;
      break;
    }
    const Fixed total = length(move);
    const Fixed travel = max(Fixed{}, hit->distance - skin);
    const Vec3 direction = move / total;
    s.position = mul_add(direction, travel, s.position);
    if (pushes) push(c, world, *hit, s.velocity, dt);
    Vec3 n = as_met(c, hit->normal, grounded);
    // A step's edge is a wall too, however its slant under the round
    // bottom leans: the move then goes up the step whole (move_character).
    // Slid over the slant, part of the walk turned upward, and a flight of
    // 0.2 m steps slowed a 2 m/s walk by a tenth.
    if (grounded && walkable(c, n) && step_up_edge(c, query, *hit, s.position, move)) {
      n = normalize_or({n.x, Fixed{}, n.z}, n);
    }
    if (n.y < c.def.max_slope_cos) s.blocked = true;
    move = without_into(direction * (total - travel), n);
    s.velocity = without_into(s.velocity, n);
  }
  return s;
}

// What lies within `reach` below the capsule at `at`.
std::optional<Hit> below(const Character& c, const WorldQuery& query, const World& world, Vec3 at, Fixed reach) {
  return cast(c, query, world, at, {Fixed{}, -reach, Fixed{}});
}

// Whether `hit` (below the capsule centred at `centre`, its normal not
// walkable) is the edge of a step: walkable ground on one side of it, the
// far side (walking up onto it) or the near side (walking off it).
bool on_step_edge(const Character& c, const WorldQuery& query, const Hit& hit, Vec3 centre) {
  if (hit.normal.y <= Fixed{}) return false;
  const Vec3 out = hit.point - centre;
  return top_beyond(c, query, hit.point, out).has_value() || top_beyond(c, query, hit.point, -out).has_value();
}

// Whether the floor found below a raised move is a step's top, at most
// step_height above the feet at `feet`: walkable, or an edge with such a top
// beyond it.
bool lands_on_step(const Character& c, const WorldQuery& query, const Hit& floor, Vec3 level_move, Fixed feet) {
  if (floor.point.y > feet + c.def.step_height + skin) return false;
  if (walkable(c, floor.normal)) return true;
  if (floor.normal.y <= Fixed{}) return false;
  const std::optional<QueryHit> top = top_beyond(c, query, floor.point, level_move);
  return top && top->point.y <= feet + c.def.step_height + skin;
}

// Riding: the ground body's change of pose since the character found it.
void ride(Character& c, const World& world) {
  if (c.ground == GroundState::in_air) return;
  const BodyId g = c.ground_body;
  if (g.index >= world.bodies().size()) return;
  const Body& body = world.bodies()[g.index];
  if (!body.alive || body.generation != g.generation) return;
  const Pose& then = c.ground_pose;
  const Pose& now = body.pose;
  if (then.position == now.position && then.orientation == now.orientation) return;
  // x' = p_now + R_now R_then^-1 (x - p_then)
  const Vec3 local = rotate_inverse(then.orientation, c.position - then.position);
  const Vec3 target = now.position + rotate(now.orientation, local);
  const Vec3 turned = rotate(now.orientation, rotate_inverse(then.orientation, c.facing));
  c.facing = normalize_or({turned.x, Fixed{}, turned.z}, c.facing);
  c.position = target;  // (carried into a wall, depenetrate pushes it out next)
}

// Out of whatever overlaps the capsule (a platform or a body that moved into
// it, a spawn on top of it): along the deepest overlap's normal by its depth
// and the skin, twice at most.
void depenetrate(Character& c, const WorldQuery& query, const World& world) {
  const Shape capsule = character_shape(c.def);
  std::vector<ShapeOverlap> overlaps;
  for (int pass = 0; pass < 2; ++pass) {
    overlaps.clear();
    query.overlap_shape(capsule, {c.position, {}}, overlaps, {c.def.collides_with, {}});
    Fixed deepest;
    Vec3 out;
    for (const ShapeOverlap& o : overlaps) {
      const Body& body = world.bodies()[o.body.index];
      if (body.sensor) continue;
      const Shape& shape = body.shapes[o.shape];
      Manifold m;
      if (collide({&capsule, {c.position, {}}}, {&shape, compose(body.pose, shape.local)}, Fixed{}, m) == 0) continue;
      for (int k = 0; k < m.point_count; ++k) {
        const ContactPoint& p = m.points[static_cast<size_t>(k)];
        if (p.depth > deepest) {
          deepest = p.depth;
          out = -m.normal;  // the normal runs from the capsule into the other shape
        }
      }
    }
    if (deepest == Fixed{}) return;
    c.position = mul_add(out, deepest + skin, c.position);
  }
}

void find_ground(Character& c, const WorldQuery& query, const World& world) {
  const std::optional<Hit> hit = below(c, query, world, c.position, skin + skin);
  if (!hit || hit->normal.y <= Fixed{}) {
    c.ground = GroundState::in_air;
    c.ground_body = {};
    c.ground_normal = {};
    return;
  }
  // Resting on an edge (the normal leans toward the character) with
  // walkable ground beyond it (a step's top) is standing.
  const bool on_edge = !walkable(c, hit->normal) && on_step_edge(c, query, *hit, c.position);
  c.ground = walkable(c, hit->normal) || on_edge ? GroundState::on_ground : GroundState::on_steep_slope;
  c.ground_body = hit->body;
  c.ground_normal = on_edge ? Vec3{Fixed{}, Fixed::one(), Fixed{}} : hit->normal;
  c.ground_pose = world.bodies()[hit->body.index].pose;
}

}  // namespace character_motion

Result<void> check_character(const CharacterDef& def) {
  const auto within = [](Fixed v, Fixed lo, Fixed hi) { return lo <= v && v <= hi; };
  const Fixed far = 16000.0_fx;
  if (abs(def.position.x) > far || abs(def.position.y) > far || abs(def.position.z) > far) {
    return Error{"position", "outside +-16000 m"};
  }
  if (!within(def.radius, 0.05_fx, 5.0_fx)) return Error{"radius", "outside 0.05..5 m"};
  if (!within(def.half_height, Fixed{}, 10.0_fx)) return Error{"half_height", "outside 0..10 m"};
  if (!within(def.max_slope_cos, Fixed{}, Fixed::one())) return Error{"max_slope", "outside 0..90 degrees"};
  if (!within(def.step_height, Fixed{}, def.radius + def.half_height)) {
    return Error{"step_height", "outside 0 m..its half height"};
  }
  if (!within(def.jump_speed, Fixed{}, 100.0_fx)) return Error{"jump_speed", "outside 0..100 m/s"};
  if (!within(def.air_acceleration, Fixed{}, 1000.0_fx)) return Error{"air_acceleration", "outside 0..1000 m/s^2"};
  if (!within(def.mass, 0.1_fx, 10000.0_fx)) return Error{"mass", "outside 0.1..10000 kg"};
  if (!within(def.max_push_force, Fixed{}, 1000000.0_fx)) return Error{"max_push_force", "outside 0..1e6 N"};
  if (def.facing.y != Fixed{} || abs(length(def.facing) - Fixed::one()) > 0.001_fx) {
    return Error{"facing", "not a level unit vector"};
  }
  return {};
}

Shape character_shape(const CharacterDef& def) {
  Shape shape;
  shape.type = ShapeType::capsule;
  shape.radius = def.radius;
  shape.half_height = def.half_height;
  return shape;
}

void find_character_ground(Character& c, const WorldQuery& query, const World& world) {
  character_motion::find_ground(c, query, world);
}

void move_character(Character& c, const WorldQuery& query, World& world, Fixed dt) {
  using namespace character_motion;
  if (!c.alive) return;
  ride(c, world);
  depenetrate(c, query, world);
  const bool grounded = c.ground == GroundState::on_ground;
  const Vec3 desired{c.controls.velocity.x, Fixed{}, c.controls.velocity.z};
  const Vec3 gravity = world.settings().gravity;
  bool jumped = false;
  if (grounded) {
    c.velocity = desired;
    if (c.controls.jump) {
      c.velocity.y = c.def.jump_speed;
      jumped = true;
    }
  } else {
    // Off the ground: gravity, and the level velocity turned toward the
    // desired one by at most air_acceleration dt.
    const Vec3 level{c.velocity.x, Fixed{}, c.velocity.z};
    const Vec3 change = desired - level;
    const Fixed most = c.def.air_acceleration * dt;
    const Fixed size = length(change);
    const Vec3 step_change = size > most ? change * (most / size) : change;
    c.velocity = c.velocity + step_change + gravity * dt;
  }
  const bool on_ground_now = grounded && !jumped;
  const Vec3 start = c.position;
  Slide moved = slide(c, query, world, start, c.velocity * dt, c.velocity, on_ground_now, dt, true);

  // Steps up: a grounded level move blocked by a wall, tried again raised.
  if (on_ground_now && moved.blocked && c.def.step_height > Fixed{}) {
    const Vec3 up{Fixed{}, c.def.step_height, Fixed{}};
    const std::optional<Hit> ceiling = cast(c, query, world, start, up);
    const Fixed rise = ceiling ? max(Fixed{}, ceiling->distance - skin) : c.def.step_height;
    const Vec3 raised{start.x, start.y + rise, start.z};
    const Vec3 level_move{c.velocity.x * dt, Fixed{}, c.velocity.z * dt};
    const Slide over = slide(c, query, world, raised, level_move, c.velocity, true, dt, false);
    const std::optional<Hit> floor = below(c, query, world, over.position, rise + skin + skin);
    const Vec3 gained = over.position - start, before = moved.position - start;
    const Fixed progress = dot({gained.x, Fixed{}, gained.z}, {gained.x, Fixed{}, gained.z});
    const Fixed progress_before = dot({before.x, Fixed{}, before.z}, {before.x, Fixed{}, before.z});
    const Fixed feet = start.y - c.def.half_height - c.def.radius;
    if (floor && lands_on_step(c, query, *floor, level_move, feet) && progress > progress_before) {
      moved.position = {over.position.x, over.position.y - max(Fixed{}, floor->distance - skin), over.position.z};
      moved.velocity = {over.velocity.x, Fixed{}, over.velocity.z};
    }
  }
  c.position = moved.position;
  c.velocity = moved.velocity;

  // Steps down: still on the ground after walking off an edge or down a slope.
  if (on_ground_now && c.def.step_height > Fixed{}) {
    const std::optional<Hit> floor = below(c, query, world, c.position, c.def.step_height + skin + skin);
    if (floor && floor->distance > skin && (walkable(c, floor->normal) || on_step_edge(c, query, *floor, c.position))) {
      c.position.y = c.position.y - (floor->distance - skin);
    }
  }
  find_ground(c, query, world);
  if (c.ground == GroundState::on_ground && !jumped) c.velocity.y = Fixed{};
}

}  // namespace bitstep
