#include "replay/input_bounds.h"

#include "fixed/decimal.h"

namespace bitstep::input_bounds {

std::string outside(Fixed lo, Fixed hi, std::string_view unit) {
  const std::string range = lo == -hi ? "+-" + to_string(hi) : to_string(lo) + ".." + to_string(hi);
  return "outside " + range + (unit.empty() ? "" : " ") + std::string(unit);
}

std::string faster_than(Fixed limit, std::string_view unit) {
  return "faster than " + to_string(limit) + (unit.empty() ? "" : " ") + std::string(unit);
}

Result<void> check_within(Fixed value, Fixed lo, Fixed hi, std::string_view what, std::string_view unit) {
  if (value >= lo && value <= hi) return {};
  return Error{std::string(what), outside(lo, hi, unit)};
}

Result<void> check_vec3(Vec3 v, Fixed limit, std::string_view what, std::string_view unit) {
  const Fixed components[3] = {v.x, v.y, v.z};
  static constexpr const char* names[3] = {".x", ".y", ".z"};
  for (int i = 0; i < 3; ++i) {
    if (Result<void> within = check_within(components[i], -limit, limit, std::string(what) + names[i], unit); !within.ok()) {
      return within;
    }
  }
  return {};
}

Result<void> check_speed(Vec3 v, Fixed limit, std::string_view what, std::string_view unit) {
  if (Result<void> components = check_vec3(v, limit, what, unit); !components.ok()) return components;
  if (length(v) > limit) return Error{std::string(what), faster_than(limit, unit)};
  return {};
}

}  // namespace bitstep::input_bounds
