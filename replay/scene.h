// Scene files (format "bitstep-scene", version 1; replay/README.md has the
// format): JSON text -> Settings, body and joint definitions in creation order.
// Numbers go from their text straight to Fixed, never through a double; every error
// names the file, the JSON path of the offending value and the reason.
#pragma once

#include <cstdint>
#include <functional>
#include <string>
#include <string_view>
#include <utility>
#include <vector>

#include "core/body.h"
#include "core/car.h"
#include "core/character.h"
#include "core/error.h"
#include "core/joint.h"
#include "core/settings.h"
#include "replay/json_tree.h"
#include "replay/limits.h"
#include "replay/material_table.h"

namespace bitstep {

struct SceneBody {
  std::string name;  // may be empty; generated bodies are "<generator name>.<index>"
  BodyDef def;
};

// A joint between two scene bodies, in the world frame at the bodies'
// scene poses. def.body_a / def.body_b are filled by build_world.
struct SceneJoint {
  std::string name;  // may be empty; generated joints are "<generator name>.joint<k>"
  JointDef def;
  uint32_t body_a = 0, body_b = 0;  // indices into Scene::bodies
};

// A raycast car (core/car.h) on a scene body. def.chassis is filled by
// build_world.
struct SceneCar {
  std::string name;   // replay "drive" inputs name it
  uint32_t chassis = 0;  // index into Scene::bodies
  CarDef def;
};

// A character controller (core/character.h): replay "move" inputs name it.
struct SceneCharacter {
  std::string name;
  CharacterDef def;
};

struct Scene {
  Settings settings;
  std::vector<SceneBody> bodies;    // creation order: "bodies" first, then each generator's
  std::vector<SceneJoint> joints;   // creation order: "joints" first, then each generator's
  std::vector<SceneCar> cars;       // "cars", in order: in a new world scene car k is car k
  std::vector<SceneCharacter> characters;  // "characters", in order: scene character k is the world's k
  MaterialTable materials;          // "materials", for bodies spawned later
};

// Parses scene JSON; on error returns the first error found and no scene,
// its place "<file_name>: <JSON path>" ("scene.json: $.bodies[2].shapes[0].radius",
// "scene.json: byte 17"). Never throws.
Result<Scene> parse_scene(std::string_view json_text, const std::string& file_name);
// The whole file's text, or the error with the file as its place ("cannot
// read the file (...)"). Its size is checked first: a file over `max_bytes`
// is refused unread.
Result<std::string> read_text_file(const std::string& path, std::uintmax_t max_bytes = limits::max_json_file_bytes);
// Refuses a file of `size` bytes over `max_bytes`: "N bytes: more than the
// limit of M bytes (K MiB)".
Result<void> check_file_size(std::uintmax_t size, std::uintmax_t max_bytes);
// Reads the file, then parse_scene.
Result<Scene> load_scene_file(const std::string& path);

// The keys of a scene's "settings" object, each applied over the value
// `settings` already holds (a scene: over the defaults; a replay's override:
// over the scene's). Throws an Error with the JSON path (scene_reader::fail).
void read_settings_onto(const json::Node& node, Settings& settings);

// A settings override as JSON text (`--settings` of bitstep run and record):
// an object of "settings" keys, applied onto `settings`. Returns the object
// as compact JSON text, or the first error (`source` in front of its
// place), leaving `settings` as it was. Never throws.
Result<std::string> apply_settings_text(std::string_view json_text, const std::string& source, Settings& settings);

// One body object in the scene format (as in "bodies"), material names
// resolved against the scene's table: for bodies spawned by replay inputs.
// Throws an Error with the JSON path (callers read through read_json).
SceneBody read_scene_body(const json::Node& node, const Scene& scene);

// One character object in the scene format (as in "characters"), for
// scenes and add_character inputs; its definition checked
// (check_character). Throws an Error with the JSON path.
SceneCharacter read_character(const json::Node& node);

// One joint object in the scene format (as in "joints"), for scenes and
// add_joint inputs: its anchors as written, each in the world frame or in
// its body's frame, and its bodies as `resolve_body` read them ("body_a",
// "body_b"; it fails with the value's path). Throws
// an Error with the JSON path.
struct JointSpec {
  std::string name;
  JointDef def;  // body ids unset; anchor_a / anchor_b in the frames below
  uint32_t body_a = 0, body_b = 0;
  bool anchor_a_local = false;  // "local_anchor_a": anchor_a is in body a's frame
  bool anchor_b_local = false;  // "local_anchor_b" (max_distance): anchor_b in body b's frame
};
using BodyResolver = std::function<uint32_t(const json::Node&)>;
JointSpec read_joint_spec(const json::Node& node, const BodyResolver& resolve_body);
// The spec's definition in the world frame: local anchors placed with the
// poses of the bodies' frames (world = frame.apply(local)).
JointDef joint_in_world(const JointSpec& spec, const Pose& frame_a, const Pose& frame_b);

}  // namespace bitstep
