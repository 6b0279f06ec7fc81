#include "replay/snapshot.h"

#include <xxhash.h>

#include <algorithm>

#include "replay/state_description.h"
#include "replay/state_hash.h"

namespace bitstep {

namespace {

constexpr char magic[8] = {'B', 'I', 'T', 'S', 'T', 'E', 'P', 'S'};
constexpr size_t header_bytes = 8 + 4 + 8;

void put_u32(std::vector<uint8_t>& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<uint8_t>(v >> (8 * i)));
}
void put_u64(std::vector<uint8_t>& out, uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<uint8_t>(v >> (8 * i)));
}

struct Corrupt {
  std::string reason;
};

// Reads the state description's bytes back, little-endian, bounds-checked:
// a value outside its range, a count the bytes left could not hold, or a
// failed requirement throws Corrupt naming the field and the byte.
class ByteReader {
 public:
  static constexpr bool reading = true;
  explicit ByteReader(std::span<const uint8_t> bytes) : bytes_(bytes) {}

  uint64_t u64() { return take(8); }
  uint32_t u32() { return static_cast<uint32_t>(take(4)); }

  template <class T>
  void integer(const char* name, T& value, int count, uint64_t lo, uint64_t hi) {
    value = static_cast<T>(within(take(count), lo, hi, name));
  }
  template <class T>
  void integers(const char* name, T& a, T& b, int count, uint64_t hi) {
    a = static_cast<T>(within(take(count), 0, hi, name));
    b = static_cast<T>(within(take(count), 0, hi, name));
  }
  template <class E, size_t N>
  void choice(const char* name, E& value, const std::array<const char*, N>&, size_t first) {
    value = static_cast<E>(within(take(1), first, N - 1, name));
  }
  template <size_t N>
  void flags(const char* name, uint8_t& bits, const std::array<const char*, N>&) {
    bits = static_cast<uint8_t>(within(take(1), 0, (1u << N) - 1, name));
  }
  void fixed(const char*, Fixed& f) { f = Fixed::from_raw(static_cast<int64_t>(take(8))); }
  void fixeds(const char*, Fixed* values, size_t n) {
    for (size_t i = 0; i < n; ++i) fixed(nullptr, values[i]);
  }
  void vec(const char*, Vec3& v) {
    fixed(nullptr, v.x);
    fixed(nullptr, v.y);
    fixed(nullptr, v.z);
  }
  void quat(const char*, Quat& q) {
    fixed(nullptr, q.w);
    fixed(nullptr, q.x);
    fixed(nullptr, q.y);
    fixed(nullptr, q.z);
  }
  void mat(const char*, Mat33& m) {
    for (Vec3& row : m.rows) vec(nullptr, row);
  }
  template <class F>
  void object(const char*, F&& describe) {
    describe();
  }
  // A count of items of at least `item_bytes` each: never more than the
  // bytes left could hold (a corrupt count must not allocate gigabytes).
  template <class T, class F>
  void list(const char* name, std::vector<T>& items, size_t item_bytes, uint64_t hi, const char*, F&& describe) {
    const uint64_t n = take(4);
    if (n > hi || n * item_bytes > bytes_.size() - at_) fail(std::string("too many ") + name);
    items.resize(static_cast<size_t>(n));
    for (T& item : items) describe(item);
  }
  template <class F>
  void items(const char*, size_t count, F&& describe) {
    for (size_t i = 0; i < count; ++i) describe(i);
  }
  template <class Test, class Reason>
  void require(Test&& test, Reason&& reason) {
    if (!test()) fail(reason());
  }
  template <class F>
  void trailing(bool, bool, F&& describe) {
    if (!done()) describe();
  }

  bool done() const { return at_ == bytes_.size(); }
  [[noreturn]] void fail(const std::string& reason) const {
    throw Corrupt{reason + " (payload byte " + std::to_string(at_) + ")"};
  }

 private:
  uint64_t within(uint64_t value, uint64_t lo, uint64_t hi, const char* name) {
    if (value < lo || value > hi) fail(std::string(name) + " out of range");
    return value;
  }
  uint64_t take(int n) {
    if (bytes_.size() - at_ < static_cast<size_t>(n)) throw Corrupt{"truncated payload"};
    uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= static_cast<uint64_t>(bytes_[at_ + static_cast<size_t>(i)]) << (8 * i);
    at_ += static_cast<size_t>(n);
    return v;
  }

  std::span<const uint8_t> bytes_;
  size_t at_ = 0;
};

World read_world(std::span<const uint8_t> payload) {
  ByteReader r(payload);
  uint64_t step_count = 0;
  Settings settings;
  std::vector<Body> bodies;
  std::vector<uint32_t> free_slots;
  std::vector<Contact> contacts;
  std::vector<Joint> joints;
  std::vector<uint32_t> free_joint_slots;
  std::vector<SensorOverlap> sensor_overlaps;
  std::vector<Car> cars;
  describe_state(r, StateParts<true>{step_count, settings, bodies, free_slots, contacts, joints, free_joint_slots,
                                     sensor_overlaps, cars});
  if (!r.done()) r.fail("bytes left after the state");
  return World::from_state(settings, step_count, std::move(bodies), std::move(free_slots), std::move(contacts),
                           std::move(joints), std::move(free_joint_slots), std::move(sensor_overlaps),
                           std::move(cars));
}

}  // namespace

std::vector<uint8_t> snapshot(const World& world) {
  std::vector<uint8_t> payload;
  serialize_state(world, payload);
  std::vector<uint8_t> image(magic, magic + 8);
  put_u32(image, snapshot_version);
  put_u64(image, payload.size());
  image.insert(image.end(), payload.begin(), payload.end());
  put_u64(image, XXH3_64bits(image.data(), image.size()));
  return image;
}

std::optional<std::string> restore(std::span<const uint8_t> image, World& world) {
  if (image.size() < header_bytes + 8) return "truncated: " + std::to_string(image.size()) + " bytes is less than a header";
  if (!std::equal(magic, magic + 8, image.begin())) return std::string("not a bitstep snapshot (bad magic)");
  ByteReader header(image.subspan(8, 12));
  const uint32_t version = header.u32();
  const uint64_t payload_size = header.u64();
  if (version != snapshot_version) {
    return "snapshot format version " + std::to_string(version) + " (this build reads " +
           std::to_string(snapshot_version) + ")";
  }
  if (payload_size != image.size() - header_bytes - 8) {
    return "truncated or padded: the header says " + std::to_string(payload_size) + " payload bytes, the image has " +
           std::to_string(image.size() - header_bytes - 8);
  }
  const size_t body_end = image.size() - 8;
  ByteReader trailer(image.subspan(body_end, 8));
  if (trailer.u64() != XXH3_64bits(image.data(), body_end)) return std::string("checksum mismatch: the image is corrupt");
  try {
    World restored = read_world(image.subspan(header_bytes, static_cast<size_t>(payload_size)));
    restored.set_executor(world.executor());  // how it steps, not state: kept
    world = std::move(restored);
  } catch (const Corrupt& corrupt) {
    return corrupt.reason;
  }
  return std::nullopt;
}

}  // namespace bitstep
