// The golden replays in scenes/ for tests: their paths, the ones this build
// runs, and the hash chain a replay gives when stepped again.
#pragma once

#include <catch2/catch.hpp>

#include <algorithm>
#include <cstdint>
#include <filesystem>
#include <string>
#include <vector>

#include "replay/replay.h"
#include "replay/state_hash.h"
#include "tests/replay/test_scenes.h"

namespace bitstep::test {

inline std::vector<std::string> golden_replays() {
  std::vector<std::string> paths;
  for (const auto& entry : std::filesystem::directory_iterator(scenes_dir)) {
    const std::string name = entry.path().filename().string();
    if (name.size() > 12 && name.ends_with(".replay.json")) paths.push_back(entry.path().string());
  }
  std::sort(paths.begin(), paths.end());
  return paths;
}

// Runs a replay; the hash chain it produces. Without `contact_reuse` the
// narrowphase tests every shape pair afresh every step and the solver
// builds every row, and the iterations sweep copies of the rows' parts
// however few the manifolds (with it, from the default 2,048: wall128's
// short replay; `copies_always` asks for them too); `executor` steps the
// world on its workers.
inline std::vector<uint64_t> replay_chain(const Replay& replay, uint64_t& scene_hash, bool contact_reuse = true,
                                          Executor* executor = nullptr, uint64_t* shared_sweep_runs = nullptr,
                                          bool copies_always = false) {
  World world(replay.scene.settings);
  REQUIRE(build_world(replay.scene, world).ok());
  world.set_contact_reuse(contact_reuse);
  if (!contact_reuse || copies_always) world.set_sweep_copies_from(0);
  world.set_executor(executor);
  scene_hash = state_hash(world);
  std::vector<uint64_t> hashes;
  run_inputs(world, replay.inputs, replay.steps, hashes);
  if (!contact_reuse) CHECK(world.reused_shape_pairs() + world.reused_manifold_rows() == 0);
  if (shared_sweep_runs) *shared_sweep_runs += world.shared_sweep_runs();
  return hashes;
}

// Whether a full replay is left to optimised builds: in unoptimised ones (the
// checked Debug build with ASan and UBSan) a scene with a short replay
// (<scene>.short.replay.json: wall128, pyramid20, playground, ragdolls, terrain, hills) runs that one
// only, as under qemu in tools/crosscheck/crosscheck.sh, whose optimised checked + UBSan
// build verifies the full ones. Their full replays took ~4 of this test's
// ~6 minutes in the checked build.
inline bool left_to_optimised_builds(const std::string& path) {
#if defined(NDEBUG)
  (void)path;
  return false;
#else
  const std::string suffix = ".replay.json";
  if (path.ends_with(".short" + suffix)) return false;
  const std::string short_path = path.substr(0, path.size() - suffix.size()) + ".short" + suffix;
  return std::filesystem::exists(short_path);
#endif
}

// Unoptimised builds, and the ThreadSanitizer build (BITSTEP_FEW_GOLDENS:
// a race shows in any replay that runs on workers), run seven replays that
// cover what the reuse and the threads must get right (a standing pyramid
// hit by a spawned sphere, a thrown pile settling and sleeping with spawns,
// removals and wakes, a body removed from a stack, spheres and capsules,
// guendelman's predicted poses) and leave the rest to the optimised builds,
// where all of them run.
inline std::vector<std::string> covering_replays() {
  std::vector<std::string> paths = golden_replays();
  std::erase_if(paths, [](const std::string& path) {
    for (const char* name : {"pyramid20.short", "thrown.sleep_motion", "stack20.remove_middle.", "playground.short",
                             "spheres.", "car_wall.guendelman"}) {
      if (path.find(std::string("/") + name) != std::string::npos) return false;
    }
    return true;
  });
  REQUIRE(paths.size() == 7);
  return paths;
}

inline std::vector<std::string> replays_of_this_build() {
#if !defined(NDEBUG) || defined(BITSTEP_FEW_GOLDENS)
  return covering_replays();
#else
  return golden_replays();
#endif
}

}  // namespace bitstep::test
