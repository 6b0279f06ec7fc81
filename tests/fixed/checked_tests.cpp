// Wrap, saturation, division by zero and domain errors: in the BITSTEP_CHECKED
// build each one aborts and names the operation; in the ordinary build each
// one takes its documented value.
//
// The death tests fork(): the child routes its stderr into a pipe, restores
// the default SIGABRT action (Catch2's handler would otherwise report from the
// child) and runs the operation; the parent asserts that the child was killed
// by SIGABRT and that the pipe carried "bitstep checked: <operation>: ...".
// If the operation returns, the child exits with status 0, which fails.
//
// Both sets are compiled in every build; `if constexpr (checked_build)` picks
// the one that runs and the other reports SUCCEED with the reason.
#include <sys/types.h>
#include <sys/wait.h>
#include <unistd.h>

#include <catch2/catch.hpp>
#include <cerrno>
#include <csignal>
#include <cstdint>
#include <cstdio>
#include <string>

#include "fixed/checked.h"
#include "fixed/fixed.h"
#include "fixed/mat33.h"
#include "fixed/quat.h"
#include "fixed/vec3.h"

namespace {

using bitstep::checked_build;
using bitstep::Fixed;
using bitstep::Vec3;

// Values the optimiser cannot see through, and a sink it cannot drop.
__attribute__((noinline)) Fixed opaque(Fixed v) {
  volatile int64_t raw = v.raw();
  return Fixed::from_raw(raw);
}
__attribute__((noinline)) Fixed opaque_raw(int64_t raw) { return opaque(Fixed::from_raw(raw)); }
volatile int64_t sink_raw = 0;
void sink(Fixed v) { sink_raw = v.raw(); }
void sink(Vec3 v) { sink_raw = v.x.raw() ^ v.y.raw() ^ v.z.raw(); }

Fixed int_(int32_t v) { return Fixed::from_int(v); }
constexpr int64_t largest_integer_raw = int64_t{0x7FFFFFFF} << 32;
constexpr int64_t half_pi_raw = 6746518852;  // round(pi/2 * 2^32)
constexpr int64_t pi_raw = 13493037705;      // round(pi * 2^32)

struct ChildResult {
  bool exited = false;
  int exit_code = -1;
  bool signaled = false;
  int signal = 0;
  std::string stderr_text;

  std::string describe() const {
    std::string s = exited ? "child exited with status " + std::to_string(exit_code)
                           : (signaled ? "child killed by signal " + std::to_string(signal) : "child state unknown");
    return s + "; its stderr: \"" + stderr_text + "\"";
  }
};

template <class Operation>
ChildResult run_in_child(Operation operation) {
  ChildResult result;
  int fds[2];
  if (pipe(fds) != 0) {
    FAIL("pipe() failed");
    return result;
  }
  std::fflush(stdout);
  std::fflush(stderr);
  const pid_t pid = fork();
  if (pid < 0) {
    FAIL("fork() failed");
    return result;
  }
  if (pid == 0) {
    std::signal(SIGABRT, SIG_DFL);
    close(fds[0]);
    dup2(fds[1], STDERR_FILENO);
    close(fds[1]);
    operation();
    _exit(0);  // only reached when the operation did not abort
  }
  close(fds[1]);
  char buffer[512];
  for (;;) {
    const ssize_t n = read(fds[0], buffer, sizeof buffer);
    if (n > 0) {
      result.stderr_text.append(buffer, static_cast<size_t>(n));
    } else if (n == 0 || errno != EINTR) {
      break;
    }
  }
  close(fds[0]);
  int status = 0;
  while (waitpid(pid, &status, 0) < 0) {
    if (errno != EINTR) {
      FAIL("waitpid() failed");
      return result;
    }
  }
  result.exited = WIFEXITED(status);
  result.exit_code = result.exited ? WEXITSTATUS(status) : -1;
  result.signaled = WIFSIGNALED(status);
  result.signal = result.signaled ? WTERMSIG(status) : 0;
  return result;
}

// The operation aborts, and stderr names it: "bitstep checked: <operation>: <reason>".
template <class Operation>
ChildResult expect_abort(const std::string& operation, const std::string& reason, Operation op) {
  const ChildResult r = run_in_child(op);
  INFO(r.describe());
  CHECK(r.signaled);
  CHECK(r.signal == SIGABRT);
  CHECK_THAT(r.stderr_text, Catch::Contains("bitstep checked: " + operation + ": " + reason));
  return r;
}

// The operation runs to completion: no abort, nothing on stderr.
template <class Operation>
void expect_no_abort(Operation op) {
  const ChildResult r = run_in_child(op);
  INFO(r.describe());
  CHECK(r.exited);
  CHECK(r.exit_code == 0);
  CHECK(r.stderr_text.empty());
}

constexpr const char* only_checked = "death tests run only in the checked build (BITSTEP_CHECKED)";
constexpr const char* only_unchecked = "documented saturation/wrap values are observable only in the unchecked build";

}  // namespace

// ===========================================================================
// Checked build: every fault aborts and names its operation.

TEST_CASE("checked: the death-test harness sees an in-range operation run to completion", "[checked]") {
  if constexpr (checked_build) {
    expect_no_abort([] { sink(opaque(Fixed::max() - Fixed::ulp()) + opaque(Fixed::ulp())); });
    expect_no_abort([] { sink(opaque(Fixed::max()) * opaque(Fixed::one())); });
    // Terms of 2^32 each (out of range alone) whose fused sum is 0: no fault.
    expect_no_abort([] {
      const Fixed big = opaque(int_(65536));
      sink(dot(Vec3{big, big, Fixed{}}, Vec3{big, -big, Fixed{}}));
    });
  } else {
    SUCCEED(only_checked);
  }
}

TEST_CASE("checked: a + b that overflows aborts naming add and both operands", "[checked]") {
  if constexpr (checked_build) {
    const ChildResult r =
        expect_abort("add", "overflow, wrapped", [] { sink(opaque(Fixed::max()) + opaque(Fixed::ulp())); });
    CHECK_THAT(r.stderr_text, Catch::Contains("(a=raw:7fffffffffffffff, b=raw:1)"));
    expect_abort("add", "overflow, wrapped", [] { sink(opaque(Fixed::lowest()) + opaque(-Fixed::ulp())); });
  } else {
    SUCCEED(only_checked);
  }
}

TEST_CASE("checked: a - b that overflows aborts naming sub, and so does -lowest", "[checked]") {
  if constexpr (checked_build) {
    expect_abort("sub", "overflow, wrapped", [] { sink(opaque(Fixed::lowest()) - opaque(Fixed::ulp())); });
    expect_abort("sub", "overflow, wrapped", [] { sink(opaque(Fixed::max()) - opaque(-Fixed::one())); });
    expect_abort("sub", "overflow, wrapped", [] { sink(-opaque(Fixed::lowest())); });
  } else {
    SUCCEED(only_checked);
  }
}

TEST_CASE("checked: a * b beyond the range aborts naming mul", "[checked]") {
  if constexpr (checked_build) {
    expect_abort("mul", "result out of range", [] { sink(opaque(int_(65536)) * opaque(int_(65536))); });
    expect_abort("mul", "result out of range", [] { sink(opaque(int_(-65536)) * opaque(int_(65536))); });
    expect_abort("mul", "result out of range", [] { sink(opaque(Fixed::lowest()) * opaque(-Fixed::one())); });
  } else {
    SUCCEED(only_checked);
  }
}

TEST_CASE("checked: a / b beyond the range aborts naming div", "[checked]") {
  if constexpr (checked_build) {
    expect_abort("div", "result out of range", [] { sink(opaque(Fixed::max()) / opaque(Fixed::ulp())); });
    // The one signed overflow of division: lowest / -1 = 2^31.
    expect_abort("div", "result out of range", [] { sink(opaque(Fixed::lowest()) / opaque(-Fixed::one())); });
  } else {
    SUCCEED(only_checked);
  }
}

TEST_CASE("checked: x / 0 aborts naming div, 0 / 0 included", "[checked]") {
  if constexpr (checked_build) {
    expect_abort("div", "division by zero", [] { sink(opaque(Fixed::one()) / opaque(Fixed{})); });
    expect_abort("div", "division by zero", [] { sink(opaque(-Fixed::one()) / opaque(Fixed{})); });
    expect_abort("div", "division by zero", [] { sink(opaque(Fixed{}) / opaque(Fixed{})); });
  } else {
    SUCCEED(only_checked);
  }
}

TEST_CASE("checked: mul_div by 0 aborts naming mul_div", "[checked]") {
  if constexpr (checked_build) {
    expect_abort("mul_div", "division by zero",
                 [] { sink(mul_div(opaque(Fixed::one()), opaque(int_(3)), opaque(Fixed{}))); });
    expect_abort("mul_div", "result out of range",
                 [] { sink(mul_div(opaque(Fixed::max()), opaque(Fixed::max()), opaque(Fixed::one()))); });
  } else {
    SUCCEED(only_checked);
  }
}

TEST_CASE("checked: mul_add beyond the range aborts naming mul_add", "[checked]") {
  if constexpr (checked_build) {
    expect_abort("mul_add", "result out of range",
                 [] { sink(mul_add(opaque(int_(65536)), opaque(int_(32768)), opaque(Fixed::max()))); });
  } else {
    SUCCEED(only_checked);
  }
}

TEST_CASE("checked: abs(lowest) aborts naming abs", "[checked]") {
  if constexpr (checked_build) {
    expect_abort("abs", "abs(lowest) saturated", [] { sink(abs(opaque(Fixed::lowest()))); });
  } else {
    SUCCEED(only_checked);
  }
}

TEST_CASE("checked: sqrt of a negative value aborts naming sqrt", "[checked]") {
  if constexpr (checked_build) {
    expect_abort("sqrt", "negative argument", [] { sink(sqrt(opaque(-Fixed::one()))); });
    expect_abort("sqrt", "negative argument", [] { sink(sqrt(opaque(-Fixed::ulp()))); });
  } else {
    SUCCEED(only_checked);
  }
}

TEST_CASE("checked: rsqrt of zero or a negative value aborts naming rsqrt", "[checked]") {
  if constexpr (checked_build) {
    expect_abort("rsqrt", "non-positive argument", [] { sink(rsqrt(opaque(Fixed{}))); });
    expect_abort("rsqrt", "non-positive argument", [] { sink(rsqrt(opaque(-Fixed::one()))); });
  } else {
    SUCCEED(only_checked);
  }
}

TEST_CASE("checked: asin and acos outside [-1, 1] abort naming the function", "[checked]") {
  if constexpr (checked_build) {
    expect_abort("asin", "argument outside [-1, 1]", [] { sink(asin(opaque(int_(2)))); });
    expect_abort("asin", "argument outside [-1, 1]", [] { sink(asin(opaque(-Fixed::one() - Fixed::ulp()))); });
    expect_abort("acos", "argument outside [-1, 1]", [] { sink(acos(opaque(Fixed::one() + Fixed::ulp()))); });
    // The domain itself is fine.
    expect_no_abort([] { sink(asin(opaque(-Fixed::one())) + acos(opaque(Fixed::one()))); });
  } else {
    SUCCEED(only_checked);
  }
}

TEST_CASE("checked: ceil and round beyond 2^31 - 1 abort naming ceil", "[checked]") {
  if constexpr (checked_build) {
    expect_abort("ceil", "result out of range", [] { sink(ceil(opaque(Fixed::max()))); });
    expect_abort("ceil", "result out of range", [] { sink(ceil(opaque_raw(largest_integer_raw + 1))); });
    expect_abort("ceil", "result out of range", [] { sink(round(opaque(Fixed::max()))); });
    expect_no_abort([] { sink(ceil(opaque_raw(largest_integer_raw))); });
  } else {
    SUCCEED(only_checked);
  }
}

TEST_CASE("checked: dot and cross beyond the range abort naming dot and cross", "[checked]") {
  if constexpr (checked_build) {
    expect_abort("dot", "result out of range", [] {
      const Fixed big = opaque(int_(40000));
      sink(dot(Vec3{big, big, big}, Vec3{big, big, big}));
    });
    expect_abort("cross", "result out of range", [] {
      const Fixed big = opaque(int_(65536));
      sink(cross(Vec3{big, Fixed{}, Fixed{}}, Vec3{Fixed{}, big, Fixed{}}));
    });
  } else {
    SUCCEED(only_checked);
  }
}

TEST_CASE("checked: the solver's in-range forms beyond the range abort naming sum_products_in_range",
          "[checked]") {
  if constexpr (checked_build) {
    expect_abort("sum_products_in_range", "result out of range", [] {
      const Fixed big = opaque(int_(65536));
      sink(mul_in_range(big, big));
    });
    expect_abort("sum_products_in_range", "result out of range", [] {
      const Fixed big = opaque(int_(65536));
      const Fixed a[3] = {big, big, big}, b[3] = {big, Fixed{}, Fixed{}};
      sink(sum_products_in_range(a, b));
    });
  } else {
    SUCCEED(only_checked);
  }
}

TEST_CASE("checked: length beyond the range and from_ratio by zero abort naming the operation", "[checked]") {
  if constexpr (checked_build) {
    expect_abort("length", "result out of range", [] {
      const Fixed m = opaque(Fixed::max());
      sink(length(Vec3{m, m, m}));
    });
    expect_abort("from_ratio", "out of range or zero denominator", [] {
      volatile int64_t zero = 0;
      sink(Fixed::from_ratio(1, zero));
    });
  } else {
    SUCCEED(only_checked);
  }
}

TEST_CASE("checked: the inverse of a singular matrix aborts naming inverse", "[checked]") {
  if constexpr (checked_build) {
    expect_abort("inverse", "singular matrix", [] {
      const Fixed one = opaque(Fixed::one());
      const bitstep::Mat33 m{{Vec3{one, one, one}, Vec3{one, one, one}, Vec3{one, -one, one}}};
      sink(inverse(m).rows[0]);
    });
  } else {
    SUCCEED(only_checked);
  }
}

// ===========================================================================
// Unchecked build: the documented values.

TEST_CASE("unchecked: a + b that overflows wraps to the exact two's complement value", "[checked]") {
  if constexpr (!checked_build) {
    CHECK(opaque(Fixed::max()) + opaque(Fixed::ulp()) == Fixed::lowest());
    CHECK(opaque(Fixed::lowest()) + opaque(-Fixed::ulp()) == Fixed::max());
    CHECK(opaque(int_(INT32_MAX)) + opaque(Fixed::one()) == int_(INT32_MIN));
    CHECK(opaque(Fixed::max()) + opaque(Fixed::max()) == Fixed::from_raw(-2));
    // (2^31 - 1) + (2^31 - 1) = 2^32 - 2 wraps to -2.
    CHECK(opaque(int_(INT32_MAX)) + opaque(int_(INT32_MAX)) == int_(-2));
  } else {
    SUCCEED(only_unchecked);
  }
}

TEST_CASE("unchecked: a - b that overflows wraps, and -lowest is lowest", "[checked]") {
  if constexpr (!checked_build) {
    CHECK(opaque(Fixed::lowest()) - opaque(Fixed::ulp()) == Fixed::max());
    CHECK(opaque(Fixed::max()) - opaque(-Fixed::one()) == Fixed::from_raw(INT64_MIN + 0xFFFFFFFF));
    CHECK(-opaque(Fixed::lowest()) == Fixed::lowest());
  } else {
    SUCCEED(only_unchecked);
  }
}

TEST_CASE("unchecked: a * b beyond the range saturates to max or lowest by the sign", "[checked]") {
  if constexpr (!checked_build) {
    CHECK(opaque(int_(65536)) * opaque(int_(65536)) == Fixed::max());
    CHECK(opaque(int_(-65536)) * opaque(int_(65536)) == Fixed::lowest());
    CHECK(opaque(int_(-65536)) * opaque(int_(-65536)) == Fixed::max());
    CHECK(opaque(Fixed::lowest()) * opaque(Fixed::lowest()) == Fixed::max());
    CHECK(opaque(Fixed::lowest()) * opaque(-Fixed::one()) == Fixed::max());    // 2^31 does not fit
    CHECK(opaque(Fixed::lowest()) * opaque(Fixed::one()) == Fixed::lowest());  // exact, no saturation
    CHECK(opaque(Fixed::max()) * opaque(Fixed::one()) == Fixed::max());
  } else {
    SUCCEED(only_unchecked);
  }
}

TEST_CASE("unchecked: a / b beyond the range saturates to max or lowest by the sign", "[checked]") {
  if constexpr (!checked_build) {
    CHECK(opaque(Fixed::max()) / opaque(Fixed::ulp()) == Fixed::max());
    CHECK(opaque(Fixed::lowest()) / opaque(Fixed::ulp()) == Fixed::lowest());
    CHECK(opaque(Fixed::max()) / opaque(-Fixed::ulp()) == Fixed::lowest());
    CHECK(opaque(Fixed::lowest()) / opaque(-Fixed::one()) == Fixed::max());
    CHECK(opaque(Fixed::lowest()) / opaque(Fixed::one()) == Fixed::lowest());
  } else {
    SUCCEED(only_unchecked);
  }
}

TEST_CASE("unchecked: x / 0 saturates by the sign of x and 0 / 0 is 0", "[checked]") {
  if constexpr (!checked_build) {
    CHECK(opaque(Fixed::one()) / opaque(Fixed{}) == Fixed::max());
    CHECK(opaque(Fixed::ulp()) / opaque(Fixed{}) == Fixed::max());
    CHECK(opaque(-Fixed::one()) / opaque(Fixed{}) == Fixed::lowest());
    CHECK(opaque(Fixed::lowest()) / opaque(Fixed{}) == Fixed::lowest());
    CHECK(opaque(Fixed{}) / opaque(Fixed{}) == Fixed{});
    CHECK(Fixed::from_ratio(opaque(int_(5)).raw(), 0) == Fixed::max());
    CHECK(Fixed::from_ratio(-1, opaque(Fixed{}).raw()) == Fixed::lowest());
    CHECK(Fixed::from_ratio(0, opaque(Fixed{}).raw()) == Fixed{});
  } else {
    SUCCEED(only_unchecked);
  }
}

TEST_CASE("unchecked: mul_div by 0 saturates by the sign of a * b, 0 * b / 0 is 0", "[checked]") {
  if constexpr (!checked_build) {
    CHECK(mul_div(opaque(Fixed::one()), opaque(int_(3)), opaque(Fixed{})) == Fixed::max());
    CHECK(mul_div(opaque(-Fixed::one()), opaque(int_(3)), opaque(Fixed{})) == Fixed::lowest());
    CHECK(mul_div(opaque(-Fixed::one()), opaque(int_(-3)), opaque(Fixed{})) == Fixed::max());
    CHECK(mul_div(opaque(Fixed{}), opaque(int_(3)), opaque(Fixed{})) == Fixed{});
    CHECK(mul_div(opaque(Fixed::max()), opaque(Fixed::max()), opaque(Fixed::one())) == Fixed::max());
    CHECK(mul_div(opaque(Fixed::max()), opaque(Fixed::max()), opaque(-Fixed::one())) == Fixed::lowest());
  } else {
    SUCCEED(only_unchecked);
  }
}

TEST_CASE("unchecked: mul_add beyond the range saturates", "[checked]") {
  if constexpr (!checked_build) {
    CHECK(mul_add(opaque(int_(65536)), opaque(int_(32768)), opaque(Fixed::max())) == Fixed::max());
    CHECK(mul_add(opaque(int_(-65536)), opaque(int_(32768)), opaque(Fixed::lowest())) == Fixed::lowest());
    // The product alone is out of range but the sum is not: exact.
    CHECK(mul_add(opaque(int_(65536)), opaque(int_(32768)), opaque(Fixed::lowest())) == Fixed{});
  } else {
    SUCCEED(only_unchecked);
  }
}

TEST_CASE("unchecked: abs(lowest) saturates to max", "[checked]") {
  if constexpr (!checked_build) {
    CHECK(abs(opaque(Fixed::lowest())) == Fixed::max());
    CHECK(abs(opaque(-Fixed::max())) == Fixed::max());
  } else {
    SUCCEED(only_unchecked);
  }
}

TEST_CASE("unchecked: sqrt of a negative value is 0", "[checked]") {
  if constexpr (!checked_build) {
    CHECK(sqrt(opaque(-Fixed::one())) == Fixed{});
    CHECK(sqrt(opaque(-Fixed::ulp())) == Fixed{});
    CHECK(sqrt(opaque(Fixed::lowest())) == Fixed{});
  } else {
    SUCCEED(only_unchecked);
  }
}

TEST_CASE("unchecked: rsqrt of zero or a negative value saturates to max", "[checked]") {
  if constexpr (!checked_build) {
    CHECK(rsqrt(opaque(Fixed{})) == Fixed::max());
    CHECK(rsqrt(opaque(-Fixed::one())) == Fixed::max());
    CHECK(rsqrt(opaque(Fixed::lowest())) == Fixed::max());
  } else {
    SUCCEED(only_unchecked);
  }
}

TEST_CASE("unchecked: asin and acos clamp their argument to [-1, 1]", "[checked]") {
  if constexpr (!checked_build) {
    CHECK(asin(opaque(int_(2))) == Fixed::from_raw(half_pi_raw));
    CHECK(asin(opaque(int_(2))) == asin(Fixed::one()));
    CHECK(asin(opaque(Fixed::max())) == Fixed::from_raw(half_pi_raw));
    CHECK(asin(opaque(int_(-2))) == Fixed::from_raw(-half_pi_raw));
    CHECK(asin(opaque(Fixed::lowest())) == Fixed::from_raw(-half_pi_raw));
    CHECK(acos(opaque(int_(2))) == Fixed{});
    CHECK(acos(opaque(Fixed::one() + Fixed::ulp())) == Fixed{});
    CHECK(acos(opaque(int_(-2))) == Fixed::from_raw(pi_raw));
    CHECK(acos(opaque(Fixed::lowest())) == acos(-Fixed::one()));
  } else {
    SUCCEED(only_unchecked);
  }
}

TEST_CASE("unchecked: ceil and round beyond 2^31 - 1 saturate to max", "[checked]") {
  if constexpr (!checked_build) {
    CHECK(ceil(opaque(Fixed::max())) == Fixed::max());
    CHECK(ceil(opaque_raw(largest_integer_raw + 1)) == Fixed::max());
    CHECK(ceil(opaque_raw(largest_integer_raw)) == Fixed::from_raw(largest_integer_raw));
    CHECK(round(opaque(Fixed::max())) == Fixed::max());
    // 2^31 - 1/2: a tie whose even neighbour 2^31 is out of range.
    CHECK(round(opaque_raw(largest_integer_raw + (int64_t{1} << 31))) == Fixed::max());
    CHECK(round(opaque_raw(largest_integer_raw + (int64_t{1} << 31) - 1)) == Fixed::from_raw(largest_integer_raw));
    CHECK(floor(opaque(Fixed::max())) == Fixed::from_raw(largest_integer_raw));
  } else {
    SUCCEED(only_unchecked);
  }
}

TEST_CASE("unchecked: dot and cross beyond the range saturate, in-range fused sums stay exact", "[checked]") {
  if constexpr (!checked_build) {
    const Fixed big = opaque(int_(40000));
    CHECK(dot(Vec3{big, big, big}, Vec3{big, big, big}) == Fixed::max());
    CHECK(dot(Vec3{big, big, big}, Vec3{-big, -big, -big}) == Fixed::lowest());
    const Fixed m = opaque(Fixed::max()), l = opaque(Fixed::lowest());
    CHECK(dot(Vec3{m, m, m}, Vec3{m, m, m}) == Fixed::max());
    CHECK(dot(Vec3{l, l, l}, Vec3{l, l, m}) == Fixed::max());
    CHECK(dot(Vec3{l, l, l}, Vec3{m, m, m}) == Fixed::lowest());
    const Fixed huge = opaque(int_(65536));
    CHECK(dot(Vec3{huge, huge, Fixed{}}, Vec3{huge, -huge, Fixed{}}) == Fixed{});
    CHECK(cross(Vec3{huge, Fixed{}, Fixed{}}, Vec3{Fixed{}, huge, Fixed{}}) == Vec3{Fixed{}, Fixed{}, Fixed::max()});
    CHECK(cross(Vec3{Fixed{}, huge, Fixed{}}, Vec3{huge, Fixed{}, Fixed{}}) == Vec3{Fixed{}, Fixed{}, Fixed::lowest()});
  } else {
    SUCCEED(only_unchecked);
  }
}

TEST_CASE("unchecked: length beyond the range saturates to max", "[checked]") {
  if constexpr (!checked_build) {
    const Fixed m = opaque(Fixed::max()), l = opaque(Fixed::lowest());
    CHECK(length(Vec3{m, m, m}) == Fixed::max());
    CHECK(length(Vec3{l, l, l}) == Fixed::max());
    CHECK(length(Vec3{l, Fixed{}, Fixed{}}) == Fixed::max());  // exactly 2^31: out of range by 1 ulp
    CHECK(length(Vec3{m, Fixed{}, Fixed{}}) == Fixed::max());
  } else {
    SUCCEED(only_unchecked);
  }
}
