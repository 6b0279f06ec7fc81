// Scene files (format "bitstep-scene", version 1; replay/README.md has the
// format): JSON text -> Settings and body definitions in creation order.
// Numbers go from their text straight to Fixed (DESIGN rule 3); every error
// names the file, the JSON path of the offending value and the reason.
#pragma once

#include <string>
#include <string_view>
#include <utility>
#include <variant>
#include <vector>

#include "core/body.h"
#include "core/settings.h"
#include "replay/json_tree.h"
#include "replay/material_table.h"

namespace bitstep {

struct SceneBody {
  std::string name;  // may be empty; generated bodies are "<generator name>.<index>"
  BodyDef def;
};

struct Scene {
  Settings settings;
  std::vector<SceneBody> bodies;  // creation order: "bodies" first, then each generator's
  MaterialTable materials;        // "materials", for bodies spawned later
};

struct SceneError {
  std::string file;
  std::string path;    // "$.bodies[2].shapes[0].radius", "byte 17", or empty (unreadable file)
  std::string reason;  // "outside 0.01..50 m"
  // "<file>: <path>: <reason>", one line.
  std::string message() const;
};

// Parses scene JSON; on error returns the first error found and no scene.
// Never throws.
std::variant<Scene, SceneError> parse_scene(std::string_view json_text, const std::string& file_name);
// Reads the whole file into `text` (at most 1 GiB); false with a reason.
bool read_text_file(const std::string& path, std::string& text, std::string& reason);
// Reads the file, then parse_scene.
std::variant<Scene, SceneError> load_scene_file(const std::string& path);

// The keys of a scene's "settings" object, each applied over the value
// `settings` already holds (a scene: over the defaults; a replay's override:
// over the scene's). Throws scene_reader::ReadFailure with the JSON path.
void read_settings_onto(const json::Node& node, Settings& settings);

// A settings override as JSON text (`--settings` of bitstep run and record):
// an object of "settings" keys, applied onto `settings`. Returns the object
// as compact JSON text, or the first error (its file `source`), leaving
// `settings` as it was. Never throws.
std::variant<std::string, SceneError> apply_settings_text(std::string_view json_text, const std::string& source,
                                                          Settings& settings);

// One body object in the scene format (as in "bodies"), material names
// resolved against the scene's table: for bodies spawned by replay inputs.
// Throws scene_reader::ReadFailure with the JSON path (callers catch it).
SceneBody read_scene_body(const json::Node& node, const Scene& scene);

}  // namespace bitstep
