#include "replay/state_hash.h"

#include <xxhash.h>

#include <array>
#include <bit>
#include <cstring>
#include <new>

#include "replay/state_bytes.h"
#include "replay/state_description.h"

namespace bitstep {

// The values go to a block on the stack and the block to `out` when full:
// a vector insert for each value (1 to 8 bytes) was most of the time a
// snapshot's serialisation took (the C API's fuzz target saves one after
// most calls).
void serialize_state(const World& world, std::vector<uint8_t>& out) {
  const uint64_t step = world.step_count();
  // Each value is copied as 8 little-endian bytes, of which `count` are
  // kept: one copy, where a store a byte checked each index (and the fuzz
  // build traced each check).
  uint8_t block[512];
  size_t used = 0;
  const auto flush = [&] {
    out.insert(out.end(), block, block + used);
    used = 0;
  };
  const auto put = [&](uint64_t value, int count) {
    if (used + 8 > sizeof block) flush();
    if constexpr (std::endian::native == std::endian::big) value = __builtin_bswap64(value);
    std::memcpy(block + used, &value, sizeof value);
    used += static_cast<size_t>(count);
  };
  state_bytes::ByteWriter<decltype(put)> writer{put};
  describe_state(writer, StateParts<false>{step, world.settings(), world.bodies(), world.free_slots(), world.contacts(),
                                             world.joints(), world.free_joint_slots(), world.sensor_overlaps(),
                                             world.cars()});
  flush();
}

namespace {

// The canonical bytes staged in a small buffer and fed to XXH3's streaming
// state whenever it fills: the same hash as XXH3-64 of the whole
// serialisation at once (XXH3 streams give the one-shot result), without
// writing the state to memory first. Appending each value to a vector (a
// size check and a copy per field) took most of a session's per-tick
// checksum.
class HashSink {
 public:
  HashSink() : state_(XXH3_createState()) {
    if (state_ == nullptr) throw std::bad_alloc();
  }
  ~HashSink() { XXH3_freeState(state_); }
  HashSink(const HashSink&) = delete;
  HashSink& operator=(const HashSink&) = delete;

  void reset() {
    XXH3_64bits_reset(state_);
    used_ = 0;
  }
  void put(uint64_t value, int count) {
    if (used_ + 8 > stage_.size()) flush();
    uint8_t* out = stage_.data() + used_;
    for (int i = 0; i < count; ++i) out[i] = static_cast<uint8_t>(value >> (8 * i));
    used_ += static_cast<size_t>(count);
  }
  uint64_t digest() {
    flush();
    return XXH3_64bits_digest(state_);
  }

 private:
  void flush() {
    XXH3_64bits_update(state_, stage_.data(), used_);
    used_ = 0;
  }

  XXH3_state_t* state_;
  std::array<uint8_t, 4096> stage_{};
  size_t used_ = 0;
};

}  // namespace

// One sink per thread (a session hashes every tick: no allocation after
// the first).
uint64_t state_hash(const World& world) {
  thread_local HashSink sink;
  sink.reset();
  const uint64_t step = world.step_count();
  const auto put = [](uint64_t value, int count) { sink.put(value, count); };
  state_bytes::ByteWriter<decltype(put)> writer{put};
  describe_state(writer,
                 StateParts<false>{step, world.settings(), world.bodies(), world.free_slots(), world.contacts(),
                                   world.joints(), world.free_joint_slots(), world.sensor_overlaps(), world.cars()});
  return sink.digest();
}

}  // namespace bitstep
