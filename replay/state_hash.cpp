#include "replay/state_hash.h"

#include <xxhash.h>

namespace bitstep {

namespace {

struct Writer {
  std::vector<uint8_t>& out;

  void u64(uint64_t v) {
    for (int i = 0; i < 8; ++i) out.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  void u32(uint32_t v) {
    for (int i = 0; i < 4; ++i) out.push_back(static_cast<uint8_t>(v >> (8 * i)));
  }
  void u8(uint8_t v) { out.push_back(v); }
  void fixed(Fixed f) { u64(static_cast<uint64_t>(f.raw())); }
  void vec(Vec3 v) {
    fixed(v.x);
    fixed(v.y);
    fixed(v.z);
  }
  void quat(Quat q) {
    fixed(q.w);
    fixed(q.x);
    fixed(q.y);
    fixed(q.z);
  }
};

}  // namespace

void serialize_state(const World& world, std::vector<uint8_t>& out) {
  Writer w{out};
  w.u64(world.step_count());
  w.u32(static_cast<uint32_t>(world.bodies().size()));
  for (const Body& body : world.bodies()) {
    w.u8(body.alive ? 1 : 0);
    w.u32(body.generation);
    if (!body.alive) continue;
    w.u8(static_cast<uint8_t>(body.type));
    w.vec(body.pose.position);
    w.quat(body.pose.orientation);
    w.vec(body.linear_velocity);
    w.vec(body.angular_velocity);
    w.vec(body.force);
    w.vec(body.torque);
  }
  w.u32(static_cast<uint32_t>(world.contacts().size()));
  for (const Contact& c : world.contacts()) {
    w.u32(c.key.body_a);
    w.u32(c.key.body_b);
    w.u32(c.key.shape_a);
    w.u32(c.key.shape_b);
    w.u8(static_cast<uint8_t>(c.manifold.point_count));
    w.fixed(c.manifold.friction_impulse[0]);
    w.fixed(c.manifold.friction_impulse[1]);
    w.fixed(c.manifold.twist_impulse);
    for (int i = 0; i < c.manifold.point_count; ++i) {
      const ContactPoint& p = c.manifold.points[static_cast<size_t>(i)];
      w.u32(p.feature);
      w.fixed(p.normal_impulse);
    }
  }
}

uint64_t state_hash(const World& world) {
  std::vector<uint8_t> bytes;
  serialize_state(world, bytes);
  return XXH3_64bits(bytes.data(), bytes.size());
}

}  // namespace bitstep
