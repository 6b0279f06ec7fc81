// Joints: constraints between two bodies that hold whatever the contacts
// do (core/README.md "Joints"). Built from the solver's constraint parts
// (solver_rows.h), warm-started like contacts, their drift removed by the
// split-impulse channel (or Baumgarte when the scene asks for it).
#pragma once

#include <cstdint>

#include "core/body.h"

namespace bitstep {

enum class JointType : uint8_t {
  // Ball and socket: a point of a and a point of b kept together (three
  // linear rows solved as one 3x3 block).
  point,
  // A rope: the anchors at most `length` apart; slack allowed, taut holds.
  max_distance,
  // A point joint whose bodies turn relative to each other about one axis
  // only (two angular rows), optionally within [lower_angle, upper_angle].
  hinge,
  // A ragdoll's shoulder or hip: a point joint whose twist axis (on b)
  // stays within swing_angle of a's copy of it (a cone) and whose twist
  // about it stays within [lower_angle, upper_angle].
  cone,
};

struct JointId {
  uint32_t index = 0;
  uint32_t generation = 0;
  friend bool operator==(JointId, JointId) = default;
};

// The most solver passes a joint may ask for (JointDef::velocity_iterations).
inline constexpr uint16_t max_joint_iterations = 1000;

// A joint as a game or a scene asks for it, in the world frame at the
// moment of creation (the scene reader turns body-frame anchors into world
// ones at the bodies' starting poses).
struct JointDef {
  JointType type = JointType::point;
  BodyId body_a, body_b;  // two different live bodies, at least one of them dynamic
  Vec3 anchor_a;          // m: the joined point on a (point, hinge: on both)
  Vec3 anchor_b;          // m: max_distance: the rope's end on b (the others use anchor_a)
  Fixed length;           // m: max_distance: the rope's length; 0 takes the anchors' distance now
  Vec3 axis;              // hinge: the axis; cone: the twist axis (any length above 1e-3; made unit)
  bool limited = false;   // hinge: the angle is kept within [lower_angle, upper_angle] (a cone's always is)
  Fixed lower_angle;      // rad, -pi..0: b's turn about the axis relative to a, from now
  Fixed upper_angle;      // rad, 0..pi
  Fixed swing_angle;      // rad, 0..pi: cone: how far b's twist axis may swing from a's
  // N s: a joint whose constraint impulse in a step exceeds this breaks
  // (is removed at the end of the step). 0: never.
  Fixed break_impulse;
  // N m: the most torque the joint's friction puts against b turning
  // relative to a (a hinge: about its axis; point and cone: about any
  // axis), 0..1e6. 0: none. Ropes have none.
  Fixed friction_torque;
  // Solver passes the joint's island asks for (0: the world's
  // Settings::velocity_iterations, position_iterations), 0..1000, as
  // Jolt's constraints may: an island (bodies joined by contacts and
  // joints) runs the most that the world or any of its joints asks, the
  // passes beyond the world's over its rows alone (core/island_passes.h).
  uint16_t velocity_iterations = 0;
  uint16_t position_iterations = 0;
};

// A joint as the world keeps it (state: hashed, saved, dumped). Anchors
// and axes in each body's frame (about its centre of mass), and the
// impulses accumulated last step, which warm-start the next.
struct Joint {
  bool alive = false;
  uint32_t generation = 0;
  JointType type = JointType::point;
  uint32_t body_a = 0, body_b = 0;  // slots; removing either body removes the joint
  Vec3 local_anchor_a, local_anchor_b;
  Vec3 local_axis_a, local_axis_b;            // hinge: the axis in each body's frame
  Vec3 local_reference_a, local_reference_b;  // hinge: a unit vector normal to the axis, equal at creation
  Fixed length;
  bool limited = false;
  Fixed lower_angle, upper_angle;
  Fixed swing_angle;  // cone
  Fixed break_impulse;
  Fixed friction_torque;
  uint16_t velocity_iterations = 0, position_iterations = 0;  // 0: the world's
  // Accumulated impulses: the point rows (N s, world axes), the rope's,
  // the hinge's two angular rows (N m s; a cone's swing row in the first)
  // and its limit's (a cone's twist limit).
  Vec3 point_impulse;
  Fixed distance_impulse;
  Fixed hinge_impulse[2];
  Fixed limit_impulse;
};

}  // namespace bitstep
