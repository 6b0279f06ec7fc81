// The world: bodies in dense arrays, their contacts, and the step.
#pragma once

#include <cstdint>
#include <memory>
#include <string>
#include <vector>

#include "core/body.h"
#include "core/car.h"
#include "core/character.h"
#include "core/contact.h"
#include "core/envelope.h"
#include "core/error.h"
#include "core/executor.h"
#include "core/joint.h"
#include "core/sensor.h"
#include "core/settings.h"

namespace bitstep {

// Per-step figures for reports (bitstep run).
struct StepStats {
  int awake_bodies = 0;     // dynamic bodies awake
  int sleeping_bodies = 0;
  int contact_points = 0;
  Fixed max_penetration;  // m
  Fixed kinetic_energy;   // J, at most 2^31 J (capped there: a report, never state)
};

// A number for each world object, drawn anew for a copy (a copy's future
// bodies are its own) and kept by a move: rollback states name the world
// they belong to with it.
class WorldInstance {
 public:
  WorldInstance() : id_(next()) {}
  WorldInstance(const WorldInstance&) : id_(next()) {}
  WorldInstance& operator=(const WorldInstance&) {
    id_ = next();
    return *this;
  }
  WorldInstance(WorldInstance&&) = default;
  WorldInstance& operator=(WorldInstance&&) = default;
  uint64_t id() const { return id_; }

 private:
  static uint64_t next();
  uint64_t id_;
};

struct WorldScratch;
struct SolveContext;

class World {
 public:
  explicit World(const Settings& settings = {});
  World(World&&) noexcept;
  World& operator=(World&&) noexcept;
  ~World();

  // A world continuing from a saved state (replay/snapshot.cpp): the caller
  // has checked that contacts and free slots refer to existing slots.
  static World from_state(const Settings& settings, uint64_t step_count, std::vector<Body> bodies,
                          std::vector<uint32_t> free_slots, std::vector<Contact> contacts,
                          std::vector<Joint> joints = {}, std::vector<uint32_t> free_joint_slots = {},
                          std::vector<SensorOverlap> sensor_overlaps = {}, std::vector<Car> cars = {},
                          std::vector<Character> characters = {});

  // Validates the definition against the world envelope first; on error
  // (its place the field: "mass", "shapes[0].radius") the world is unchanged.
  Result<BodyId> create_body(const BodyDef& def);
  // Removes the body and every joint attached to it.
  bool remove_body(BodyId id);

  // Joins two bodies (core/joint.h): checked first (live, different bodies,
  // one of them dynamic, anchors within reach of the bodies, a usable axis
  // and limits); on error (its place the field: "body_b", "axis") the world
  // is unchanged. A sleeping body joined to an awake one wakes with its
  // island; two sleeping ones stay asleep.
  Result<JointId> create_joint(const JointDef& def);
  // Sets a hinge's or a slider's motor (JointDef::motor_speed, motor_max;
  // max 0: none) from the next step on, and wakes its bodies. Refused (a
  // dead joint, a type without a motor, a setting out of range), the joint
  // is unchanged.
  Result<void> set_joint_motor(JointId id, Fixed speed, Fixed max);
  // Removes the joint and wakes its bodies (a chain whose holder is cut falls).
  bool remove_joint(JointId id);
  bool is_alive(JointId id) const;

  // One step of dt. At its end every body whose centre of mass is past
  // envelope::world_bound (+-2^19 m) on an axis is removed, as remove_body
  // does (its joints, contacts, overlaps and car go with it), in slot
  // order, each with a left_world event (listed whether or not events are
  // on: a game must learn that its handle died). Removal, not freezing or
  // clamping: a dead slot is what every state format already holds (no
  // format change; an older state with a body past the bound loads and
  // loses it in its next step), where a frozen body needs a new state flag
  // and a clamped one an invisible wall. Box2D 2.0 froze a body leaving
  // its world AABB and told its b2BoundaryListener; Bullet takes a body
  // whose AABB overflows out of the simulation (DISABLE_SIMULATION); Jolt
  // offers double-precision positions instead of a bound (core/README.md
  // "World bounds").
  void step();

  // Inputs, applied by the next step. An impulse changes the velocities at
  // once, clamped to the speed clamps; forces add up until the step, bounded
  // so that the step's velocity change stays below 2^28 m/s and rad/s; a set
  // velocity is clamped. Any magnitude computes (core/envelope.h); replays
  // bound impulses and forces to 1e6 per component, points to +-16 km.
  void apply_impulse(BodyId id, Vec3 impulse, Vec3 world_point);
  void apply_force(BodyId id, Vec3 force, Vec3 world_point);
  void set_velocity(BodyId id, Vec3 linear, Vec3 angular);
  // A raycast car on a live dynamic chassis (core/car.h): checked first
  // (check_car); on error (its place the field: "chassis",
  // "wheel_radius") the world is unchanged.
  Result<CarId> create_car(const CarDef& def);
  // The driver's controls, clamped to their ranges, kept until changed.
  void set_car_controls(CarId id, CarControls controls);
  // Cars in creation order; a car whose chassis is removed is dead.
  const std::vector<Car>& cars() const { return cars_; }

  // A character controller (core/character.h): checked first
  // (check_character); on error (its place the field) the world is
  // unchanged. It moves each step, after the bodies, in creation order.
  Result<CharacterId> create_character(const CharacterDef& def);
  // What it is asked to do from the next step on (a `move` input).
  void set_character_controls(CharacterId id, CharacterControls controls);
  void remove_character(CharacterId id);
  // Characters in creation order; a removed one is dead.
  const std::vector<Character>& characters() const { return characters_; }
  // Wakes the body's island (no-op when it is awake or sleep is off).
  void wake(BodyId id);

  const Settings& settings() const { return settings_; }
  uint64_t step_count() const { return step_count_; }
  bool is_alive(BodyId id) const;
  const Body& body(BodyId id) const { return bodies_[id.index]; }
  // Slots in creation order; dead slots have alive == false.
  const std::vector<Body>& bodies() const { return bodies_; }
  const std::vector<Contact>& contacts() const { return contacts_; }
  // Removed slots, reused last-in first-out (state: it decides where the next body goes).
  const std::vector<uint32_t>& free_slots() const { return free_slots_; }
  // Joint slots in creation order (dead ones alive == false), and the
  // removed slots, reused last-in first-out (state, as the bodies').
  const std::vector<Joint>& joints() const { return joints_; }
  const std::vector<uint32_t>& free_joint_slots() const { return free_joint_slots_; }
  StepStats stats() const;
  // What overlaps the sensors' shapes (state), and the last step's events:
  // joints that broke (in slot order, always listed), then, once
  // set_events(true), what began and ended touching (contacts, then
  // sensors, each in key order), then bodies that left the world (always
  // listed). A removed body's contacts and overlaps end without an event. Events are off by default (not state: they
  // cost two passes over the contacts a step, 65% of a sleeping wall128's step).
  const std::vector<SensorOverlap>& sensor_overlaps() const { return sensor_overlaps_; }
  void set_events(bool on) { events_on_ = on; }
  bool events_on() const { return events_on_; }
  const std::vector<WorldEvent>& events() const { return events_; }

  // Exact reuse of last step's broadphase pairs where no body's bounds or
  // margin changed by a bit (broadphase.h), of its narrowphase results where
  // both bodies' poses did not move by a bit (contact_update.h), and of a manifold's
  // pose-dependent solver rows where everything they are computed from is
  // bit-identical (row_cache.h). On by default; the results are the same
  // bits either way (tests compare the two). Not state.
  void set_contact_reuse(bool on);
  // From how many manifolds the iterations sweep copies of the rows'
  // parts (solver_rows.h, SweepRows; default 2,048). Speed only: the
  // same bits for any value (tests set 0). Not state.
  void set_sweep_copies_from(size_t manifolds);
  // Spreads the step's solver sweeps over the executor's workers (null, the
  // default: the caller's thread alone). The world does not own it; it must
  // outlive the world's steps. The same bits for any executor (tests verify
  // every golden replay with 1, 2, 3 and 8 workers). Not state.
  // Not state: this world object's number, and the serial of its next body.
  uint64_t instance() const { return instance_.id(); }
  // After a rollback state was read into this world in place
  // (replay/rollback_state.cpp): recounts what the step counts from the
  // bodies and forgets every cache, as a world just built from a state has
  // none.
  void after_in_place_restore();

  void set_executor(Executor* executor) { executor_ = executor; }
  Executor* executor() const { return executor_; }
  // Sweep runs (a solve's iterations, or its position passes) that were
  // shared among several workers, over the world's life.
  uint64_t shared_sweep_runs() const;
  // Shape pairs whose collision test was reused / run, over the world's life.
  uint64_t reused_shape_pairs() const;
  uint64_t tested_shape_pairs() const;
  // Manifolds whose solver rows were reused / built, over the world's life.
  uint64_t reused_manifold_rows() const;
  uint64_t built_manifold_rows() const;
  // Manifold rows solved at the held islands' velocity passes, over the
  // world's life (core/held_islands.h).
  uint64_t held_manifold_rows() const;

 private:
  // create_joint's checks: the first refusal, or none.
  Result<void> joint_error(const JointDef& def) const;
  // The step's parts (world.cpp). Those of a substep take its settings,
  // whose dt is the substep's; the rest run once per step.
  void substep(const Settings& s);
  void run_substeps();
  void break_joints();
  void touching_before_step();
  void report_events();
  void remove_beyond_bound();  // world_bounds.cpp
  void step_standard(const Settings& s);
  void step_guendelman(const Settings& s);
  void find_contacts(const Settings& s);
  const std::vector<BodyPair>& contact_pairs();
  SolveContext solve_context(const Settings& s);  // this world's, for core/solver.h
  void wake_islands_of(const std::vector<uint32_t>& slots);
  void wake_if_asleep(uint32_t slot);
  // Drops the narrowphase results of a slot whose body is removed.
  void forget_narrowphase(uint32_t slot);

  friend struct WorldStateAccess;  // replay/rollback_state.cpp reads a state into these in place

  Settings settings_;
  uint64_t step_count_ = 0;
  WorldInstance instance_;
  uint64_t last_serial_ = 0;
  std::vector<Body> bodies_;
  std::vector<uint32_t> free_slots_;  // removed slots, reused last-in first-out
  std::vector<Contact> contacts_;     // sorted by (body a, body b, shape a, shape b)
  std::vector<Joint> joints_;
  std::vector<uint32_t> free_joint_slots_;
  std::vector<SensorOverlap> sensor_overlaps_;  // sorted by key
  std::vector<Car> cars_;
  std::vector<Character> characters_;
  void move_characters();
  std::vector<WorldEvent> events_;              // the last step's (not state: the next step's are new)
  bool events_on_ = false;
  // Live bodies off the default filter or sensors, and sensors: the step
  // skips filtering and sensor tests when there are none.
  uint32_t special_bodies_ = 0, sensor_bodies_ = 0;
  void count_special(const Body& body, int change);
  // What the step keeps only to reuse memory and exact results
  // (core/world_scratch.h): never state, rebuilt or checked every step.
  std::unique_ptr<WorldScratch> scratch_;
  Executor* executor_ = nullptr;
  bool moves_far(const Body& body, Fixed dt) const;
  void move_contacts_back();
};

}  // namespace bitstep
