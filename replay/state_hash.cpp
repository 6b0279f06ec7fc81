#include "replay/state_hash.h"

#include <xxhash.h>

#include "replay/state_bytes.h"
#include "replay/state_description.h"

namespace bitstep {

void serialize_state(const World& world, std::vector<uint8_t>& out) {
  const uint64_t step = world.step_count();
  const auto put = [&out](uint64_t value, int count) {
    uint8_t bytes[8];
    for (int i = 0; i < count; ++i) bytes[i] = static_cast<uint8_t>(value >> (8 * i));
    out.insert(out.end(), bytes, bytes + count);
  };
  state_bytes::ByteWriter<decltype(put)> writer{put};
  describe_state(writer, StateParts<false>{step, world.settings(), world.bodies(), world.free_slots(), world.contacts(),
                                             world.joints(), world.free_joint_slots(), world.sensor_overlaps(),
                                             world.cars()});
}

// The bytes in a buffer each thread keeps (a session hashes every tick:
// after the first, no allocation), then XXH3-64 of them at once.
uint64_t state_hash(const World& world) {
  thread_local std::vector<uint8_t> bytes;
  bytes.clear();
  serialize_state(world, bytes);
  return XXH3_64bits(bytes.data(), bytes.size());
}

}  // namespace bitstep
