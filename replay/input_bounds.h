// The bounds of a game's inputs between steps: an impulse or force and the
// point it acts at, a velocity set outright, a car's controls. The replay
// reader refuses an input file past them (replay/replay.cpp) and the facade
// (replay/simulation.h) and the C API (replay/bitstep.h) refuse a call past
// them, with the same bounds and words: a match recorded and the same match
// played live take exactly the same inputs, and every input taken is one
// the world's arithmetic was bounded for (a velocity of 2^31 m/s overflows
// the speed clamp's length; the checked build aborts on it).
#pragma once

#include <string>
#include <string_view>

#include "core/error.h"
#include "core/settings.h"
#include "fixed/vec3.h"

namespace bitstep::input_bounds {

// Per component. Their effect on a body is not bounded here (it depends on
// the body then in the slot and where it is): 1e6 N s on 0.01 kg is 1e8 m/s,
// at the corner of a 0.01 m box ~1e12 rad/s. World::apply_impulse and
// apply_force compute it at a scale where it cannot overflow, and the speed
// clamps apply (core/envelope.h).
inline constexpr Fixed max_impulse = 1000000.0_fx;  // N s
inline constexpr Fixed max_force = 1000000.0_fx;    // N
// The point an impulse or force acts at, per component: where a scene may
// place a body (core/settings.h, envelope::max_position).
inline constexpr Fixed max_point = envelope::max_position;  // m
// A velocity set outright, per component and in length: the world's clamps.
inline constexpr Fixed max_linear_speed = envelope::max_linear_speed;    // m/s
inline constexpr Fixed max_angular_speed = envelope::max_angular_speed;  // rad/s

// "outside +-500 m/s" or "outside 0..1": the reason a value lo..hi refuses.
std::string outside(Fixed lo, Fixed hi, std::string_view unit);
// "faster than 500 m/s": a velocity's length past its limit.
std::string faster_than(Fixed limit, std::string_view unit);

// Fine when `value` is within lo..hi; else an error at `what`: "outside ...".
Result<void> check_within(Fixed value, Fixed lo, Fixed hi, std::string_view what, std::string_view unit);
// Each component within -limit..limit ("<what>.y": "outside +-1000000 N s").
Result<void> check_vec3(Vec3 v, Fixed limit, std::string_view what, std::string_view unit);
// A velocity: its components within the limit (so that its length stays in
// range), then its length ("<what>": "faster than 100 rad/s").
Result<void> check_speed(Vec3 v, Fixed limit, std::string_view what, std::string_view unit);

}  // namespace bitstep::input_bounds
