#include "core/car.h"

#include "core/envelope.h"
#include "core/query.h"
#include "core/settings.h"
#include "core/tyre_rows.h"

namespace bitstep {

Result<void> check_car(const CarDef& def, const std::vector<Body>& bodies) {
  const BodyId c = def.chassis;
  if (c.index >= bodies.size() || !bodies[c.index].alive || bodies[c.index].generation != c.generation) {
    return Error{"chassis", "not a live body"};
  }
  if (bodies[c.index].type != BodyType::dynamic) return Error{"chassis", "not a dynamic body"};
  if (def.wheels.empty() || def.wheels.size() > 8) return Error{"wheels", "1..8"};
  for (const WheelDef& w : def.wheels) {
    const Fixed reach = envelope::max_size + envelope::max_size;
    if (abs(w.attachment.x) > reach || abs(w.attachment.y) > reach || abs(w.attachment.z) > reach) {
      return Error{"wheels", "an attachment farther than 100 m from the chassis"};
    }
  }
  auto within = [](Fixed v, Fixed lo, Fixed hi) { return lo <= v && v <= hi; };
  if (!within(def.wheel_radius, 0.05_fx, 5.0_fx)) return Error{"wheel_radius", "0.05..5 m"};
  if (!within(def.rest_length, Fixed{}, 5.0_fx)) return Error{"rest_length", "0..5 m"};
  if (!within(def.stiffness, Fixed{}, 10000000.0_fx)) return Error{"stiffness", "0..1e7 N/m"};
  if (!within(def.damping, Fixed{}, 1000000.0_fx)) return Error{"damping", "0..1e6 N s/m"};
  if (!within(def.grip, Fixed{}, 10.0_fx)) return Error{"grip", "0..10"};
  if (!within(def.drive_force, Fixed{}, 1000000.0_fx)) return Error{"drive_force", "0..1e6 N"};
  if (!within(def.brake_force, Fixed{}, 1000000.0_fx)) return Error{"brake_force", "0..1e6 N"};
  if (!within(def.max_steer, Fixed{}, 1.5_fx)) return Error{"max_steer", "0..1.5 rad"};
  if (def.rays_per_wheel < 1 || def.rays_per_wheel > 8) return Error{"rays_per_wheel", "1..8"};
  return {};
}

namespace {

Vec3 up_in(const Body& chassis) { return rotate(chassis.pose.orientation, Vec3{Fixed{}, Fixed::one(), Fixed{}}); }

// Where one wheel touches: its rays spread along `ahead` across 0.8 of the
// radius, each as long as the suspension plus the wheel's depth below its
// centre at that offset (sqrt(r^2 - o^2): the rays trace the wheel's
// circle over a bump); the most compressed ray wins.
WheelState touch(const WorldQuery& query, const CarDef& def, const Body& chassis, const WheelDef& wheel, Vec3 ahead) {
  const Vec3 down = -up_in(chassis);
  const Vec3 top = chassis.pose.position + rotate(chassis.pose.orientation, wheel.attachment);
  const Fixed r = def.wheel_radius;
  const int n = def.rays_per_wheel;
  WheelState best;
  for (int k = 0; k < n; ++k) {
    const Fixed offset = n == 1 ? Fixed{} : r * Fixed::from_ratio(4 * (2 * k - (n - 1)), 5 * (n - 1));
    const Fixed length = def.rest_length + sqrt(r * r - offset * offset);
    const Vec3 origin = top + ahead * offset;
    const auto hit = query.cast_ray(origin, down * length, {UINT32_MAX, def.chassis});
    if (!hit) continue;
    const Fixed compression = length - hit->fraction * length;
    if (best.on_ground && compression <= best.compression) continue;
    best = {true, compression, Fixed{}, hit->point, hit->normal, Vec3{}, hit->body.index};
  }
  return best;
}

// The suspension as a soft row of the solve: a spring k and damper c
// integrated implicitly over the step h. With s the compression, C = -s
// (negative while compressed) and J v = dC/dt the wheel point's speed away
// from the ground along its normal n, they push the chassis along n with
//   F = -k C - c J v.
// Implicitly, at the step's end, where the velocity is v' and C has become
// C + h J v', the step's impulse is
//   N = h F = -h k (C + h J v') - h c J v'
// so that
//   J v' + (beta / h) C + gamma N = 0,  beta = h k / (c + h k),  gamma = 1 / (h (c + h k)):
// a row asking J v' = target - gamma N with target = -(beta / h) C =
// k s / (c + h k), the speed outward the compression asks for, softened by
// gamma (the solve's effective mass is 1 / (J M^-1 J^T + gamma)). At rest
// (J v' = 0) N = h k s: the spring's force k s, so the chassis sags m g /
// (n k). Stable for every k and h, where an explicit force k s + c ds/dt
// diverges once h^2 k / m passes 4. False when neither spring nor damper
// acts (gamma would be infinite: no row).
bool suspension_row(const CarDef& def, Fixed compression, Fixed h, TyreContact& tyre) {
  const Fixed c_plus_hk = def.damping + h * def.stiffness;
  const Fixed h_c_plus_hk = h * c_plus_hk;
  if (h_c_plus_hk <= Fixed{}) return false;
  tyre.softness = Fixed::one() / h_c_plus_hk;
  tyre.suspension_target = mul_div(def.stiffness, compression, c_plus_hk);
  return true;
}

}  // namespace

Aabb car_region(const std::vector<Car>& cars, const std::vector<Body>& bodies) {
  bool any = false;
  Aabb region;
  for (const Car& car : cars) {
    if (!car.alive) continue;
    const Body& chassis = bodies[car.def.chassis.index];
    Fixed reach;
    for (const WheelDef& w : car.def.wheels) {
      reach = max(reach, max(abs(w.attachment.x), max(abs(w.attachment.y), abs(w.attachment.z))));
    }
    reach = reach * Fixed::from_int(2) + car.def.rest_length + car.def.wheel_radius + car.def.wheel_radius;
    const Vec3 c = chassis.pose.position, r{reach, reach, reach};
    const Aabb box{c - r, c + r};
    region = any ? region.merged(box) : box;
    any = true;
  }
  return region;
}

void drive_cars(const WorldQuery& query, Fixed dt, std::vector<Body>& bodies, std::vector<Car>& cars,
                std::vector<TyreContact>& tyres, std::vector<uint32_t>& to_wake) {
  tyres.clear();
  for (uint32_t c = 0; c < cars.size(); ++c) {
    Car& car = cars[c];
    if (!car.alive) continue;
    const CarDef& def = car.def;
    Body& chassis = bodies[def.chassis.index];
    car.wheels.assign(def.wheels.size(), WheelState{});
    if (chassis.asleep) {
      // Parked: brake and steering move nothing at rest, so only the
      // throttle wakes it (a car with its handbrake on sleeps).
      if (car.controls.throttle == Fixed{}) continue;
      to_wake.push_back(def.chassis.index);
    }
    const Vec3 up = up_in(chassis);
    const Vec3 ahead = rotate(chassis.pose.orientation, Vec3{Fixed{}, Fixed{}, Fixed::one()});
    // The steered wheels turn about the chassis's up (positive: toward +x,
    // the left of a car facing +z).
    const Fixed angle = clamp(car.controls.steer, -Fixed::one(), Fixed::one()) * def.max_steer;
    const Vec3 steered = ahead * cos(angle) + cross(up, ahead) * sin(angle);
    const Fixed throttle = clamp(car.controls.throttle, -Fixed::one(), Fixed::one());
    const Fixed brake = clamp(car.controls.brake, Fixed{}, Fixed::one());
    for (uint32_t w = 0; w < def.wheels.size(); ++w) {
      WheelState& state = car.wheels[w];
      const Vec3 heading = def.wheels[w].steered ? steered : ahead;
      state = touch(query, def, chassis, def.wheels[w], heading);
      const TyreImpulse last = car.tyre_impulses[w];
      car.tyre_impulses[w] = {};  // a wheel off the ground keeps none
      if (!state.on_ground) continue;
      // The suspension (a soft row, suspension_row) and the tyre (rows
      // within the friction circle of its impulse), between the chassis and
      // the body under the wheel at its ground point, the pair's
      // coefficients mixed as contacts mix them. The ground pushes back
      // along its normal (as Bullet's raycast vehicle does): along the
      // chassis's tilted up, a car squatting as it accelerates would lose
      // part of its drive to the spring's slant.
      const Body& ground = bodies[state.ground];
      if (ground.type == BodyType::dynamic && ground.asleep) to_wake.push_back(state.ground);
      const Vec3 n = state.normal;
      TyreContact tyre;
      if (!suspension_row(def, state.compression, dt, tyre)) continue;
      tyre.car = c;
      tyre.wheel = w;
      tyre.chassis = def.chassis.index;
      tyre.ground = state.ground;
      tyre.point = state.point;
      tyre.normal = n;
      tyre.forward = normalize_or(heading - n * dot(heading, n), ahead);
      tyre.side = cross(n, tyre.forward);
      tyre.drive = def.wheels[w].driven ? throttle * def.drive_force * dt : Fixed{};
      tyre.brake = brake * def.brake_force * dt;
      tyre.static_friction = sqrt(def.grip * ground.material.static_friction);
      tyre.dynamic_friction = sqrt(def.grip * ground.material.dynamic_friction);
      tyre.suspension_impulse = last.suspension;
      tyre.forward_impulse = last.forward;
      tyre.side_impulse = last.side;
      tyres.push_back(tyre);
    }
  }
}

void record_tyre_forces(const std::vector<TyreContact>& tyres, Fixed dt, std::vector<Car>& cars) {
  for (const TyreContact& tyre : tyres) {
    Car& car = cars[tyre.car];
    car.tyre_impulses[tyre.wheel] = {tyre.suspension_impulse, tyre.forward_impulse, tyre.side_impulse};
    WheelState& wheel = car.wheels[tyre.wheel];
    wheel.suspension_force = tyre.suspension_impulse / dt;
    wheel.tyre_force = (tyre.forward * tyre.forward_impulse + tyre.side * tyre.side_impulse) / dt;
  }
}

}  // namespace bitstep
