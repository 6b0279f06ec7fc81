// The BITSTEP_CHECKED build turns every wrap, saturation, division by zero and
// domain error in fixed/ into an abort that names the operation and operands.
// Without it those cases take their documented values (see fixed/README.md).
#pragma once

#include <cstdint>

namespace bitstep {

#if defined(BITSTEP_CHECKED)
inline constexpr bool checked_build = true;
#else
inline constexpr bool checked_build = false;
#endif

// Prints "bitstep checked: <operation>: <reason> (a=raw:..., b=raw:...)" to
// stderr and aborts. Operands are raw Q32.32 values.
[[noreturn]] void fixed_fault(const char* operation, const char* reason, int64_t a, int64_t b);

}  // namespace bitstep

// Checks `condition` only in the checked build; compiles to nothing otherwise.
#define BITSTEP_FAULT_IF(condition, operation, reason, a, b)                  \
  do {                                                                        \
    if constexpr (::bitstep::checked_build) {                                 \
      if (condition) ::bitstep::fixed_fault((operation), (reason), (a), (b)); \
    }                                                                         \
  } while (false)
