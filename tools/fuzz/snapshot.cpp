// Fuzzes snapshot restore: the bytes as a snapshot image to restore
// (replay/snapshot.h) into a world built from a small scene, once as they
// are and once with the image's payload-size and checksum fields rewritten
// to match the bytes (else nearly every mutation would stop at the
// checksum, and the payload reader would never be reached). Must hold: no
// crash, no undefined behaviour, no leak; refused: a one-line reason and the
// world untouched (its state bytes as before); restored: the world
// snapshots to exactly the image's bytes, and steps.
#include <xxhash.h>

#include <algorithm>
#include <vector>

#include "core/world.h"
#include "replay/replay.h"
#include "replay/scene.h"
#include "replay/snapshot.h"
#include "replay/state_hash.h"
#include "tools/fuzz/fuzz_targets.h"

namespace bitstep::fuzz {

namespace {

// A ground, a box and a sphere joined by a point joint.
constexpr std::string_view small_scene = R"({"format": "bitstep-scene", "version": 1,
  "bodies": [
    {"name": "ground", "type": "static", "position": [0, -1, 0], "shapes": [{"type": "box", "half_extents": [10, 1, 10]}]},
    {"name": "box", "position": [0, 0.5, 0], "shapes": [{"type": "box", "half_extents": [0.5, 0.5, 0.5]}]},
    {"name": "ball", "position": [0, 2, 0], "shapes": [{"type": "sphere", "radius": 0.5}]}],
  "joints": [{"type": "point", "body_a": "box", "body_b": "ball", "anchor": [0, 1.25, 0]}]})";

std::vector<uint8_t> state_bytes(const World& world) {
  std::vector<uint8_t> bytes;
  serialize_state(world, bytes);
  return bytes;
}

// The small scene's world, built once (a world's construction costs more
// than most restores), with its image and state bytes: every restore goes
// into it, and an accepted one is undone by restoring the image.
struct Target {
  World world;
  std::vector<uint8_t> image, bytes;
  Target() {
    const Result<Scene> parsed = parse_scene(small_scene, "small scene");
    require(parsed.ok(), "the small scene parses");
    const Scene& scene = parsed.value();
    world = World(scene.settings);
    require(build_world(scene, world).ok(), "the small scene builds");
    image = snapshot(world);
    bytes = state_bytes(world);
  }
};

Target& target() {
  static Target t;
  return t;
}

// One restore: its outcome, with the properties checked.
Outcome restore_checked(std::span<const uint8_t> image) {
  Target& t = target();
  if (const Result<void> restored = restore(image, t.world); !restored.ok()) {
    require_one_line_error(restored.error().message(), "");
    require(state_bytes(t.world) == t.bytes, "a refused restore leaves the world untouched");
    return {false, restored.error().message()};
  }
  const std::vector<uint8_t> again = snapshot(t.world);
  require(again.size() == image.size() && std::equal(again.begin(), again.end(), image.begin()),
          "a restored world snapshots to the same bytes");
  t.world.step();
  require(restore(t.image, t.world).ok(), "the small scene's image restores");
  return {true, {}};
}

}  // namespace

Outcome snapshot_restore(std::span<const uint8_t> data) {
  const Outcome as_is = restore_checked(data);
  constexpr size_t header = 8 + 4 + 8, trailer = 8;
  if (data.size() < header + trailer) return as_is;
  std::vector<uint8_t> fixed(data.begin(), data.end());
  const uint64_t payload = fixed.size() - header - trailer;
  for (size_t i = 0; i < 8; ++i) fixed[12 + i] = static_cast<uint8_t>(payload >> (8 * i));
  const size_t body_end = fixed.size() - trailer;
  const uint64_t checksum = XXH3_64bits(fixed.data(), body_end);
  for (size_t i = 0; i < 8; ++i) fixed[body_end + i] = static_cast<uint8_t>(checksum >> (8 * i));
  const Outcome made_right = restore_checked(fixed);
  return as_is.accepted ? as_is : made_right;
}

}  // namespace bitstep::fuzz

#ifndef BITSTEP_FUZZ_NO_MAIN
extern "C" int LLVMFuzzerTestOneInput(const uint8_t* data, size_t size) {
  bitstep::fuzz::snapshot_restore({data, size});
  return 0;
}
#endif
