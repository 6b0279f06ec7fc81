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
inline PortableU128 wide(int64_t v) { return {v < 0 ? UINT64_MAX : 0, static_cast<uint64_t>(v)}; }

}  // namespace bitstep::test
