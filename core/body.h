// Bodies: handles, definitions with defaults, and materials.
#pragma once

#include <cstdint>
#include <vector>

#include "core/settings.h"
#include "core/shape.h"
#include "fixed/mat33.h"

namespace bitstep {

// A handle into the world's dense body arrays; the generation tells a
// removed body's handle from its slot's next occupant.
struct BodyId {
  uint32_t index = UINT32_MAX;
  uint32_t generation = 0;
  friend bool operator==(BodyId, BodyId) = default;
  bool valid() const { return index != UINT32_MAX; }
};

enum class BodyType : uint8_t {
  static_body,  // never moves, infinite mass
  kinematic,    // moved by its velocity (set by inputs), infinite mass
  dynamic,      // moved by forces and contacts
};

// Friction, restitution and rolling resistance. A pair combines by the
// geometric mean of the frictions and of the rolling resistances, and the
// maximum of the restitutions (Box2D's mixing rules).
struct Material {
  Fixed static_friction = 0.5_fx;   // 1, stick while |friction impulse| <= mu_s * normal impulse
  Fixed dynamic_friction = 0.5_fx;  // 1, sliding friction impulse = mu_d * normal impulse
  Fixed restitution = 0.0_fx;       // 1, bounce factor above Settings::restitution_threshold
  // 1, c: a sphere or capsule of radius r resists rolling on what it touches
  // with a torque of at most c r N (N the normal force), as a wheel's
  // rolling resistance force c N at the axle. It holds a roller on a slope
  // of up to ~c rad and slows a free roll by ~c g (5/7 for a ball). Not 0
  // by default: without it rolling is neutral, and a roller on sub-micron
  // tilts (a pile's overlaps) rolls down them for ever, gaining energy.
  // 0.001 is a steel ball on steel; a 5 m/s roll loses 0.07 m/s in 10 s.
  Fixed rolling_resistance = 0.001_fx;
};

// Which bodies collide: a body is on `layers` (bits 0..31) and collides
// with bodies on `collides_with`. Two bodies touch only when each is on a
// layer the other collides with (Box2D's category and mask bits). A pair
// they keep apart makes no contact, and queries can skip layers too
// (core/query.h). Set at creation.
struct CollisionFilter {
  uint32_t layers = 1;
  uint32_t collides_with = UINT32_MAX;
  friend bool operator==(const CollisionFilter&, const CollisionFilter&) = default;
};
inline bool collide_together(const CollisionFilter& a, const CollisionFilter& b) {
  return (a.layers & b.collides_with) != 0 && (b.layers & a.collides_with) != 0;
}

struct BodyDef {
  BodyType type = BodyType::dynamic;
  Pose pose;  // of the body frame, in which the shapes' local poses are given
  Vec3 linear_velocity;   // m/s
  Vec3 angular_velocity;  // rad/s, world frame
  std::vector<Shape> shapes;
  // Mass from density (kg/m^3) unless mass (kg) is set (> 0): then the
  // density is scaled to give that mass.
  Fixed density = 1000.0_fx;
  Fixed mass;
  Material material;
  Fixed linear_damping;   // 1/s
  Fixed angular_damping;  // 1/s
  bool asleep = false;    // start asleep (dynamic, at rest): a wall built to stand (as in Kenwright's engine)
  CollisionFilter filter;
  // Its shapes report what overlaps them (core/sensor.h) and make no
  // contact: a trigger volume. They still give the body its mass.
  bool sensor = false;
};

// Speed clamps (core/envelope.h, speed_limits).
struct SpeedLimits {
  Fixed linear;   // m/s (Settings::max_linear_speed)
  Fixed angular;  // rad/s (Settings::max_angular_speed)
};

// What a body is made of, in dense per-slot arrays (structure of records).
struct Body {
  BodyType type = BodyType::dynamic;
  bool alive = false;
  uint32_t generation = 0;
  Pose pose;  // of the centre of mass: shapes were re-based onto it at creation
  Vec3 linear_velocity;
  Vec3 angular_velocity;
  Vec3 force;   // N, accumulated until the next step
  Vec3 torque;  // N m
  Fixed inverse_mass;             // 1/kg, 0 for static and kinematic bodies
  Mat33 inertia_local;            // kg m^2, body frame (for reports)
  Mat33 inverse_inertia_local;    // 1/(kg m^2), body frame
  Mat33 inverse_inertia_world;    // R I^-1 R^T, refreshed each step
  Material material;
  Fixed linear_damping;
  Fixed angular_damping;
  std::vector<Shape> shapes;      // local poses relative to the centre of mass
  CollisionFilter filter;
  bool sensor = false;
  // Sleep (core/sleep.h). A sleeping body is not integrated, has zero
  // velocity, and is immovable to the bodies that touch it.
  bool asleep = false;
  Fixed sleep_motion;             // m^2/s^2, motion: the recently-weighted average of v.v + w.w
  uint32_t sleepy_steps = 0;      // steps in a row below sleep_epsilon (motion) or within tolerance (still)
  Pose sleep_reference;           // still: the pose the body has stayed near
  // Not state: which creation made this body, unique over its world
  // object's life (a rollback does not bring a number back); 0 when dead.
  // A rollback state (replay/rollback_state.h) keeps a body's static data
  // once per serial.
  uint64_t serial = 0;
  // Not state: the envelope's clamps for this body's mass and shapes
  // (speed_limits, at most the envelope's speeds), set by World when the
  // body is created or read; the step clamps to the lower of these and the
  // settings' (Body::limits_in).
  SpeedLimits limits{envelope::max_linear_speed, envelope::max_angular_speed};
  SpeedLimits limits_in(const Settings& settings) const {
    return {min(limits.linear, settings.max_linear_speed), min(limits.angular, settings.max_angular_speed)};
  }
};

// Moved by the integrator and the solver this step.
inline bool is_awake_dynamic(const Body& body) {
  return body.alive && body.type == BodyType::dynamic && !body.asleep;
}

// Can change its contacts this step: an awake dynamic body or a kinematic one
// with a velocity. Contacts between bodies that cannot are kept as they are.
inline bool moves(const Body& body) {
  if (!body.alive) return false;
  if (body.type == BodyType::kinematic) return body.linear_velocity != Vec3{} || body.angular_velocity != Vec3{};
  return is_awake_dynamic(body);
}

// Its contacts are found this step: it moves, or it was created asleep and
// has not had its contacts found yet (sleepy_steps 0: a body that falls
// asleep has counted at least one sleepy step).
inline bool needs_contacts(const Body& body) { return moves(body) || (body.asleep && body.sleepy_steps == 0); }

}  // namespace bitstep
