// Rollback: the world is built from the scene file as `bitstep run` builds
// it, stepped to `from_step`, and its snapshot (replay/snapshot.h) restored
// into the same world before each round; times by std::chrono::steady_clock.
#include "tools/bench_costs.h"

#include <sys/resource.h>

#include <chrono>
#include <stdexcept>
#include <variant>
#include <vector>

#include "core/world.h"
#include "replay/replay.h"
#include "replay/scene.h"
#include "replay/snapshot.h"
#include "replay/state_hash.h"

namespace bitstep::bench {

RollbackRow measure_rollback(const std::string& scenes_dir, const std::string& scene_name, int from_step,
                             int rounds) {
  const std::string path = scenes_dir + "/" + scene_name;
  auto loaded = load_scene_file(path);
  if (const SceneError* error = std::get_if<SceneError>(&loaded)) throw std::runtime_error(error->message());
  const Scene& scene = std::get<Scene>(loaded);
  World world(scene.settings);
  std::string reason;
  if (!build_world(scene, world, reason)) throw std::runtime_error(path + ": " + reason);
  for (int i = 0; i < from_step; ++i) world.step();
  const std::vector<uint8_t> image = snapshot(world);

  RollbackRow row;
  row.scene = scene_name;
  row.from_step = from_step;
  row.snapshot_bytes = image.size();
  row.rounds = rounds;
  using Clock = std::chrono::steady_clock;
  Clock::duration restoring{}, rolling_back{};
  uint64_t first_hash = 0;
  for (int round = 0; round < rounds; ++round) {
    const auto start = Clock::now();
    if (const auto failed = restore(image, world)) throw std::runtime_error(path + ": restore: " + *failed);
    const auto restored = Clock::now();
    for (int frame = 0; frame < rollback_frames; ++frame) world.step();
    const auto done = Clock::now();
    restoring += restored - start;
    rolling_back += done - start;
    const uint64_t hash = state_hash(world);
    if (round == 0) first_hash = hash;
    row.same_bits = row.same_bits && hash == first_hash;
  }
  const auto mean_ms = [rounds](Clock::duration total) {
    return std::chrono::duration<double, std::milli>(total).count() / rounds;
  };
  row.restore_ms = mean_ms(restoring);
  row.rollback_ms = mean_ms(rolling_back);
  return row;
}

long peak_resident_kib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

}  // namespace bitstep::bench
