#include "replay/rollback_state.h"

#include <xxhash.h>

#include <algorithm>
#include <bit>
#include <cstring>
#include <optional>

#include "replay/state_description.h"

namespace bitstep {

// The world's state members (a friend of World): copied out, and swapped
// with a copy that a state was read into whole.
struct WorldStateAccess {
  static void copy(const World& w, OwnedStateParts& p) {
    p.step_count = w.step_count_;
    p.settings = w.settings_;
    p.bodies = w.bodies_;
    p.free_slots = w.free_slots_;
    p.contacts = w.contacts_;
    p.joints = w.joints_;
    p.free_joint_slots = w.free_joint_slots_;
    p.sensor_overlaps = w.sensor_overlaps_;
    p.cars = w.cars_;
    p.characters = w.characters_;
  }
  static void swap(World& w, OwnedStateParts& p) {
    std::swap(w.step_count_, p.step_count);
    std::swap(w.settings_, p.settings);
    w.bodies_.swap(p.bodies);
    w.free_slots_.swap(p.free_slots);
    w.contacts_.swap(p.contacts);
    w.joints_.swap(p.joints);
    w.free_joint_slots_.swap(p.free_joint_slots);
    w.sensor_overlaps_.swap(p.sensor_overlaps);
    w.cars_.swap(p.cars);
    w.characters_.swap(p.characters);
  }
};

namespace {

constexpr uint8_t rollback_magic[8] = {'B', 'I', 'T', 'S', 'T', 'E', 'P', 'R'};
// magic, version, world, save number, state checksum, serials, payload size
constexpr size_t rollback_header_bytes = 8 + 4 + 8 + 8 + 8 + 4 + 8;
constexpr size_t checksum_at = 28, serials_at = 36, payload_size_at = 40;

void put_le(std::span<uint8_t> buffer, size_t at, uint64_t value, int bytes) {
  for (int i = 0; i < bytes; ++i) buffer[at + static_cast<size_t>(i)] = static_cast<uint8_t>(value >> (8 * i));
}

// Writes into a buffer while it has room, and counts every byte. A value
// is stored as 8 little-endian bytes at once where the buffer has room for
// them (the next value overwrites what is past its `count`), byte by byte
// near the end; the count is the Put's own (a store through a pointer that
// may alias it cost a reload per byte).
struct BufferPut {
  std::span<uint8_t> buffer;
  size_t at = 0;
  size_t serial_at = 0;  // the live bodies' serials go apart, from here
  void serial(uint64_t value) {
    if (serial_at + 8 <= buffer.size()) put_le(buffer, serial_at, value, 8);
    serial_at += 8;
  }
  [[gnu::always_inline]] void operator()(uint64_t value, int count) {
    const size_t start = at;
    at = start + static_cast<size_t>(count);
    if (start + 8 <= buffer.size()) {
      if constexpr (std::endian::native == std::endian::big) value = __builtin_bswap64(value);
      std::memcpy(buffer.data() + start, &value, sizeof value);
    } else if (at <= buffer.size()) {
      for (int i = 0; i < count; ++i) buffer[start + static_cast<size_t>(i)] = static_cast<uint8_t>(value >> (8 * i));
    }
  }
};

uint64_t get_le(std::span<const uint8_t> bytes, size_t at, int count) {
  uint64_t v = 0;
  for (int i = 0; i < count; ++i) v |= static_cast<uint64_t>(bytes[at + static_cast<size_t>(i)]) << (8 * i);
  return v;
}

}  // namespace

void RollbackStates::remember(const Body& body) {
  const auto found = statics_.find(body.serial);
  if (found == statics_.end()) {
    statics_.emplace(body.serial, Kept{body, saves_ + 1});
  } else {
    found->second.last_save = saves_ + 1;
  }
}

void RollbackStates::forget_all_but_last(uint64_t saves) {
  const size_t forgotten =
      std::erase_if(statics_, [&](const auto& entry) { return entry.second.last_save + saves <= saves_; });
  if (forgotten > 0 && saves_ >= saves) oldest_restorable_ = std::max(oldest_restorable_, saves_ - saves + 1);
}

// The fields describe_body keeps in `statics` (and the filters block's).
bool RollbackStates::recall(uint64_t serial, Body& body) const {
  const auto found = statics_.find(serial);
  if (found == statics_.end()) return false;
  const Body& kept = found->second.body;
  body.type = kept.type;
  body.inverse_mass = kept.inverse_mass;
  body.inertia_local = kept.inertia_local;
  body.inverse_inertia_local = kept.inverse_inertia_local;
  body.material = kept.material;
  body.linear_damping = kept.linear_damping;
  body.angular_damping = kept.angular_damping;
  body.shapes = kept.shapes;
  body.filter = kept.filter;
  body.sensor = kept.sensor;
  return true;
}

size_t RollbackStates::save(const World& world, std::span<uint8_t> buffer, uint64_t* checksum) {
  if (world.instance() != instance_) {  // serials are numbers of one world object
    statics_.clear();
    instance_ = world.instance();
  }
  // Saves are numbered when written whole: a call that only asks the size
  // marks its bodies as seen in the next one.
  const uint64_t number = saves_ + 1;
  const auto live = static_cast<size_t>(
      std::count_if(world.bodies().begin(), world.bodies().end(), [](const Body& b) { return b.alive; }));
  const size_t payload_at = rollback_header_bytes + 8 * live;
  const uint64_t step = world.step_count();
  state_bytes::ByteWriter<BufferPut> writer{BufferPut{buffer, payload_at, rollback_header_bytes}, this};
  describe_state(writer, state_parts_of(world, step));
  const size_t end = writer.put.at;
  const size_t size = end + 8;
  if (size > buffer.size()) return size;
  saves_ = number;
  // The payload's hash is the state's checksum: it names no serial, no
  // world and no save, so peers with the same state have the same.
  const uint64_t state = XXH3_64bits(buffer.data() + payload_at, end - payload_at);
  if (checksum != nullptr) *checksum = state;
  std::copy(rollback_magic, rollback_magic + 8, buffer.begin());
  put_le(buffer, 8, rollback_state_version, 4);
  put_le(buffer, 12, world.instance(), 8);
  put_le(buffer, 20, saves_, 8);
  put_le(buffer, checksum_at, state, 8);
  put_le(buffer, serials_at, live, 4);
  put_le(buffer, payload_size_at, end - payload_at, 8);
  // The header and the serials, checked by the trailer; the payload by the checksum in the header.
  put_le(buffer, end, XXH3_64bits(buffer.data(), payload_at), 8);
  return size;
}

uint64_t state_checksum(const World& world) {
  thread_local RollbackStates states;
  thread_local std::vector<uint8_t> scratch;
  uint64_t checksum = 0;
  states.save(world, scratch, &checksum);
  return checksum;
}

std::optional<uint64_t> RollbackStates::checksum(std::span<const uint8_t> image) {
  if (image.size() < rollback_header_bytes + 8 || !std::equal(rollback_magic, rollback_magic + 8, image.begin()) ||
      get_le(image, 8, 4) != rollback_state_version) {
    return std::nullopt;
  }
  return get_le(image, checksum_at, 8);
}

void RollbackStates::save(const World& world, std::vector<uint8_t>& buffer, uint64_t* checksum) {
  buffer.resize(buffer.capacity());  // as large as it has been
  size_t size = save(world, std::span<uint8_t>(buffer), checksum);
  if (size > buffer.size()) {
    buffer.resize(size);
    size = save(world, std::span<uint8_t>(buffer), checksum);
  }
  buffer.resize(size);
}

Result<void> RollbackStates::restore(std::span<const uint8_t> image, World& world) const {
  const auto refuse = [](std::string reason) { return Error{{}, std::move(reason)}; };
  if (image.size() < rollback_header_bytes + 8 || !std::equal(rollback_magic, rollback_magic + 8, image.begin())) {
    return refuse("not a rollback state");
  }
  if (get_le(image, 8, 4) != rollback_state_version) {
    return refuse("rollback state version " + std::to_string(get_le(image, 8, 4)));
  }
  if (get_le(image, 12, 8) != world.instance() || world.instance() != instance_) {
    return refuse("a rollback state of another world");
  }
  if (get_le(image, 20, 8) < oldest_restorable_) {
    return refuse("older than the states kept: a body it names was forgotten");
  }
  const uint64_t serials = get_le(image, serials_at, 4), payload = get_le(image, payload_size_at, 8);
  const size_t room = image.size() - rollback_header_bytes - 8;
  if (serials > room / 8 || payload != room - 8 * serials) return refuse("truncated or padded");
  const size_t payload_at = rollback_header_bytes + 8 * static_cast<size_t>(serials);
  if (get_le(image, image.size() - 8, 8) != XXH3_64bits(image.data(), payload_at) ||
      get_le(image, checksum_at, 8) != XXH3_64bits(image.data() + payload_at, static_cast<size_t>(payload))) {
    return refuse("checksum mismatch: the image is corrupt");
  }
  // Our own bytes, intact. Read into a copy of the world's state (as in
  // place: a body still in its slot keeps its static fields), swapped in
  // only when read whole: a refused state changes nothing.
  WorldStateAccess::copy(world, read_);
  try {
    state_bytes::ByteReader r(image.subspan(payload_at, static_cast<size_t>(payload)), this, &marks_,
                              image.subspan(rollback_header_bytes, payload_at - rollback_header_bytes));
    describe_state(r, read_.refs());
    if (!r.done()) r.fail("bytes left after the state");
  } catch (const Error& corrupt) {  // state_bytes::ByteReader's
    return refuse("rollback state unreadable: " + corrupt.message());
  }
  WorldStateAccess::swap(world, read_);
  world.after_in_place_restore();
  return {};
}

}  // namespace bitstep
