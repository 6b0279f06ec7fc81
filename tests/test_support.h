// Helpers shared by the Catch2 tests.
#pragma once

#include <catch2/catch.hpp>
#include <cmath>
#include <cstdint>

#include "fixed/fixed.h"
#include "fixed/u128.h"

// For random loops: only a failing check reaches Catch2, whose per-assertion
// bookkeeping would otherwise dominate the run time; the message is built
// only then.
#define REQUIRE_QUIETLY(condition, message) \
  do {                                      \
    if (!(condition)) {                     \
      INFO(message);                        \
      REQUIRE(condition);                   \
    }                                       \
  } while (false)

namespace bitstep::test {

// Sample counts of the random sweeps: the full count in optimised builds, a
// tenth in unoptimised ones (the checked Debug build with ASan and UBSan,
// ~15x slower per operation), whose point is the asserts on every path; the
// Release run and tools/crosscheck/crosscheck.sh's optimised checked build cover the
// full count. Keeps tools/test.sh inside the CI budget (the full sweeps took
// ~7 of the checked build's ~22 test minutes on 2 cores).
constexpr uint64_t samples(uint64_t full) {
#if defined(NDEBUG)
  return full;
#else
  return full / 10;
#endif
}

// For reports and tolerances in tests only (never inside the simulation).
inline double to_double(Fixed f) { return static_cast<double>(f.raw()) * 0x1p-32; }
// The nearest Fixed to x, for test inputs computed in double (|x| < 2^31).
inline Fixed to_fixed(double x) { return Fixed::from_raw(static_cast<int64_t>(std::llround(x * 0x1p32))); }

// v sign-extended to a two's complement 128-bit value.
// How far a body sliding at v0 travels until friction's deceleration a
// stops it, stepped as the engine steps (semi-implicit Euler, dt): each
// step takes a dt off the speed, then moves by the new speed, until the
// speed would turn back (friction then holds it). The continuous v0^2 / 2a
// is v0 dt / 2 farther (1% at 5 m/s, mu 0.3, 60 Hz).
inline double euler_stop_distance(double v0, double a, double dt) {
  const auto n = static_cast<double>(static_cast<int64_t>(v0 / (a * dt)));  // whole steps that slow it
  return dt * (n * v0 - a * dt * n * (n + 1) / 2);
}

inline PortableU128 wide(int64_t v) { return {v < 0 ? UINT64_MAX : 0, static_cast<uint64_t>(v)}; }

}  // namespace bitstep::test
