// Rollback: the world is built from the scene file as `bitstep run` builds
// it, stepped to `from_step`, and its snapshot (replay/snapshot.h) restored
// into the same world before each round, then the same with a rollback
// state (replay/rollback_state.h) restored in place, untouched and with a
// body pushed at the first re-simulated step; times by
// std::chrono::steady_clock.
#include "tools/bench/costs.h"

#include <sys/resource.h>

#include <chrono>
#include <stdexcept>
#include <variant>
#include <vector>

#include "core/world.h"
#include "replay/replay.h"
#include "replay/rollback_state.h"
#include "replay/scene.h"
#include "replay/snapshot.h"
#include "replay/state_hash.h"

namespace bitstep::bench {

RollbackRow measure_rollback(const std::string& scenes_dir, const std::string& scene_name, int from_step,
                             int rounds) {
  const std::string path = scenes_dir + "/" + scene_name;
  const Result<Scene> loaded = load_scene_file(path);
  if (!loaded.ok()) throw std::runtime_error(loaded.error().message());
  const Scene& scene = loaded.value();
  World world(scene.settings);
  if (const Result<void> built = build_world(scene, world); !built.ok()) {
    throw std::runtime_error(built.error().within(path).message());
  }
  for (int i = 0; i < from_step; ++i) world.step();
  using Clock = std::chrono::steady_clock;
  const auto mean_ms = [rounds](Clock::duration total) {
    return std::chrono::duration<double, std::milli>(total).count() / rounds;
  };
  RollbackRow row;
  row.scene = scene_name;
  row.from_step = from_step;
  row.bodies = world.bodies().size();
  row.rounds = rounds;
  // Saving, each way (the rollback state's buffer kept, as a game keeps it).
  RollbackStates states;
  std::vector<uint8_t> state;
  states.save(world, state);
  std::vector<uint8_t> image;
  Clock::duration saving_state{}, saving_snapshot{};
  for (int round = 0; round < rounds; ++round) {
    const auto start = Clock::now();
    states.save(world, state);
    const auto saved = Clock::now();
    image = snapshot(world);
    saving_state += saved - start;
    saving_snapshot += Clock::now() - saved;
  }
  row.state_bytes = state.size();
  row.snapshot_bytes = image.size();
  row.state_save_ms = mean_ms(saving_state);
  row.snapshot_save_ms = mean_ms(saving_snapshot);
  // The body a remote input pushes (the last dynamic one: a pyramid's top
  // cube, a pile's last), 2 m/s sideways at its centre of mass.
  const std::optional<BodyId> pushed = last_dynamic_body(world);
  const auto push = [&] {
    if (!pushed) return;
    const Body& b = world.body(*pushed);
    world.apply_impulse(*pushed, sideways_impulse(b, Fixed::from_int(2)), b.pose.position);
  };
  // Rolling back, each way: restore, then rollback_frames steps; untouched
  // (the inputs as predicted) or with the push at the first (a remote input
  // that moves a body: what wakes a resting pile and costs a rollback game).
  uint64_t first_hash[2] = {0, 0};
  bool first[2] = {true, true};
  const auto time_rollbacks = [&](auto&& restore_now, bool pushing, double& restore_ms, double& rollback_ms) {
    Clock::duration restoring{}, rolling_back{};
    for (int round = 0; round < rounds; ++round) {
      const auto start = Clock::now();
      if (const Result<void> restored = restore_now(); !restored.ok()) {
        throw std::runtime_error(restored.error().within(path + ": restore").message());
      }
      const auto restored = Clock::now();
      if (pushing) push();
      for (int frame = 0; frame < rollback_frames; ++frame) world.step();
      const auto done = Clock::now();
      restoring += restored - start;
      rolling_back += done - start;
      const uint64_t hash = state_hash(world);
      if (first[pushing]) first_hash[pushing] = hash;
      first[pushing] = false;
      row.same_bits = row.same_bits && hash == first_hash[pushing];
    }
    restore_ms = mean_ms(restoring);
    rollback_ms = mean_ms(rolling_back);
  };
  time_rollbacks([&] { return restore(image, world); }, false, row.restore_ms, row.rollback_ms);
  // The snapshot made a new world object: the rollback state is saved again from it.
  states = RollbackStates{};
  if (const Result<void> restored = restore(image, world); !restored.ok()) {
    throw std::runtime_error(restored.error().within(path + ": restore").message());
  }
  states.save(world, state);
  time_rollbacks([&] { return states.restore(state, world); }, false, row.state_restore_ms, row.state_rollback_ms);
  double restore_again = 0;
  time_rollbacks([&] { return states.restore(state, world); }, true, restore_again, row.pushed_rollback_ms);
  return row;
}

std::optional<BodyId> last_dynamic_body(const World& world) {
  const std::vector<Body>& bodies = world.bodies();
  for (uint32_t slot = static_cast<uint32_t>(bodies.size()); slot-- > 0;) {
    if (bodies[slot].alive && bodies[slot].type == BodyType::dynamic) return BodyId{slot, bodies[slot].generation};
  }
  return std::nullopt;
}

Vec3 sideways_impulse(const Body& body, Fixed speed) { return {speed / body.inverse_mass, Fixed{}, Fixed{}}; }

long peak_resident_kib() {
  rusage usage{};
  getrusage(RUSAGE_SELF, &usage);
  return usage.ru_maxrss;
}

}  // namespace bitstep::bench
