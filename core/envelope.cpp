#include "core/envelope.h"

#include <algorithm>
#include <bit>

#include "core/aabb.h"
#include "core/mass.h"
#include "core/shape_types.h"
#include "fixed/decimal.h"

namespace bitstep {

namespace {

bool position_inside(Vec3 p) {
  const Fixed limit = envelope::max_position;
  return abs(p.x) <= limit && abs(p.y) <= limit && abs(p.z) <= limit;
}

// A shape's field as the body's: "shapes[2].radius".
std::string shape_field(int index, const char* field) { return "shapes[" + std::to_string(index) + "]." + field; }

}  // namespace

Result<void> check_shape(const Shape& shape, int index) {
  auto error = [index](const char* field, const char* reason) { return Error{shape_field(index, field), reason}; };
  // Parts of a compound stay within 50 m of the body origin, so that the
  // parallel-axis terms m d^2 of the inertia stay inside the range.
  const Fixed reach = envelope::max_size;
  const Vec3 p = shape.local.position;
  if (abs(p.x) > reach || abs(p.y) > reach || abs(p.z) > reach) return error("position", "more than 50 m from the body origin");
  const Result<void> own = with_shape_type(shape.type, [&](auto type) { return decltype(type)::check(shape); });
  if (!own.ok()) return Error{shape_field(index, own.error().place.c_str()), own.error().reason};
  return {};
}

namespace {

// A given mass is spread over the shapes' total volume; past 2^30 m^3 (a
// compound of over 1,000 of the largest boxes) that sum could leave the range.
constexpr Fixed max_total_volume = 1073741824.0_fx;

std::string text(Fixed value) { return to_string(value); }

// The density and the mass it gives: rho = m / V for a given mass, at most
// max_density (the mass formulas stay in range below it); then the mass of
// the shapes at that density within 0.01..1e5 kg.
Result<void> check_density(const BodyDef& def) {
  const bool mass_given = def.mass > Fixed{};
  if (mass_given) {
    Fixed volume_sum;
    for (const Shape& shape : def.shapes) {
      volume_sum += volume(shape);
      if (volume_sum > max_total_volume) {
        return Error{"shapes", "more than 2^30 m^3 in all to spread a given mass over"};
      }
    }
    // m / V >= max_density  <=>  max_density V <= m (no quotient: 1e5 kg in
    // the smallest sphere is 2.4e10 kg/m^3, beyond the range).
    if (!product_exceeds(envelope::max_density, volume_sum, def.mass)) {
      return Error{"mass", text(def.mass) + " kg in " + text(volume_sum) + " m^3 is denser than " +
                               text(envelope::max_density) + " kg/m^3"};
    }
  } else if (def.density > envelope::max_density) {
    return Error{"density", text(def.density) + " kg/m^3 is denser than " + text(envelope::max_density) + " kg/m^3"};
  }
  if (!mass_properties(def.shapes, def.density, def.mass).ok) {
    if (mass_given) {
      // m / V rounded to Q32.32 lost half of the mass (a volume past 1e6 m^3 per 10 g).
      return Error{"mass", text(def.mass) + " kg in " + text(total_volume(def.shapes)) +
                               " m^3 rounds to a density of " + text(body_density(def.shapes, def.density, def.mass)) +
                               " kg/m^3, too light to hold it"};
    }
    return Error{"density", text(def.density) + " kg/m^3 gives a mass outside 0.01..100000 kg"};
  }
  return {};
}

// --- inputs at a power-of-two scale ------------------------------------------

// A vector v 2^shift: a velocity change far beyond the range, kept with its
// direction and about 30 significant bits.
struct Scaled {
  Vec3 v;
  int shift = 0;
};

// Scaled values are kept below 2^headroom, so that a sum of two and the
// length of a vector of such sums stay inside Q32.32 (below 2^31).
constexpr int headroom = 29;

// The least e with |x| < 2^e (x = raw 2^-32; -32 for zero).
int exponent_bound(Fixed x) { return static_cast<int>(std::bit_width(magnitude(x.raw()))) - raw::fraction_bits; }
int exponent_bound(Vec3 v) { return std::max({exponent_bound(v.x), exponent_bound(v.y), exponent_bound(v.z)}); }
int exponent_bound(const Mat33& m) {
  return std::max({exponent_bound(m.rows[0]), exponent_bound(m.rows[1]), exponent_bound(m.rows[2])});
}

// The shift that brings a quantity below 2^e under 2^headroom.
int shift_for(int e) { return std::max(0, e - headroom); }

// v 2^shift for either sign of shift: up exactly (the caller knows it fits),
// down rounded to nearest (in steps of at most 31 bits).
Vec3 rescale(Vec3 v, int shift) {
  for (; shift > 0; shift -= std::min(shift, 30)) v = v * Fixed::from_int(int32_t{1} << std::min(shift, 30));
  for (; shift < 0; shift += std::min(-shift, 31)) v = v * Fixed::from_raw(int64_t{1} << (32 - std::min(-shift, 31)));
  return v;
}

// s v: |s v_i| < 2^(e_s + e_v).
Scaled times(Fixed s, Vec3 v) {
  const int shift = shift_for(exponent_bound(s) + exponent_bound(v));
  return {rescale(v, -shift) * s, shift};
}

// M v: |row . v| <= 3 max|M| max|v| < 2^(2 + e_M + e_v).
Scaled times(const Mat33& m, Scaled v) {
  const int shift = shift_for(2 + exponent_bound(m) + exponent_bound(v.v));
  return {m * rescale(v.v, -shift), v.shift + shift};
}

// a x b: |a_y b_z - a_z b_y| < 2^(1 + e_a + e_b).
Scaled cross_scaled(Vec3 a, Vec3 b) {
  const int shift = shift_for(1 + exponent_bound(a) + exponent_bound(b));
  return {cross(a, rescale(b, -shift)), shift};
}

// a + b 2^shift, at the scale of the larger.
Scaled plus(Vec3 a, Scaled b) {
  const int shift = std::max(b.shift, shift_for(exponent_bound(a)));
  return {rescale(a, -shift) + rescale(b.v, b.shift - shift), shift};
}

// v 2^shift scaled down to length `limit` when it is longer (the step's
// clamp, which it is at shift 0: the plain formula's bits); the scaled
// length decides, and the clamped result does not depend on the scale.
Vec3 clamp_length(Scaled s, Fixed limit) {
  const Fixed l = length(s.v);
  if (l > rescale({limit, {}, {}}, -s.shift).x) return {mul_div(s.v.x, limit, l), mul_div(s.v.y, limit, l), mul_div(s.v.z, limit, l)};
  return rescale(s.v, s.shift);
}

// v 2^shift, or when that reaches 2^cap, v scaled by a power of two to just
// below 2^cap (same direction).
Vec3 capped(Scaled s, int cap) {
  const int excess = std::max(0, exponent_bound(s.v) + s.shift - cap);
  return rescale(s.v, s.shift - excess);
}

// One step's velocity change from the accumulated force or torque stays
// below 2^28 (m/s, rad/s): v + dt F / m and w + dt I^-1 tau stay in range,
// and the step's clamps apply.
constexpr int max_step_change = 28;

// A total's bound, no higher than a value the range holds at scale 0.
int total_cap(int cap) { return std::min(cap, headroom + 1); }

}  // namespace

Fixed reach(const std::vector<Shape>& shapes) {
  Fixed farthest;
  for (const Shape& s : shapes) {
    const Fixed extent = with_shape_type(s.type, [&](auto type) { return decltype(type)::extent(s); });
    farthest = max(farthest, length(s.local.position) + extent);
  }
  return farthest;
}

namespace {

// min(cap, L / (m x)) = min(cap, L inverse_mass / x) for x > 0, without
// forming L inverse_mass (up to 1.3e10 for 10 g): the cap stands unless
// x cap m > L, i.e. x cap > L inverse_mass.
Fixed momentum_limit(Fixed inverse_mass, Fixed x, Fixed cap) {
  const Fixed at_cap = x * cap;  // <= 150^2 x 500 for the envelope's reach
  if (product_exceeds(envelope::max_reach_momentum, inverse_mass, at_cap)) return cap;
  return mul_div(envelope::max_reach_momentum, inverse_mass, x);
}

// A speed over its limit, as a reason ("faster than 12.5 m/s, ...").
std::string over_limit(Fixed limit, Fixed cap, const char* unit) {
  std::string reason = "faster than " + text(limit) + " " + unit;
  if (limit < cap) reason += ", this body's limit for its mass and reach";
  return reason;
}

}  // namespace

SpeedLimits speed_limits(Fixed inverse_mass, const std::vector<Shape>& shapes, SpeedLimits world) {
  if (inverse_mass == Fixed{}) return world;
  const Fixed r = reach(shapes);
  if (r == Fixed{}) return world;
  return {momentum_limit(inverse_mass, r, world.linear), momentum_limit(inverse_mass, r * r, world.angular)};
}

Result<void> check_envelope(const BodyDef& def) {
  if (!position_inside(def.pose.position)) return Error{"position", "outside +-16000 m"};
  if (def.shapes.empty()) return Error{"shapes", "a body needs at least one shape"};
  for (size_t i = 0; i < def.shapes.size(); ++i) {
    const Shape& shape = def.shapes[i];
    if (shape.type == ShapeType::plane && def.type != BodyType::static_body) {
      return Error{shape_field(static_cast<int>(i), "type"), "a plane belongs to a static body"};
    }
    if (has_triangles(shape.type) && def.type != BodyType::static_body) {
      return Error{shape_field(static_cast<int>(i), "type"),
                   std::string("a ") + shape_name(shape.type) + " belongs to a static body"};
    }
    if (Result<void> refused = check_shape(shape, static_cast<int>(i)); !refused.ok()) return refused;
  }
  if (def.type == BodyType::dynamic) {
    if (def.mass != Fixed{} && (def.mass < envelope::min_mass || def.mass > envelope::max_mass)) {
      return Error{"mass", "outside 0.01..100000 kg"};
    }
    if (def.density <= Fixed{}) return Error{"density", "must be positive"};
    if (Result<void> refused = check_density(def); !refused.ok()) return refused;
  }
  // Components first, so that the length cannot overflow.
  auto faster_than = [](Vec3 v, Fixed limit) {
    if (abs(v.x) > limit || abs(v.y) > limit || abs(v.z) > limit) return true;
    return length(v) > limit;
  };
  const SpeedLimits world{envelope::max_linear_speed, envelope::max_angular_speed};
  SpeedLimits limits = world;
  if (def.type == BodyType::dynamic) {
    // The body as World::create_body makes it: its shapes about the centre of mass.
    const MassProperties mass = mass_properties(def.shapes, def.density, def.mass);
    std::vector<Shape> shapes = def.shapes;
    for (Shape& s : shapes) s.local.position -= mass.center;
    limits = speed_limits(Fixed::one() / mass.mass, shapes, world);
  }
  if (faster_than(def.linear_velocity, limits.linear)) {
    return Error{"velocity", over_limit(limits.linear, world.linear, "m/s")};
  }
  if (faster_than(def.angular_velocity, limits.angular)) {
    return Error{"angular_velocity", over_limit(limits.angular, world.angular, "rad/s")};
  }
  if (def.asleep && def.type != BodyType::dynamic) return Error{"asleep", "only a dynamic body sleeps"};
  if (def.asleep && (def.linear_velocity != Vec3{} || def.angular_velocity != Vec3{})) {
    return Error{"asleep", "a sleeping body has no velocity"};
  }
  return {};
}

void add_impulse(Body& body, Vec3 impulse, Vec3 world_point, SpeedLimits limits) {
  const Vec3 arm = world_point - body.pose.position;
  const Scaled linear_change = times(body.inverse_mass, impulse);
  const Scaled angular_change = times(body.inverse_inertia_world, cross_scaled(arm, impulse));
  body.linear_velocity = clamp_length(plus(body.linear_velocity, linear_change), limits.linear);
  body.angular_velocity = clamp_length(plus(body.angular_velocity, angular_change), limits.angular);
}

void add_force(Body& body, Vec3 force, Vec3 world_point, Fixed dt) {
  const Vec3 arm = world_point - body.pose.position;
  // dt F / m < 2^(e_F + e_1/m + e_dt); the product F / m alone must fit too.
  const int dt_bound = std::max(0, exponent_bound(dt));
  body.force = capped(plus(body.force, {force, 0}), total_cap(max_step_change - exponent_bound(body.inverse_mass) - dt_bound));
  // The step refreshes R I^-1 R^T from the new pose: any rotation's entries
  // are within 3 max|I^-1 local| (Gershgorin), and a row times tau within
  // 3 max|entry| max|tau|: 2^(2 + 2 + e_I^-1 + e_tau).
  const int inverse_inertia_bound = 2 + exponent_bound(body.inverse_inertia_local);
  body.torque = capped(plus(body.torque, cross_scaled(arm, force)),
                       total_cap(max_step_change - 2 - inverse_inertia_bound - dt_bound));
}

Vec3 clamp_speed(Vec3 velocity, Fixed limit) { return clamp_length(Scaled{velocity, 0}, limit); }

namespace {

// The key of the first setting outside the world envelope, or null.
const char* setting_outside_envelope(const Settings& s) {
  const auto within = [](Fixed value, Fixed lo, Fixed hi) { return value >= lo && value <= hi; };
  if (!within(s.dt, envelope::min_dt, envelope::max_dt)) return "dt";
  if (s.substeps < 1 || s.substeps > envelope::max_substeps) return "substeps";
  if (s.dt / Fixed::from_int(s.substeps) < envelope::min_dt) return "substeps";
  if (s.soft_substeps < 0 || s.soft_substeps > envelope::max_substeps) return "soft_substeps";
  if (s.soft_substeps > 0 && s.dt / Fixed::from_int(s.substeps * s.soft_substeps) < envelope::min_dt) {
    return "soft_substeps";
  }
  if (!within(s.contact_hertz, Fixed{}, envelope::max_contact_hertz)) return "contact_hertz";
  if (!within(s.contact_damping_ratio, Fixed{}, envelope::max_damping_ratio)) return "contact_damping_ratio";
  for (Fixed g : {s.gravity.x, s.gravity.y, s.gravity.z}) {
    if (!within(g, -envelope::max_gravity, envelope::max_gravity)) return "gravity";
  }
  if (!within(s.penetration_slop, Fixed{}, envelope::max_size)) return "penetration_slop";
  if (!within(s.split_impulse_factor, Fixed{}, Fixed::one())) return "split_impulse_factor";
  if (!within(s.max_push_out_speed, Fixed{}, envelope::max_linear_speed)) return "max_push_out_speed";
  if (!within(s.baumgarte_factor, Fixed{}, Fixed::one())) return "baumgarte_factor";
  if (!within(s.restitution_threshold, Fixed{}, envelope::max_linear_speed)) return "restitution_threshold";
  if (!within(s.speculative_distance, Fixed{}, envelope::max_size)) return "speculative_distance";
  if (!within(s.max_linear_speed, Fixed::from_raw(1), envelope::max_linear_speed)) return "max_linear_speed";
  if (!within(s.max_angular_speed, Fixed::from_raw(1), envelope::max_angular_speed)) return "max_angular_speed";
  return nullptr;
}

}  // namespace

Result<void> check_settings(const Settings& settings) {
  if (const char* key = setting_outside_envelope(settings)) return Error{key, "outside the world envelope"};
  return {};
}

}  // namespace bitstep
