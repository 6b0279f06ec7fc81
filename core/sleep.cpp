#include "core/sleep.h"

#include <algorithm>

#include "core/integrate.h"

namespace bitstep {

namespace {

constexpr uint8_t island_supported = 1;    // touches a static body or a kinematic one at rest
constexpr uint8_t island_has_sleeper = 2;  // holds a sleeping body
constexpr uint8_t island_woken = 4;        // woken this step: stays awake until the next
constexpr uint8_t island_touched = 8;      // a body fast enough to wake it touches it

// Steps that make up `time` (s), at least one: round(time / dt), exact on
// the raw values (both positive and below 2^62).
uint32_t steps_for(Fixed time, Fixed dt) {
  const int64_t steps = (time.raw() + dt.raw() / 2) / dt.raw();
  return static_cast<uint32_t>(std::clamp<int64_t>(steps, 1, INT32_MAX));
}

// v.v + w.w (m^2/s^2 and rad^2/s^2 added as numbers, as Kenwright's simple impulse engine does).
Fixed motion_of(const Body& body) { return length_sq(body.linear_velocity) + length_sq(body.angular_velocity); }

// The fastest speed (m/s) at which `toucher` closes in on the sleeping body
// of contact m at one of its points; `normal` points from the toucher to it.
Fixed closing_speed(const Body& toucher, const Manifold& m, Vec3 normal) {
  Fixed fastest = Fixed::lowest();
  for (int i = 0; i < m.point_count; ++i) {
    const Vec3 r = m.points[static_cast<size_t>(i)].position - toucher.pose.position;
    fastest = max(fastest, dot(toucher.linear_velocity + cross(toucher.angular_velocity, r), normal));
  }
  return fastest;
}

// Does awake body `toucher`, in contact m with a sleeping body, wake it?
// A speculative contact counts when the toucher closes in. motion: the
// toucher's v.v + w.w exceeds 2 epsilon (as in Kenwright's engine). still:
// it closes in faster than the tolerance per sleep time, or touches and has
// just left its own tolerance (a body sliding along the sleeper).
bool wakes_on_touch(const Settings& settings, const Body& toucher, const Manifold& m, Vec3 normal) {
  if (toucher.type == BodyType::kinematic) return moves(toucher);
  if (!is_awake_dynamic(toucher)) return false;
  const bool touching = touches(m);
  const Fixed closing = closing_speed(toucher, m, normal);
  if (settings.sleep_method == SleepMethod::motion) {
    return motion_of(toucher) > settings.sleep_epsilon * 2.0_fx && (touching || closing > Fixed{});
  }
  const Fixed slow = settings.sleep_linear_tolerance / max(settings.sleep_time, settings.dt);
  return closing > slow || (touching && toucher.sleepy_steps == 0);
}

void wake(const Settings& settings, Body& body) {
  body.asleep = false;
  reset_sleep(settings, body);
}

// The rotation angle from `reference` to `q`, as 2 |vector part of q r^-1|
// = 2 sin(angle / 2) (within 0.01 % of the angle below 0.05 rad).
Fixed rotation_between(Quat q, Quat reference) {
  const Quat r = q * conjugate(reference);
  return length(Vec3{r.x, r.y, r.z}) * 2.0_fx;
}

// Advances one awake body's measure; true when it is sleepy.
bool update_measure(const Settings& settings, Body& body) {
  if (settings.sleep_method == SleepMethod::motion) {
    const Fixed bias = settings.sleep_bias;
    body.sleep_motion = min(bias * body.sleep_motion + (Fixed::one() - bias) * motion_of(body),
                            settings.sleep_epsilon * 10.0_fx);
    const uint32_t needed = steps_for(settings.sleep_min_time, settings.dt);
    if (body.sleep_motion < settings.sleep_epsilon) {
      if (body.sleepy_steps < needed) ++body.sleepy_steps;
    } else {
      body.sleepy_steps = 0;
    }
    return body.sleepy_steps >= needed;
  }
  // still
  const Vec3 moved = body.pose.position - body.sleep_reference.position;
  const Fixed reach = settings.sleep_linear_tolerance;
  const bool near = abs(moved.x) <= reach && abs(moved.y) <= reach && abs(moved.z) <= reach &&
                    length(moved) <= reach &&
                    rotation_between(body.pose.orientation, body.sleep_reference.orientation) <=
                        settings.sleep_angular_tolerance;
  const uint32_t needed = steps_for(settings.sleep_time, settings.dt);
  if (!near) {
    body.sleep_reference = body.pose;
    body.sleepy_steps = 0;
    return false;
  }
  if (body.sleepy_steps < needed) ++body.sleepy_steps;
  // Over the second half of the time the velocities ramp down to zero:
  // scale (needed - steps) / (needed - half).
  const uint32_t half = needed / 2;
  if (body.sleepy_steps > half) {
    const Fixed scale = Fixed::from_int(static_cast<int32_t>(needed - body.sleepy_steps)) /
                        Fixed::from_int(static_cast<int32_t>(needed - half));
    body.linear_velocity *= scale;
    body.angular_velocity *= scale;
  }
  return body.sleepy_steps >= needed;
}

}  // namespace

void reset_sleep(const Settings& settings, Body& body) {
  // A woken body starts above epsilon (Kenwright's engine: 2 epsilon), so
  // that it stays awake for a while before it can be sleepy again.
  body.sleep_motion = settings.sleep_epsilon * 2.0_fx;
  body.sleepy_steps = 0;
  body.sleep_reference = body.pose;
}

int wake_islands(const Settings& settings, std::vector<Body>& bodies, const std::vector<Contact>& contacts,
                 const std::vector<Joint>& joints, SleepScratch& scratch, bool forces_done) {
  Islands& islands = scratch.islands;
  build_islands(bodies, contacts, joints, islands);
  for (Body& body : bodies) {
    if (body.asleep && body.sleepy_steps == 0) body.sleepy_steps = 1;  // created asleep: its contacts are found now
  }
  std::vector<uint8_t>& flags = scratch.island_flags;
  flags.assign(islands.count(), 0);
  for (uint32_t i = 0; i < bodies.size(); ++i) {
    if (islands.island_of[i] != no_island && bodies[i].asleep) flags[islands.island_of[i]] |= island_has_sleeper;
  }
  for (const Contact& c : contacts) {
    if (c.manifold.point_count == 0) continue;
    const Body& a = bodies[c.key.body_a];
    const Body& b = bodies[c.key.body_b];
    const uint32_t island_a = islands.island_of[c.key.body_a], island_b = islands.island_of[c.key.body_b];
    // Resting on something that does not move.
    const bool holds_a = a.type != BodyType::dynamic && !moves(a);
    const bool holds_b = b.type != BodyType::dynamic && !moves(b);
    if (holds_a && island_b != no_island && touches(c.manifold)) flags[island_b] |= island_supported;
    if (holds_b && island_a != no_island && touches(c.manifold)) flags[island_a] |= island_supported;
    // A body touching a sleeping one (a speculative contact counts: it is
    // closing in this step).
    const Vec3 n = c.manifold.normal;  // from a to b
    if (b.asleep && wakes_on_touch(settings, a, c.manifold, n)) flags[island_b] |= island_touched;
    if (a.asleep && wakes_on_touch(settings, b, c.manifold, -n)) flags[island_a] |= island_touched;
  }
  // Hung from something that does not move (a chain from a static bar).
  for (const Joint& j : joints) {
    if (!j.alive) continue;
    const Body& a = bodies[j.body_a];
    const Body& b = bodies[j.body_b];
    if (a.type != BodyType::dynamic && !moves(a) && islands.island_of[j.body_b] != no_island) {
      flags[islands.island_of[j.body_b]] |= island_supported;
    }
    if (b.type != BodyType::dynamic && !moves(b) && islands.island_of[j.body_a] != no_island) {
      flags[islands.island_of[j.body_a]] |= island_supported;
    }
  }
  int woken = 0;
  for (size_t k = 0; k < islands.count(); ++k) {
    if (!(flags[k] & island_has_sleeper)) continue;
    if (!(flags[k] & island_touched) && (flags[k] & island_supported)) continue;
    flags[k] |= island_woken;
    for (uint32_t m = islands.first[k]; m < islands.first[k + 1]; ++m) {
      Body& body = bodies[islands.members[m]];
      if (!body.asleep) continue;
      wake(settings, body);
      if (forces_done) integrate_velocity(settings, body);
      ++woken;
    }
  }
  return woken;
}

void sleep_islands(const Settings& settings, std::vector<Body>& bodies, SleepScratch& scratch) {
  const Islands& islands = scratch.islands;
  for (size_t k = 0; k < islands.count(); ++k) {
    bool all_sleepy = true, any_awake = false;
    for (uint32_t m = islands.first[k]; m < islands.first[k + 1]; ++m) {
      Body& body = bodies[islands.members[m]];
      if (body.asleep) continue;
      any_awake = true;
      // Every body's measure advances, so no loop may stop early.
      if (!update_measure(settings, body)) all_sleepy = false;
    }
    const uint8_t f = scratch.island_flags[k];
    if (!any_awake || !all_sleepy || (f & island_woken)) continue;
    if (!(f & (island_supported | island_has_sleeper))) continue;  // rests on nothing: never sleeps in the air
    for (uint32_t m = islands.first[k]; m < islands.first[k + 1]; ++m) {
      Body& body = bodies[islands.members[m]];
      body.asleep = true;
      body.linear_velocity = body.angular_velocity = Vec3{};
    }
  }
}

void wake_islands_of(const Settings& settings, std::vector<Body>& bodies, const std::vector<Contact>& contacts,
                     const std::vector<Joint>& joints, const std::vector<uint32_t>& slots) {
  bool any = false;
  for (const uint32_t slot : slots) any = any || (bodies[slot].alive && bodies[slot].asleep);
  if (!any) return;
  Islands islands;
  build_islands(bodies, contacts, joints, islands);
  for (const uint32_t slot : slots) {
    const uint32_t k = islands.island_of[slot];
    if (k == no_island) continue;
    for (uint32_t m = islands.first[k]; m < islands.first[k + 1]; ++m) {
      Body& body = bodies[islands.members[m]];
      if (body.asleep) wake(settings, body);
    }
  }
}

}  // namespace bitstep
