// Shipped scenes for tests: their folder, and a world built from one.
#pragma once

#include <catch2/catch.hpp>

#include <string>
#include <variant>

#include "replay/replay.h"

namespace bitstep::test {

inline const std::string scenes_dir = std::string(BITSTEP_SOURCE_DIR) + "/scenes";

inline World world_of(const std::string& scene_name) {
  auto loaded = load_scene_file(scenes_dir + "/" + scene_name);
  if (const SceneError* error = std::get_if<SceneError>(&loaded)) FAIL(error->message());
  const Scene& scene = std::get<Scene>(loaded);
  World world(scene.settings);
  std::string reason;
  if (!build_world(scene, world, reason)) FAIL(reason);
  return world;
}

}  // namespace bitstep::test
