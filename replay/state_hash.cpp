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
  const Settings& s = world.settings();
  w.fixed(s.dt);
  w.vec(s.gravity);
  w.u32(static_cast<uint32_t>(s.velocity_iterations));
  w.u32(static_cast<uint32_t>(s.position_iterations));
  for (Fixed f : {s.penetration_slop, s.split_impulse_factor, s.max_push_out_speed, s.baumgarte_factor,
                  s.restitution_threshold, s.speculative_distance, s.max_linear_speed, s.max_angular_speed}) {
    w.fixed(f);
  }
  // Sleep adds its block only when on (flag 8), so a world without sleep
  // serialises as it did before sleep existed; flag 16: the guendelman pipeline.
  const bool sleep = s.sleep_method != SleepMethod::off;
  w.u8(static_cast<uint8_t>((s.baumgarte ? 1 : 0) | (s.warm_starting ? 2 : 0) | (s.shock_propagation ? 4 : 0) |
                            (sleep ? 8 : 0) | (s.pipeline == Pipeline::guendelman ? 16 : 0)));
  w.u32(static_cast<uint32_t>(s.shock_iterations));
  if (sleep) {
    w.u8(static_cast<uint8_t>(s.sleep_method));
    for (Fixed f : {s.sleep_epsilon, s.sleep_bias, s.sleep_min_time, s.sleep_time, s.sleep_linear_tolerance,
                    s.sleep_angular_tolerance}) {
      w.fixed(f);
    }
  }
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
    // What the body is made of (a spawned body is part of the state too).
    w.fixed(body.inverse_mass);
    for (const Vec3& row : body.inertia_local.rows) w.vec(row);
    for (const Vec3& row : body.inverse_inertia_local.rows) w.vec(row);
    // Refreshed at the start of a step, from the pose before it moved: an
    // impulse applied between steps uses this one.
    for (const Vec3& row : body.inverse_inertia_world.rows) w.vec(row);
    w.fixed(body.material.static_friction);
    w.fixed(body.material.dynamic_friction);
    w.fixed(body.material.restitution);
    w.fixed(body.material.rolling_resistance);
    w.fixed(body.linear_damping);
    w.fixed(body.angular_damping);
    if (sleep) {
      w.u8(body.asleep ? 1 : 0);
      w.fixed(body.sleep_motion);
      w.u32(body.sleepy_steps);
      w.vec(body.sleep_reference.position);
      w.quat(body.sleep_reference.orientation);
    }
    w.u32(static_cast<uint32_t>(body.shapes.size()));
    for (const Shape& shape : body.shapes) {
      w.u8(static_cast<uint8_t>(shape.type));
      w.vec(shape.half_extents);
      w.fixed(shape.radius);
      w.fixed(shape.half_height);
      w.vec(shape.local.position);
      w.quat(shape.local.orientation);
    }
  }
  w.u32(static_cast<uint32_t>(world.free_slots().size()));
  for (uint32_t slot : world.free_slots()) w.u32(slot);
  w.u32(static_cast<uint32_t>(world.contacts().size()));
  for (const Contact& c : world.contacts()) {
    w.u32(c.key.body_a);
    w.u32(c.key.body_b);
    w.u32(c.key.shape_a);
    w.u32(c.key.shape_b);
    w.u8(static_cast<uint8_t>(c.manifold.point_count));
    w.vec(c.manifold.normal);
    w.fixed(c.manifold.friction_impulse[0]);
    w.fixed(c.manifold.friction_impulse[1]);
    w.fixed(c.manifold.twist_impulse);
    w.fixed(c.manifold.rolling_impulse[0]);
    w.fixed(c.manifold.rolling_impulse[1]);
    for (int i = 0; i < c.manifold.point_count; ++i) {
      const ContactPoint& p = c.manifold.points[static_cast<size_t>(i)];
      w.u32(p.feature);
      w.vec(p.position);  // warm starting matches old points by position too
      w.fixed(p.depth);
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
