#include "core/integrate.h"

#include "core/mass.h"

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

// A spinning body keeps its angular momentum L = I w, not w: in body axes
// I dw/dt = -w x I w (Euler's equations without torque). One implicit Newton
// step of I (w' - w) + dt w' x I w' = 0 (Catto, "Numerical Methods", GDC
// 2015), written with I^-1 so the matrix to invert is near the identity:
//   M = 1 + dt I^-1 (skew(w) I - skew(I w)),  w' = w - M^-1 (dt I^-1 (w x I w)).
// Without it a tumbling box's L drifts (tests/tools/bench_tests.cpp: the
// drift shrinks with the step). M can turn singular
// for a fast spin about the middle axis at a large step (det M = 1 -
// dt^2 w^2 (..) ): then the step keeps w, as without the term.
//
// Both M and the residual are unchanged when I is scaled by 2^-k and I^-1 by
// 2^k, so I is brought under 2^15 kg m^2 first (k = 0, the plain bits, for
// every body below it; then |w x I w| <= 100 x 300 x 2^15 < 2^30 at the speed
// clamp): the heaviest, largest body of the envelope (I up to ~2.5e8 kg m^2)
// would take I w and skew(w) I past the number range at ~13 rad/s.
// A body so thin that the step would be stiff (an entry of M or of the
// residual beyond 128: a 100 m rod spun across its axis) keeps w too; below
// that bound the cross products, det M and the correction stay far inside
// the range.
Vec3 gyroscopic_step(const Body& body, Fixed dt) {
  const Quat& q = body.pose.orientation;
  const Vec3 w = rotate_inverse(q, body.angular_velocity);
  Mat33 inertia = body.inertia_local;
  Mat33 inverse_inertia = body.inverse_inertia_local;
  scale_inertia_down(inertia, &inverse_inertia);
  const Vec3 momentum = inertia * w;
  // dt first, so that I^-1 meets the small factors (its entries reach 1e4).
  const Mat33 turning = (skew(w) * inertia - skew(momentum)) * dt;
  const Vec3 gyration = cross(w, momentum) * dt;
  // A product I^-1 X has entries within 3 max|I^-1| max|X|: past 2^30 the
  // step is far stiffer than the bound below (a 10 g, 100 m rod spun across
  // its axis: I^-1 to 2.5e6, X to 1e5) and the products could leave the
  // range, so w is kept as for a stiff step.
  constexpr Fixed product_bound = Fixed::from_raw(int64_t{1} << 60);  // 2^28
  if (product_exceeds(largest_entry(inverse_inertia), max(largest_entry(turning), largest_component(gyration)),
                      product_bound)) {
    return body.angular_velocity;
  }
  const Mat33 m = Mat33::identity() + inverse_inertia * turning;
  const Vec3 residual = inverse_inertia * gyration;
  constexpr Fixed stiff = 128.0_fx;
  if (largest_entry(m) > stiff || largest_component(residual) > stiff) return body.angular_velocity;
  // M^-1 = [c0 c1 c2] / det M with c0 = r1 x r2, c1 = r2 x r0, c2 = r0 x r1
  // (the rows' cross products): plain Fixed arithmetic suffices, det M >= 1/8.
  const Vec3 c0 = cross(m.rows[1], m.rows[2]), c1 = cross(m.rows[2], m.rows[0]), c2 = cross(m.rows[0], m.rows[1]);
  const Fixed det = dot(m.rows[0], c0);
  if (det < 0.125_fx) return body.angular_velocity;
  const Vec3 correction = (c0 * residual.x + c1 * residual.y + c2 * residual.z) / det;
  return rotate(q, w - correction);
}

}  // namespace

Fixed largest_component(Vec3 v) { return max(max(abs(v.x), abs(v.y)), abs(v.z)); }
Fixed largest_entry(const Mat33& m) {
  return max(max(largest_component(m.rows[0]), largest_component(m.rows[1])), largest_component(m.rows[2]));
}

int scale_inertia_down(Mat33& inertia, Mat33* inverse) {
  constexpr Fixed bound = 32768.0_fx;  // 2^15 kg m^2
  int halvings = 0;
  for (; largest_entry(inertia) > bound; ++halvings) {
    inertia = inertia * 0.5_fx;
    if (inverse != nullptr) *inverse = *inverse * 2.0_fx;
  }
  return halvings;
}

void refresh_inverse_inertia(Body& body) {
  const Mat33 r = rotation(body.pose.orientation);
  body.inverse_inertia_world = r * body.inverse_inertia_local * transpose(r);
}

namespace {

// refresh_inverse_inertia, or the cached matrix where it was computed from
// the same orientation and body-frame inverse (the same bits).
void refresh_inverse_inertia(Body& body, InertiaCache::Entry& cached) {
  if (cached.valid && cached.orientation == body.pose.orientation && cached.local == body.inverse_inertia_local) {
    body.inverse_inertia_world = cached.world;
    return;
  }
  refresh_inverse_inertia(body);
  cached = {body.pose.orientation, body.inverse_inertia_local, body.inverse_inertia_world, true};
}

}  // namespace

void integrate_velocity(const Settings& settings, Body& body, InertiaCache::Entry* cached) {
  const Fixed dt = settings.dt;
  if (cached != nullptr) {
    refresh_inverse_inertia(body, *cached);
  } else {
    refresh_inverse_inertia(body);
  }
  body.linear_velocity += (settings.gravity + body.force * body.inverse_mass) * dt;
  body.angular_velocity += body.inverse_inertia_world * body.torque * dt;
  // A torque may take w far past the clamp (add_force bounds dt I^-1 tau by
  // 2^28 rad/s only): clamped before the gyroscopic step, which is bounded
  // for |w| <= 100 rad/s (a 1e5 kg needle pushed 16 km from its axis spun
  // at 2e5 rad/s there and left the range). Without a torque w is within
  // the clamp already (the last step's, or an input's).
  const SpeedLimits limits = body.limits_in(settings);
  if (body.torque != Vec3{}) body.angular_velocity = clamp_length(body.angular_velocity, limits.angular);
  if (body.angular_velocity != Vec3{}) body.angular_velocity = gyroscopic_step(body, dt);
  if (body.linear_damping > Fixed{}) body.linear_velocity *= damping_factor(dt, body.linear_damping);
  if (body.angular_damping > Fixed{}) body.angular_velocity *= damping_factor(dt, body.angular_damping);
  body.linear_velocity = clamp_length(body.linear_velocity, limits.linear);
  body.angular_velocity = clamp_length(body.angular_velocity, limits.angular);
  body.force = body.torque = Vec3{};
}

void integrate_velocities(const Settings& settings, std::vector<Body>& bodies, InertiaCache* cache) {
  if (cache != nullptr) cache->entries.resize(bodies.size());
  for (size_t i = 0; i < bodies.size(); ++i) {
    if (is_awake_dynamic(bodies[i])) integrate_velocity(settings, bodies[i], cache ? &cache->entries[i] : nullptr);
  }
}

void integrate_positions(const Settings& settings, std::vector<Body>& bodies, const PushVelocities& push,
                         const std::vector<BodyRates>& start_velocities, const std::vector<Contact>& contacts,
                         const std::vector<Joint>& joints, const std::vector<TyreContact>& tyres,
                         std::vector<uint8_t>& touching) {
  const Fixed dt = settings.dt;
  touching.assign(bodies.size(), 0);
  for (const Contact& c : contacts) {
    if (c.manifold.point_count == 0) continue;
    touching[c.key.body_a] = touching[c.key.body_b] = 1;
  }
  for (const Joint& j : joints) {
    if (j.alive) touching[j.body_a] = touching[j.body_b] = 1;
  }
  for (const TyreContact& t : tyres) touching[t.chassis] = touching[t.ground] = 1;
  for (size_t i = 0; i < bodies.size(); ++i) {
    Body& body = bodies[i];
    if (!body.alive || body.type == BodyType::static_body || body.asleep) continue;
    const bool pushed = i < push.linear.size();
    const SpeedLimits limits = body.limits_in(settings);
    const Vec3 v = clamp_length(body.linear_velocity, limits.linear);
    const Vec3 w = clamp_length(body.angular_velocity, limits.angular);
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
