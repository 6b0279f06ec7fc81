#include "replay/state_hash.h"

#include <xxhash.h>

#include "replay/state_description.h"

namespace bitstep {

namespace {

// Writes the state description as its canonical bytes.
struct ByteWriter {
  static constexpr bool reading = false;
  std::vector<uint8_t>& out;

  void bytes(uint64_t v, int count) {
    for (int i = 0; i < count; ++i) out.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  template <class T>
  void integer(const char*, const T& value, int count, uint64_t, uint64_t) {
    bytes(static_cast<uint64_t>(value), count);
  }
  template <class T>
  void integers(const char*, const T& a, const T& b, int count, uint64_t) {
    bytes(a, count);
    bytes(b, count);
  }
  template <class E, size_t N>
  void choice(const char*, const E& value, const std::array<const char*, N>&, size_t) {
    bytes(static_cast<uint64_t>(value), 1);
  }
  template <size_t N>
  void flags(const char*, const uint8_t& bits, const std::array<const char*, N>&) {
    bytes(bits, 1);
  }
  void fixed(const char*, Fixed f) { bytes(static_cast<uint64_t>(f.raw()), 8); }
  void fixeds(const char*, const Fixed* values, size_t n) {
    for (size_t i = 0; i < n; ++i) fixed(nullptr, values[i]);
  }
  void vec(const char*, Vec3 v) {
    fixed(nullptr, v.x);
    fixed(nullptr, v.y);
    fixed(nullptr, v.z);
  }
  void quat(const char*, Quat q) {
    fixed(nullptr, q.w);
    fixed(nullptr, q.x);
    fixed(nullptr, q.y);
    fixed(nullptr, q.z);
  }
  void mat(const char*, const Mat33& m) {
    for (const Vec3& row : m.rows) vec(nullptr, row);
  }
  template <class F>
  void object(const char*, F&& describe) {
    describe();
  }
  template <class T, class F>
  void list(const char*, const std::vector<T>& items, size_t, uint64_t, const char*, F&& describe) {
    bytes(items.size(), 4);
    for (const T& item : items) describe(item);
  }
  template <class F>
  void items(const char*, size_t count, F&& describe) {
    for (size_t i = 0; i < count; ++i) describe(i);
  }
  template <class Test, class Reason>
  void require(Test&&, Reason&&) {}  // a world's own state holds
  template <class F>
  void trailing(bool present, bool, F&& describe) {
    if (present) describe();
  }
};

}  // namespace

void serialize_state(const World& world, std::vector<uint8_t>& out) {
  const uint64_t step = world.step_count();
  ByteWriter writer{out};
  describe_state(writer, StateParts<false>{step, world.settings(), world.bodies(), world.free_slots(), world.contacts(),
                                             world.joints(), world.free_joint_slots(), world.sensor_overlaps(),
                                             world.cars()});
}

uint64_t state_hash(const World& world) {
  std::vector<uint8_t> bytes;
  serialize_state(world, bytes);
  return XXH3_64bits(bytes.data(), bytes.size());
}

}  // namespace bitstep
