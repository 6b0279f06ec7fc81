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
  if (!loaded.ok()) FAIL(loaded.error().message());
  const Scene& scene = loaded.value();
  World world(scene.settings);
  if (const Result<void> built = build_world(scene, world); !built.ok()) FAIL(built.error().message());
  return world;
}

}  // namespace bitstep::test
