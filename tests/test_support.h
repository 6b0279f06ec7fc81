// Helpers shared by the Catch2 tests.
#pragma once

#include <catch2/catch.hpp>
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

// For reports and tolerances in tests only (never inside the simulation).
inline double to_double(Fixed f) { return static_cast<double>(f.raw()) * 0x1p-32; }

// v sign-extended to a two's complement 128-bit value.
inline PortableU128 wide(int64_t v) { return {v < 0 ? UINT64_MAX : 0, static_cast<uint64_t>(v)}; }

}  // namespace bitstep::test
