// bitstep for a game: one world built from a scene, stepped tick by tick,
// with the inputs a game applies between ticks, its bodies' poses, save and
// load, a state hash and the world's queries. The library's stable C++
// facade; a C API over it is replay/bitstep.h. It lives in replay/ because
// it is built from what replay/ owns (scenes, snapshots, hashes); core/
// stays the simulator alone.
//
// Everything that reaches the world is exact (Q32.32): a lockstep game
// feeds every peer the same inputs and gets the same bits. Floats are for
// drawing only (replay/render_pose.h), never fed back.
#pragma once

#include <cstdint>
#include <map>
#include <memory>
#include <optional>
#include <span>
#include <string>
#include <string_view>
#include <vector>

#include "core/query.h"
#include "core/world.h"
#include "replay/rollback_state.h"
#include "replay/scene.h"

namespace bitstep {

// What an input call did: applied; nothing, for a body or car that is not
// there; or nothing, for a value past its bound or a body the input cannot
// move (an impulse or force on a static or kinematic body, a velocity on a
// static one), `refusal` saying which (place "set_velocity: linear", reason
// "faster than 500 m/s"; "apply_impulse", "the body is static: impulses
// move dynamic bodies"). True when
// applied. A status, not a Result: a missing body is no error in a game
// (it may have left the world) and the C API tells the two apart.
struct InputResult {
  enum class Status { applied, not_found, refused };
  Status status = Status::applied;
  Error refusal;  // refused: "<call>: <argument>" and the bound

  explicit operator bool() const { return status == Status::applied; }
};

class Simulation {
 public:
  // A world from a scene file, or from scene JSON text (`name` stands for
  // the file in messages); or the scene's error (place "<file>: <JSON
  // path>", or "<file>: body 3: <field>" for a body the world refuses).
  static Result<Simulation> from_file(const std::string& path);
  static Result<Simulation> from_text(std::string_view scene_json, const std::string& name);

  // Bodies. A scene body by its name; a new body from one body object of
  // the scene format ({"name": "crate", "position": [0, 2, 0], "shapes":
  // [...]}, the scene's materials known); removal. A removed body's handle
  // is refused by every call (its slot's generation moved on).
  std::optional<BodyId> find_body(std::string_view name) const;
  // An error's place starts with the call: "add_body: $.shapes[0].radius".
  Result<BodyId> add_body(std::string_view body_json);
  // The same from a definition (the C API's plain structs): the world's
  // checks (core/envelope.h; place "create_body: shapes[0].radius"), and
  // a name no body has yet ("" for none).
  Result<BodyId> create_body(const BodyDef& def, const std::string& name);
  bool remove_body(BodyId id);
  // Joints: one joint object of the scene format, its bodies by name.
  Result<JointId> add_joint(std::string_view joint_json);
  // The same from a definition in the world frame (World::create_joint's checks).
  Result<JointId> create_joint(const JointDef& def);
  bool remove_joint(JointId id);

  // Inputs, for the next step. Each is bounded as the replay reader bounds
  // the same input (replay/input_bounds.h): an impulse or force within
  // +-1,000,000 N s or N per component, its point within +-16,000 m; a
  // velocity within 500 m/s and 100 rad/s (per component and in length); a
  // car's throttle and steer within -1..1, its brake 0..1. A value past its
  // bound is refused and changes nothing (InputResult::refused, the refusal
  // naming the call, the argument and the bound); so is a handle no body
  // has (not_found). A handle is checked before the values.
  InputResult apply_impulse(BodyId id, Vec3 impulse, Vec3 world_point);
  InputResult apply_force(BodyId id, Vec3 force, Vec3 world_point);
  InputResult set_velocity(BodyId id, Vec3 linear, Vec3 angular);
  bool wake(BodyId id);
  InputResult drive(std::string_view car_name, CarControls controls);
  // A character's desired level velocity (within 100 m/s per component;
  // its y is ignored) and jump, from the next step on.
  InputResult move(std::string_view character_name, CharacterControls controls);
  // The character named so (core/character.h: where it is, how it moves,
  // what it stands on), or none.
  const Character* character(std::string_view name) const;
  // A new character: one character object of the scene format, its name
  // one no live character has (a replay's add_character input); it stands
  // where it is created from the next step on. remove_character: false
  // when no live character has the name.
  Result<void> add_character(std::string_view character_json);
  bool remove_character(std::string_view name);

  void step();
  uint64_t tick() const { return world_.step_count(); }

  // Where a body is: the pose of its frame as the scene (or add_body)
  // defined it, not its centre of mass (a table defined at y 0.4 reads
  // 0.4). nullopt for a handle no body has.
  std::optional<Pose> pose(BodyId id) const;
  // A live body's name ("" for none), and where its defined frame's origin
  // is seen from its centre of mass, in the body frame (a shape's local
  // pose in the defined frame is the world's Shape::local moved by it).
  std::string_view name(BodyId id) const;
  Vec3 frame_offset(BodyId id) const;

  // The whole state as a snapshot image (replay/snapshot.h); load restores
  // one into this simulation (a rollback, or a late joiner's start) or
  // says why it cannot and changes nothing (whether the world lists its
  // events, a choice not in the state, stays). hash() is the state hash
  // the replays' chains hold.
  std::vector<uint8_t> save() const;
  Result<void> load(std::span<const uint8_t> image);
  uint64_t hash() const;
  // The checksum of the step's state that sessions' peers compare
  // (rollback_state.h): no serial, no static field, the same for peers
  // whose worlds were built apart.
  uint64_t checksum() const;

  // A rollback game's save and load (replay/rollback_state.h): the step's
  // state alone into the caller's buffer (the size it needs returned; when
  // larger than the buffer, nothing usable written), restored in place.
  // Only into this simulation, and not across a load() (a new world).
  size_t save_state(std::span<uint8_t> buffer);
  Result<void> load_state(std::span<const uint8_t> image);

  // The world's queries as it stands (core/query.h): build after each step.
  WorldQuery query() const { return WorldQuery(world_); }

  // The scene it was built from (its bodies' names, materials, cars).
  const Scene& scene() const { return scene_; }
  const World& world() const { return world_; }
  World& world() { return world_; }

 private:
  Simulation(Scene scene, World world);
  static Result<Simulation> built(Result<Scene> read, const std::string& name);
  bool valid(BodyId id) const;
  void remember(BodyId id, const BodyDef& def, const std::string& name);

  Scene scene_;  // its materials and settings, for bodies added later
  World world_;
  RollbackStates states_;
  std::map<std::string, BodyId, std::less<>> names_;     // bodies by name
  std::map<std::string, uint32_t, std::less<>> cars_;    // cars by name
  std::map<std::string, uint32_t, std::less<>> characters_;  // characters by name
  // Per body ever created here (slot, generation): its frame's origin as
  // seen from its centre of mass, in the body frame, and its name. Kept
  // for removed bodies too, so a rolled-back world still finds them.
  struct Defined {
    Vec3 frame_offset;
    std::string name;
  };
  std::map<std::pair<uint32_t, uint32_t>, Defined> defined_;
};

}  // namespace bitstep
