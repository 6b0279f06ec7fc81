#include "replay/snapshot.h"

#include <xxhash.h>

#include <algorithm>

#include "core/envelope.h"
#include "replay/state_hash.h"

namespace bitstep {

namespace {

constexpr char magic[8] = {'B', 'I', 'T', 'S', 'T', 'E', 'P', 'S'};
constexpr size_t header_bytes = 8 + 4 + 8;
constexpr uint32_t max_iterations = 1000;  // as the scene format

void put_u32(std::vector<uint8_t>& out, uint32_t v) {
  for (int i = 0; i < 4; ++i) out.push_back(static_cast<uint8_t>(v >> (8 * i)));
}
void put_u64(std::vector<uint8_t>& out, uint64_t v) {
  for (int i = 0; i < 8; ++i) out.push_back(static_cast<uint8_t>(v >> (8 * i)));
}

struct Corrupt {
  std::string reason;
};

// Reads serialize_state's layout back, little-endian, bounds-checked.
class Reader {
 public:
  explicit Reader(std::span<const uint8_t> bytes) : bytes_(bytes) {}

  uint64_t u64() { return take(8); }
  uint32_t u32() { return static_cast<uint32_t>(take(4)); }
  uint8_t u8() { return static_cast<uint8_t>(take(1)); }
  Fixed fixed() { return Fixed::from_raw(static_cast<int64_t>(u64())); }
  Vec3 vec() {
    const Fixed x = fixed(), y = fixed(), z = fixed();
    return {x, y, z};
  }
  Quat quat() {
    const Fixed w = fixed(), x = fixed(), y = fixed(), z = fixed();
    return {w, x, y, z};
  }
  Mat33 mat() {
    Mat33 m;
    for (Vec3& row : m.rows) row = vec();
    return m;
  }
  // A count of items of at least `item_bytes` each: never more than the
  // bytes left could hold (a corrupt count must not allocate gigabytes).
  uint32_t count(size_t item_bytes, const char* what) {
    const uint32_t n = u32();
    if (static_cast<uint64_t>(n) * item_bytes > bytes_.size() - at_) fail(std::string("too many ") + what);
    return n;
  }
  uint32_t within(uint32_t value, uint32_t lo, uint32_t hi, const char* what) {
    if (value < lo || value > hi) fail(std::string(what) + " out of range");
    return value;
  }
  bool done() const { return at_ == bytes_.size(); }
  [[noreturn]] void fail(const std::string& reason) const {
    throw Corrupt{reason + " (payload byte " + std::to_string(at_) + ")"};
  }

 private:
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

Settings read_settings(Reader& r) {
  Settings s;
  s.dt = r.fixed();
  s.gravity = r.vec();
  s.velocity_iterations = static_cast<int>(r.within(r.u32(), 1, max_iterations, "velocity_iterations"));
  s.position_iterations = static_cast<int>(r.within(r.u32(), 0, max_iterations, "position_iterations"));
  for (Fixed* f : {&s.penetration_slop, &s.split_impulse_factor, &s.max_push_out_speed, &s.baumgarte_factor,
                   &s.restitution_threshold, &s.speculative_distance, &s.max_linear_speed, &s.max_angular_speed}) {
    *f = r.fixed();
  }
  const uint8_t flags = static_cast<uint8_t>(r.within(r.u8(), 0, 31, "settings flags"));
  s.baumgarte = (flags & 1) != 0;
  s.warm_starting = (flags & 2) != 0;
  s.shock_propagation = (flags & 4) != 0;
  s.pipeline = (flags & 16) != 0 ? Pipeline::guendelman : Pipeline::standard;
  s.shock_iterations = static_cast<int>(r.within(r.u32(), 1, max_iterations, "shock_iterations"));
  if (const char* key = setting_outside_envelope(s)) r.fail(std::string(key) + " outside the world envelope");
  if ((flags & 8) != 0) {
    s.sleep_method = static_cast<SleepMethod>(r.within(r.u8(), 1, 2, "sleep method"));
    for (Fixed* f : {&s.sleep_epsilon, &s.sleep_bias, &s.sleep_min_time, &s.sleep_time, &s.sleep_linear_tolerance,
                     &s.sleep_angular_tolerance}) {
      *f = r.fixed();
    }
  }
  if (s.dt <= Fixed{}) r.fail("dt not positive");
  return s;
}

Body read_body(Reader& r, bool sleep) {
  Body body;
  body.alive = r.within(r.u8(), 0, 1, "alive flag") == 1;
  body.generation = r.u32();
  if (!body.alive) return body;
  body.type = static_cast<BodyType>(r.within(r.u8(), 0, 2, "body type"));
  body.pose.position = r.vec();
  body.pose.orientation = r.quat();
  body.linear_velocity = r.vec();
  body.angular_velocity = r.vec();
  body.force = r.vec();
  body.torque = r.vec();
  body.inverse_mass = r.fixed();
  body.inertia_local = r.mat();
  body.inverse_inertia_local = r.mat();
  body.inverse_inertia_world = r.mat();
  body.material.static_friction = r.fixed();
  body.material.dynamic_friction = r.fixed();
  body.material.restitution = r.fixed();
  body.material.rolling_resistance = r.fixed();
  body.linear_damping = r.fixed();
  body.angular_damping = r.fixed();
  if (sleep) {
    body.asleep = r.within(r.u8(), 0, 1, "asleep flag") == 1;
    if (body.asleep && body.type != BodyType::dynamic) r.fail("only a dynamic body sleeps");
    body.sleep_motion = r.fixed();
    body.sleepy_steps = r.u32();
    body.sleep_reference.position = r.vec();
    body.sleep_reference.orientation = r.quat();
  }
  const uint32_t shapes = r.count(1 + 8 * 12, "shapes");
  if (shapes == 0 || shapes > UINT16_MAX) r.fail("a body needs 1..65535 shapes");
  for (uint32_t i = 0; i < shapes; ++i) {
    Shape shape;
    shape.type = static_cast<ShapeType>(r.within(r.u8(), 0, 3, "shape type"));
    shape.half_extents = r.vec();
    shape.radius = r.fixed();
    shape.half_height = r.fixed();
    shape.local.position = r.vec();
    shape.local.orientation = r.quat();
    body.shapes.push_back(shape);
  }
  return body;
}

World read_world(std::span<const uint8_t> payload) {
  Reader r(payload);
  const uint64_t step_count = r.u64();
  const Settings settings = read_settings(r);
  std::vector<Body> bodies(r.count(5, "bodies"));
  for (Body& body : bodies) body = read_body(r, settings.sleep_method != SleepMethod::off);

  // Free slots: exactly the dead slots, each once.
  std::vector<uint32_t> free_slots(r.count(4, "free slots"));
  std::vector<uint8_t> listed(bodies.size(), 0);
  for (uint32_t& slot : free_slots) {
    slot = r.u32();
    if (slot >= bodies.size() || bodies[slot].alive || listed[slot]++ != 0) r.fail("free slot list does not match the dead slots");
  }
  for (size_t i = 0; i < bodies.size(); ++i) {
    if (!bodies[i].alive && listed[i] == 0) r.fail("free slot list does not match the dead slots");
  }

  // Contacts: between live bodies and existing shapes, strictly in key order.
  std::vector<Contact> contacts(r.count(17, "contacts"));
  for (size_t i = 0; i < contacts.size(); ++i) {
    Contact& c = contacts[i];
    c.key.body_a = r.u32();
    c.key.body_b = r.u32();
    const uint32_t shape_a = r.u32(), shape_b = r.u32();
    if (c.key.body_a >= c.key.body_b || c.key.body_b >= bodies.size() || !bodies[c.key.body_a].alive ||
        !bodies[c.key.body_b].alive || shape_a >= bodies[c.key.body_a].shapes.size() ||
        shape_b >= bodies[c.key.body_b].shapes.size()) {
      r.fail("a contact refers to a body or shape that does not exist");
    }
    c.key.shape_a = static_cast<uint16_t>(shape_a);
    c.key.shape_b = static_cast<uint16_t>(shape_b);
    if (i > 0 && !(contacts[i - 1].key < c.key)) r.fail("contacts out of order");
    Manifold& m = c.manifold;
    m.point_count = static_cast<int>(r.within(r.u8(), 0, max_manifold_points, "contact point count"));
    m.normal = r.vec();
    m.friction_impulse[0] = r.fixed();
    m.friction_impulse[1] = r.fixed();
    m.twist_impulse = r.fixed();
    m.rolling_impulse[0] = r.fixed();
    m.rolling_impulse[1] = r.fixed();
    for (int k = 0; k < m.point_count; ++k) {
      ContactPoint& p = m.points[static_cast<size_t>(k)];
      p.feature = r.u32();
      p.position = r.vec();
      p.depth = r.fixed();
      p.normal_impulse = r.fixed();
    }
  }
  if (!r.done()) r.fail("bytes left after the state");
  return World::from_state(settings, step_count, std::move(bodies), std::move(free_slots), std::move(contacts));
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
  Reader header(image.subspan(8, 12));
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
  Reader trailer(image.subspan(body_end, 8));
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
