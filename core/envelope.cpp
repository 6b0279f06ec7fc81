#include "core/envelope.h"

#include "core/mass.h"
#include "fixed/decimal.h"

namespace bitstep {

namespace {

bool position_inside(Vec3 p) {
  const Fixed limit = envelope::max_position;
  return abs(p.x) <= limit && abs(p.y) <= limit && abs(p.z) <= limit;
}

bool size_inside(Fixed s) { return s >= envelope::min_size && s <= envelope::max_size; }

EnvelopeError check_shape(const Shape& shape, int index) {
  auto error = [index](const char* field, const char* reason) { return EnvelopeError{field, index, reason}; };
  // Parts of a compound stay within 50 m of the body origin, so that the
  // parallel-axis terms m d^2 of the inertia stay inside the range.
  const Fixed reach = envelope::max_size;
  const Vec3 p = shape.local.position;
  if (abs(p.x) > reach || abs(p.y) > reach || abs(p.z) > reach) return error("position", "more than 50 m from the body origin");
  switch (shape.type) {
    case ShapeType::box:
      if (!size_inside(shape.half_extents.x) || !size_inside(shape.half_extents.y) ||
          !size_inside(shape.half_extents.z)) {
        return error("half_extents", "outside 0.01..50 m");
      }
      break;
    case ShapeType::sphere:
      if (!size_inside(shape.radius)) return error("radius", "outside 0.01..50 m");
      break;
    case ShapeType::capsule:
      if (!size_inside(shape.radius)) return error("radius", "outside 0.01..50 m");
      if (shape.half_height < Fixed{} || shape.half_height > envelope::max_size) {
        return error("half_height", "outside 0..50 m");
      }
      break;
    case ShapeType::plane: break;
  }
  return {};
}

// A given mass is spread over the shapes' total volume; past 2^30 m^3 (a
// compound of over 1,000 of the largest boxes) that sum could leave the range.
constexpr Fixed max_total_volume = 1073741824.0_fx;

std::string text(Fixed value) { return to_string(value); }

// The density and the mass it gives: rho = m / V for a given mass, at most
// max_density (the mass formulas stay in range below it); then the mass of
// the shapes at that density within 0.01..1e5 kg.
EnvelopeError check_density(const BodyDef& def) {
  const bool mass_given = def.mass > Fixed{};
  if (mass_given) {
    Fixed volume_sum;
    for (const Shape& shape : def.shapes) {
      volume_sum += volume(shape);
      if (volume_sum > max_total_volume) return {"shapes", -1, "more than 2^30 m^3 in all to spread a given mass over"};
    }
    // m / V >= max_density  <=>  max_density V <= m (no quotient: 1e5 kg in
    // the smallest sphere is 2.4e10 kg/m^3, beyond the range).
    if (!product_exceeds(envelope::max_density, volume_sum, def.mass)) {
      return {"mass", -1, text(def.mass) + " kg in " + text(volume_sum) + " m^3 is denser than " +
                              text(envelope::max_density) + " kg/m^3"};
    }
  } else if (def.density > envelope::max_density) {
    return {"density", -1, text(def.density) + " kg/m^3 is denser than " + text(envelope::max_density) + " kg/m^3"};
  }
  if (!mass_properties(def.shapes, def.density, def.mass).ok) {
    if (mass_given) {
      // m / V rounded to Q32.32 lost half of the mass (a volume past 1e6 m^3 per 10 g).
      return {"mass", -1, text(def.mass) + " kg in " + text(total_volume(def.shapes)) + " m^3 rounds to a density of " +
                              text(body_density(def.shapes, def.density, def.mass)) + " kg/m^3, too light to hold it"};
    }
    return {"density", -1, text(def.density) + " kg/m^3 gives a mass outside 0.01..100000 kg"};
  }
  return {};
}

}  // namespace

EnvelopeError check_envelope(const BodyDef& def) {
  if (!position_inside(def.pose.position)) return {"position", -1, "outside +-16000 m"};
  if (def.shapes.empty()) return {"shapes", -1, "a body needs at least one shape"};
  for (size_t i = 0; i < def.shapes.size(); ++i) {
    const Shape& shape = def.shapes[i];
    if (shape.type == ShapeType::plane && def.type != BodyType::static_body) {
      return {"type", static_cast<int>(i), "a plane belongs to a static body"};
    }
    EnvelopeError e = check_shape(shape, static_cast<int>(i));
    if (!e.ok()) return e;
  }
  if (def.type == BodyType::dynamic) {
    if (def.mass != Fixed{} && (def.mass < envelope::min_mass || def.mass > envelope::max_mass)) {
      return {"mass", -1, "outside 0.01..100000 kg"};
    }
    if (def.density <= Fixed{}) return {"density", -1, "must be positive"};
    EnvelopeError e = check_density(def);
    if (!e.ok()) return e;
  }
  // Components first, so that the length cannot overflow.
  auto faster_than = [](Vec3 v, Fixed limit) {
    if (abs(v.x) > limit || abs(v.y) > limit || abs(v.z) > limit) return true;
    return length(v) > limit;
  };
  if (faster_than(def.linear_velocity, envelope::max_linear_speed)) return {"velocity", -1, "faster than 500 m/s"};
  if (faster_than(def.angular_velocity, envelope::max_angular_speed)) return {"angular_velocity", -1, "faster than 100 rad/s"};
  if (def.asleep && def.type != BodyType::dynamic) return {"asleep", -1, "only a dynamic body sleeps"};
  if (def.asleep && (def.linear_velocity != Vec3{} || def.angular_velocity != Vec3{})) {
    return {"asleep", -1, "a sleeping body has no velocity"};
  }
  return {};
}

}  // namespace bitstep
