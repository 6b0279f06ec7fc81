#include "replay/state_hash.h"

#include <xxhash.h>

#include <array>
#include <bit>
#include <cstring>
#include <new>

#include "replay/state_bytes.h"
#include "replay/state_description.h"

namespace bitstep {

namespace {

// The canonical bytes of the world's state (describe_state), each value
// staged as 8 little-endian bytes of which `count` are kept (one copy, not
// a checked store per byte), and handed to `take(bytes, size)` a block at
// a time: a vector insert or a hash update per value was most of the time
// a snapshot's serialisation and a session's per-tick checksum took.
template <class Take>
void write_state(const World& world, Take take) {
  std::array<uint8_t, 4096> block;
  size_t used = 0;
  const auto put = [&](uint64_t value, int count) {
    if (used + 8 > block.size()) {
      take(block.data(), used);
      used = 0;
    }
    if constexpr (std::endian::native == std::endian::big) value = __builtin_bswap64(value);
    std::memcpy(block.data() + used, &value, sizeof value);
    used += static_cast<size_t>(count);
  };
  const uint64_t step = world.step_count();
  state_bytes::ByteWriter<decltype(put)> writer{put};
  describe_state(writer, state_parts_of(world, step));
  take(block.data(), used);
}

// XXH3's streaming state, one per thread (a session hashes every tick: no
// allocation after the first). A stream gives the one-shot hash of the
// same bytes.
class HashState {
 public:
  HashState() : state_(XXH3_createState()) {
    if (state_ == nullptr) throw std::bad_alloc();
  }
  ~HashState() { XXH3_freeState(state_); }
  HashState(const HashState&) = delete;
  HashState& operator=(const HashState&) = delete;
  XXH3_state_t* get() const { return state_; }

 private:
  XXH3_state_t* state_;
};

}  // namespace

void serialize_state(const World& world, std::vector<uint8_t>& out) {
  write_state(world, [&out](const uint8_t* bytes, size_t size) { out.insert(out.end(), bytes, bytes + size); });
}

uint64_t state_hash(const World& world) {
  thread_local HashState hash;
  XXH3_64bits_reset(hash.get());
  write_state(world, [](const uint8_t* bytes, size_t size) { XXH3_64bits_update(hash.get(), bytes, size); });
  return XXH3_64bits_digest(hash.get());
}

}  // namespace bitstep
