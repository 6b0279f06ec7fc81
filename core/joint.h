// Joints: constraints between two bodies that hold whatever the contacts
// do (core/README.md "Joints"). Built from the solver's constraint parts
// (solver_rows.h), warm-started like contacts, their drift removed by the
// split-impulse channel (or Baumgarte when the scene asks for it).
#pragma once

#include <array>
#include <cstdint>

#include "core/body.h"
#include "core/error.h"

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
  // Prismatic: b slides along an axis fixed in a, without turning relative
  // to a (three angular rows) or leaving the axis (two linear rows),
  // optionally within [lower_translation, upper_translation].
  slider,
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
  Vec3 axis;              // hinge: the axis; cone: the twist axis; slider: the axis b slides along (any length above 1e-3; made unit)
  // hinge: the angle is kept within [lower_angle, upper_angle] (a cone's
  // always is); slider: the translation within [lower_translation,
  // upper_translation].
  bool limited = false;
  Fixed lower_angle;      // rad, -pi..0: b's turn about the axis relative to a, from now
  Fixed upper_angle;      // rad, 0..pi
  Fixed swing_angle;      // rad, 0..pi: cone: how far b's twist axis may swing from a's
  Fixed lower_translation;  // m, -1000..0: slider: b's anchor along the axis from a's, from now
  Fixed upper_translation;  // m, 0..1000
  // A motor (hinge, slider): drives b relative to a at motor_speed (rad/s
  // about a hinge's axis, within the world's max_angular_speed; m/s along
  // a slider's, within max_linear_speed) with at most motor_max (N m; a
  // slider's N), 0..1e6. 0: no motor. World::set_joint_motor changes both.
  Fixed motor_speed;
  Fixed motor_max;
  // N s: a joint whose constraint impulse in a step exceeds this breaks
  // (is removed at the end of the step). 0: never.
  Fixed break_impulse;
  // N m: the most torque the joint's friction puts against b turning
  // relative to a (a hinge: about its axis; point and cone: about any
  // axis), 0..1e6. 0: none. Ropes have none. A slider's is a force (N)
  // against b sliding along its axis.
  Fixed friction_torque;
  // Solver passes the joint's island asks for (0: the world's
  // Settings::velocity_iterations, position_iterations), 0..1000, as
  // Jolt's constraints may: an island (bodies joined by contacts and
  // joints) runs the most that the world or any of its joints asks, the
  // passes beyond the world's over its rows alone (core/island_passes.h).
  uint16_t velocity_iterations = 0;
  uint16_t position_iterations = 0;
};

// Whether a joint of `type` can have this motor (JointDef::motor_speed,
// motor_max): refused for a type without motors or a setting out of
// range ("motor"), or fine.
Result<void> check_joint_motor(JointType type, Fixed speed, Fixed max);

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
  Fixed lower_translation, upper_translation;  // slider (m)
  Fixed motor_speed, motor_max;  // hinge, slider: the motor (JointDef's); motor_max 0: none
  Fixed break_impulse;
  Fixed friction_torque;
  uint16_t velocity_iterations = 0, position_iterations = 0;  // 0: the world's
  // Accumulated impulses: the point rows (N s, world axes; a slider's two
  // rows across its axis), the rope's, the hinge's two angular rows (N m
  // s; a cone's swing row in the first) and its limit's (a cone's twist
  // limit; a slider's translation limit, N s), a slider's three angular
  // rows (N m s, world axes), and the motor's (N m s; a slider's N s).
  Vec3 point_impulse;
  Fixed distance_impulse;
  Fixed hinge_impulse[2];
  Fixed limit_impulse;
  Vec3 angular_impulse;
  Fixed motor_impulse;
};

// The most a joint keeps of any accumulated impulse, per component (N s;
// the angular rows' N m s alike): 2^27, above the largest a step gives
// at the envelope's bounds (1e5 kg stopped from twice the speed clamp,
// 2 x 500 m/s: 1e8 N s) and far from the range. Joints that cannot all
// hold (two hinges on one pair of bodies whose axes differ in one body's frame)
// trade ever larger impulses pass after pass: every row's accumulation is
// held within the bound as it goes (bounded_total, joint_parts.h), and
// World::step clamps what a joint keeps once more (a slider's projection
// of its point impulse across its axis can lengthen a component).
inline constexpr Fixed max_joint_impulse = Fixed::from_raw(int64_t{1} << 59);

// Every component of the impulses a joint keeps for its next warm start.
inline std::array<Fixed*, 11> kept_impulses(Joint& joint) {
  return {&joint.point_impulse.x,   &joint.point_impulse.y,   &joint.point_impulse.z, &joint.distance_impulse,
          &joint.hinge_impulse[0],  &joint.hinge_impulse[1],  &joint.limit_impulse,   &joint.angular_impulse.x,
          &joint.angular_impulse.y, &joint.angular_impulse.z, &joint.motor_impulse};
}

// Whether a joint as a world keeps it is one World::create_joint makes
// between bodies a and b: create_joint's own checks of the numbers, unit
// axes, anchors within its reach, the impulses within max_joint_impulse;
// refused with the field and why. The state readers' check of a joint
// read back (replay/state_description.h).
Result<void> check_joint_state(const Joint& joint, const Body& a, const Body& b);

}  // namespace bitstep
