// A character controller: a kinematic upright capsule that a game moves with
// a desired velocity and a jump, the way Jolt's CharacterVirtual and
// Bullet's btKinematicCharacterController do. It is not a body: no solver
// pushes it; it moves itself by shape casts against the world's bodies
// (move and slide), so it never sinks, jitters or is knocked over, and it
// acts on dynamic bodies only through bounded pushes.
//
// Each step (World::step, after the bodies have moved):
//   1. Riding: on the ground of a moving body, the character moves with it
//      by the exact change of that body's pose since the last step (a
//      platform that turns turns the character's facing too). Then out of
//      whatever overlaps it, along the deepest contact's normal.
//   2. Velocity: on walkable ground the horizontal velocity is the desired
//      one and the vertical is 0, or the jump speed on a jump; on a steep
//      slope or in the air gravity acts and the horizontal velocity turns
//      toward the desired one by at most air_acceleration dt.
//   3. Move and slide: up to `max_slides` casts along what is left of
//      velocity dt; at each hit the character stops `skin` short, the rest
//      of the move and the velocity lose their part into the surface, and
//      a dynamic body hit is pushed (an impulse of at most max_push_force dt
//      along the move). On the ground a steep surface is a wall: its normal
//      is taken level, so the character cannot walk up it.
//   4. Steps: a move on the ground blocked by a wall is tried again raised
//      by step_height, then lowered onto what lies beneath; it is kept if
//      it went farther and lands on walkable ground. Walking down (stairs,
//      slopes), a character that was on the ground is lowered by up to
//      step_height onto walkable ground below.
//   5. Ground state: a short cast down (2 skin) finds walkable ground
//      (on_ground: its body, normal and pose kept for riding), a steep
//      slope (on_steep_slope) or nothing (in_air).
// Every quantity is fixed point and every query deterministic: the same
// bits on every build.
#pragma once

#include <array>
#include <cstdint>

#include "core/body.h"
#include "core/error.h"
#include "core/pose.h"
#include "fixed/decimal.h"

namespace bitstep {

using namespace bitstep::literals;

struct CharacterDef {
  Vec3 position;               // m, the capsule's centre
  Fixed radius = 0.3_fx;       // m
  Fixed half_height = 0.6_fx;  // m, of the capsule's inner segment (total height 2 (radius + half_height))
  // The steepest walkable ground: its normal's y at least this (cos of the
  // slope's angle; 0.7071: 45 degrees).
  Fixed max_slope_cos = 0.7071_fx;
  Fixed step_height = 0.3_fx;                   // m, the highest step it walks up (and down)
  Fixed jump_speed = 5.0_fx;                    // m/s
  Fixed air_acceleration = 5.0_fx;              // m/s^2, toward the desired velocity off the ground
  Fixed mass = 80.0_fx;                         // kg, for its pushes
  Fixed max_push_force = 400.0_fx;              // N, the most it pushes a dynamic body with
  uint32_t collides_with = UINT32_MAX;          // the layers of the bodies it meets (CollisionFilter)
  Vec3 facing{Fixed{}, Fixed{}, Fixed::one()};  // unit, level
};

// What a game asks of a character each step (a `move` input).
struct CharacterControls {
  Vec3 velocity;      // m/s, desired, level (its y is ignored)
  bool jump = false;  // taken when on walkable ground
};

enum class GroundState : uint8_t { on_ground, on_steep_slope, in_air };
inline constexpr std::array<const char*, 3> ground_state_names = {"on_ground", "on_steep_slope", "in_air"};

struct Character {
  CharacterDef def;  // its shape and limits, as created (position and facing: the initial ones)
  Vec3 position;     // m, the capsule's centre
  Vec3 velocity;     // m/s, its own (riding a platform adds the platform's motion)
  Vec3 facing;       // unit, level
  CharacterControls controls;
  GroundState ground = GroundState::in_air;
  BodyId ground_body;  // on_ground or on_steep_slope: what it stands on
  Vec3 ground_normal;  // unit
  Pose ground_pose;    // the ground body's pose when it was found (riding follows its change)
  bool alive = true;
};

struct CharacterId {
  uint32_t index = UINT32_MAX;
  friend bool operator==(const CharacterId&, const CharacterId&) = default;
};

// The definition's refusals, with the field: "radius: outside 0.05..5 m".
Result<void> check_character(const CharacterDef& def);

// The character's upright capsule at `position`.
Shape character_shape(const CharacterDef& def);

class World;
class WorldQuery;

// One step of the character (the steps above) in `world`, whose bodies have
// just moved; `query` is built over them. Pushes go to dynamic bodies as
// impulses (applied at once: the next step sees them).
void move_character(Character& character, const WorldQuery& query, World& world, Fixed dt);

// Its ground state where it stands (step 5 above alone): a character
// created on the ground stands from its first step, not one step in the air.
void find_character_ground(Character& character, const WorldQuery& query, const World& world);

}  // namespace bitstep
