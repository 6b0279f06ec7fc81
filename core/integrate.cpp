#include "core/integrate.h"

namespace bitstep {

namespace {

// Scales v down to length `limit` when it is longer (the world envelope).
Vec3 clamp_length(Vec3 v, Fixed limit) {
  const Fixed l = length(v);
  if (l <= limit) return v;
  return {mul_div(v.x, limit, l), mul_div(v.y, limit, l), mul_div(v.z, limit, l)};
}

// Box2D's damping: v /= 1 + dt c, stable for any c >= 0.
Fixed damping_factor(Fixed dt, Fixed damping) { return Fixed::one() / (Fixed::one() + dt * damping); }

}  // namespace

void refresh_inverse_inertia(Body& body) {
  const Mat33 r = rotation(body.pose.orientation);
  body.inverse_inertia_world = r * body.inverse_inertia_local * transpose(r);
}

void integrate_velocity(const Settings& settings, Body& body) {
  const Fixed dt = settings.dt;
  refresh_inverse_inertia(body);
  body.linear_velocity += (settings.gravity + body.force * body.inverse_mass) * dt;
  body.angular_velocity += body.inverse_inertia_world * body.torque * dt;
  if (body.linear_damping > Fixed{}) body.linear_velocity *= damping_factor(dt, body.linear_damping);
  if (body.angular_damping > Fixed{}) body.angular_velocity *= damping_factor(dt, body.angular_damping);
  body.linear_velocity = clamp_length(body.linear_velocity, settings.max_linear_speed);
  body.angular_velocity = clamp_length(body.angular_velocity, settings.max_angular_speed);
  body.force = body.torque = Vec3{};
}

void integrate_velocities(const Settings& settings, std::vector<Body>& bodies) {
  for (Body& body : bodies) {
    if (is_awake_dynamic(body)) integrate_velocity(settings, body);
  }
}

void integrate_positions(const Settings& settings, std::vector<Body>& bodies, const PushVelocities& push,
                         const std::vector<BodyRates>& start_velocities, const std::vector<Contact>& contacts,
                         std::vector<uint8_t>& touching) {
  const Fixed dt = settings.dt;
  touching.assign(bodies.size(), 0);
  for (const Contact& c : contacts) {
    if (c.manifold.point_count == 0) continue;
    touching[c.key.body_a] = touching[c.key.body_b] = 1;
  }
  for (size_t i = 0; i < bodies.size(); ++i) {
    Body& body = bodies[i];
    if (!body.alive || body.type == BodyType::static_body || body.asleep) continue;
    const bool pushed = i < push.linear.size();
    const Vec3 v = clamp_length(body.linear_velocity, settings.max_linear_speed);
    const Vec3 w = clamp_length(body.angular_velocity, settings.max_angular_speed);
    const Vec3 linear = pushed ? v + push.linear[i] : v;
    const Vec3 angular = pushed ? w + push.angular[i] : w;
    body.linear_velocity = v;
    body.angular_velocity = w;
    if (touching[i] || i >= start_velocities.size()) {
      body.pose.position = mul_add(linear, dt, body.pose.position);
    } else {
      // In free flight the mean of the step's start and end velocities: the
      // exact parabola under constant force (plain semi-implicit Euler lags
      // it by g dt t / 2, 16 cm after a 2 s fall at 60 Hz).
      body.pose.position = mul_add((start_velocities[i].linear + v) / 2.0_fx, dt, body.pose.position);
    }
    if (angular != Vec3{}) body.pose.orientation = integrate(body.pose.orientation, angular, dt);
  }
}

}  // namespace bitstep
