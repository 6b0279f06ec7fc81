// Scene files (format "bitstep-scene", version 1; replay/README.md has the
// format): JSON text -> Settings and body definitions in creation order.
// Numbers go from their text straight to Fixed (DESIGN rule 3); every error
// names the file, the JSON path of the offending value and the reason.
#pragma once

#include <string>
#include <string_view>
#include <variant>
#include <vector>

#include "core/body.h"
#include "core/settings.h"

namespace bitstep {

struct SceneBody {
  std::string name;  // may be empty; generated bodies are "<generator name>.<index>"
  BodyDef def;
};

struct Scene {
  Settings settings;
  std::vector<SceneBody> bodies;  // creation order: "bodies" first, then each generator's
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
// Reads the file, then parse_scene.
std::variant<Scene, SceneError> load_scene_file(const std::string& path);

}  // namespace bitstep
