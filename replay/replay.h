// Input replays (format "bitstep-replay", version 1; replay/README.md): a
// scene, the inputs by step and the hash chain, one state hash per step.
// Recording runs the scene with the inputs and writes the chain; verifying
// runs it again and compares every step.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <vector>

#include "core/world.h"
#include "replay/json_tree.h"
#include "replay/scene.h"

namespace bitstep {

// One input. It applies at the start of step `step` (the first step is 1),
// after the inputs before it in the file. `body` is a slot index (a name in
// the file is resolved to the scene body's slot when the replay is read);
// the input goes to whatever body occupies the slot then, and is ignored
// when the slot is empty. add_joint's bodies are slots in the same way; a
// joint the world refuses then (World::create_joint) is not added.
struct Input {
  enum class Kind {
    impulse,
    force,
    set_velocity,
    spawn,
    remove,
    wake,
    add_joint,
    remove_joint,
    drive,
    motor,
    move,
    add_character,
    remove_character
  };
  int64_t step = 1;
  Kind kind = Kind::impulse;
  uint32_t body = 0;
  Vec3 vector;       // impulse (N s), force (N) or linear velocity (m/s)
  Vec3 point;        // world point of an impulse or force (m); angular velocity (rad/s) for set_velocity
  SceneBody spawned; // spawn: the new body
  // add_joint: the joint, its bodies as slots, local anchors in the body's
  // frame in the world at that step (about its centre of mass); remove_joint:
  // joint.name only.
  JointSpec joint;
  uint32_t joint_number = 0;  // add_joint, remove_joint, motor: the joint, numbered as in InputRun::joints
  uint32_t car = 0;           // drive: the scene's car
  CarControls controls;       // drive: the controls from this step on
  // move, remove_character: the character, numbered as the world's: the
  // scene's 0..n-1, then each add_character's in input order (its name
  // resolved when the replay is read); add_character: the new one.
  uint32_t character = 0;
  SceneCharacter added;
  CharacterControls moving;   // move: what it is asked from this step on
  Fixed motor_speed, motor_max;  // motor: World::set_joint_motor's (rad/s or m/s; N m or N)
  json::Node source; // the input as written, kept for writing the replay back exactly
};

struct Replay {
  std::string scene_file;    // as written in the replay: relative to the replay's folder
  std::string inline_scene;  // or the scene itself, as compact JSON (then scene_file is empty)
  std::string settings_override;  // the replay's own "settings" as compact JSON, applied onto scene.settings; or empty
  Scene scene;
  uint64_t scene_hash = 0;  // state_hash of the scene's world before step 1
  int64_t steps = 0;
  std::vector<Input> inputs;    // in step order (stable: file order within a step)
  std::vector<uint64_t> hashes; // state hash after each step; empty before recording
};

// A hash as replays write it: 16 lowercase hex digits.
std::string hex16(uint64_t value);

// Reads a replay file and the scene it names. With `require_hashes` the hash
// chain must be there, one per step (for verify); a recording's input file
// has none. An error's place is "<file>: <JSON path>": the replay's, or the
// scene file's for an error inside that file.
Result<Replay> load_replay_file(const std::string& path, bool require_hashes);
// The same from the file's text: `path` names it in errors, and a scene
// file the replay names is read from `path`'s folder. Never throws.
Result<Replay> parse_replay(std::string_view json_text, const std::string& path, bool require_hashes);

// Reads an inputs file for `bitstep record`: {"inputs": [...]} against a
// scene, or a replay file (its inputs, to record it again, and its settings
// override, checked against the scene's settings).
struct InputsFile {
  std::vector<Input> inputs;
  std::string settings_override;  // a replay's "settings" as compact JSON, or empty
};
Result<InputsFile> load_inputs_file(const std::string& path, const Scene& scene);

// A JSON array of inputs (as a replay's "inputs") read against a scene:
// for inputs that travel on their own (a session's). `name` stands for the
// file in errors.
Result<std::vector<Input>> parse_inputs(std::string_view json_array, const Scene& scene, const std::string& name);

// A world with the scene's bodies in order, then its joints in order (in a
// new world scene body i is slot i and scene joint k joint slot k); the
// error when a body, a car or a joint is refused, World's with the object
// in front of its place: "body 3: shapes[0].radius: <reason>", "joint 2
// (\"rope\"): body_b: <reason>".
Result<void> build_world(const Scene& scene, World& world);

// A run of inputs: the next one to apply, and the joints inputs name, by
// number: the scene's (the world's joint slots at step 0, as build_world
// made them), then each add_joint's in input order, as it is created
// (an index no joint has: nothing).
struct InputRun {
  explicit InputRun(const World& world_at_step_0);
  size_t next = 0;
  std::vector<JointId> joints;
};

// Applies the inputs of step `step` starting at `run.next` (advanced past them).
void apply_inputs(World& world, const std::vector<Input>& inputs, int64_t step, InputRun& run);

// Runs `steps` steps with the inputs from a world at step 0, appending each
// step's state hash.
// With `dump` set, the state after step `dump_step` (0: before step 1) is
// written into it as dump_state's JSON. `watch`, when set, sees the world
// before step 1 and after each step (`record` / `verify --trace`).
using StepWatch = std::function<void(const World&)>;
void run_inputs(World& world, const std::vector<Input>& inputs, int64_t steps, std::vector<uint64_t>& hashes,
                int64_t dump_step = -1, std::string* dump = nullptr, const StepWatch& watch = {});

// Re-runs a replay from its scene and compares every hash.
struct Verification {
  Result<void> built;          // an error: a scene body, car or joint was refused (build_world's)
  uint64_t scene_hash = 0;     // of the world before step 1
  bool scene_matches = false;  // scene_hash equals the recorded one
  int64_t divergent_step = 0;  // first step whose hash differs, 0 when all match
  std::vector<uint64_t> hashes;
  uint64_t snapshot_checksum = 0;  // of the snapshot image after the last step (the same bytes in every build)
  bool ok() const { return built.ok() && scene_matches && divergent_step == 0; }
};
// `executor` (null: one thread) steps the world (World::set_executor).
Verification verify_replay(const Replay& replay, int64_t dump_step = -1, std::string* dump = nullptr,
                           Executor* executor = nullptr, const StepWatch& watch = {});

// The replay as JSON text (hashes as 16 hex digits).
std::string replay_json(const Replay& replay, const std::string& engine_version);

// Where two hash chains first differ: the step (1-based) or 0 when equal.
int64_t first_divergent_step(const std::vector<uint64_t>& recorded, const std::vector<uint64_t>& replayed);

}  // namespace bitstep
