// `bitstep bench fixed`: ns/op of Fixed, float and double doing the same work.
//
// Method. Each case draws 4096 operands (or operand pairs) from a seeded
// SplitMix64 generator as Fixed values, in ranges where nothing saturates, and
// converts the very same values to float and double before any timing starts.
// One sample times `sweeps` passes over the array with std::chrono::steady_clock
// (sweeps is calibrated so that a sample lasts about 1 ms with --quick, 4 ms
// otherwise). The table shows the minimum over the samples, the run least
// disturbed by other processes; the CSV also has the median.
//
// No dependent chain: the operands are independent, so the loop measures
// throughput, which is what a solver sweeping over many bodies and contacts
// sees. Every result goes through `escape`, an empty asm statement that claims
// to read it from the register it is in, so neither gcc nor clang can drop the
// work, fold it across sweeps or vectorise it, and it adds no instruction. The
// times include the operand loads and the loop (unrolled by 4): about one cycle
// per element, which is all of the float add and mul figures.
#include "tools/bench/fixed_ops.h"

#include <fmt/core.h>

#include <algorithm>
#include <chrono>
#include <cmath>
#include <concepts>
#include <cstdint>
#include <cstdio>
#include <fstream>
#include <string>
#include <string_view>
#include <type_traits>
#include <vector>

#include "fixed/checked.h"
#include "fixed/fixed.h"
#include "fixed/u128.h"
#include "fixed/vec3.h"
#include "fixed/splitmix64.h"
#include "tools/cli/options.h"
#include "tools/cli/exit_codes.h"
#include "tools/cli/file_output.h"

namespace bitstep {

namespace {

using Clock = std::chrono::steady_clock;

constexpr std::size_t operand_count = 4096;
static_assert(operand_count % 4 == 0, "time_sweeps unrolls by 4");
constexpr uint64_t operand_seed = 0xBE7C5EEDu;

// ---- float and double counterparts of the fixed-point operations ----------

template <std::floating_point F>
F sqrt(F a) {
  return std::sqrt(a);
}
template <std::floating_point F>
F rsqrt(F a) {
  return F{1} / std::sqrt(a);
}
template <std::floating_point F>
F sin(F a) {
  return std::sin(a);
}
template <std::floating_point F>
F cos(F a) {
  return std::cos(a);
}
template <std::floating_point F>
F atan2(F y, F x) {
  return std::atan2(y, x);
}

template <std::floating_point F>
struct FloatVec3 {
  F x, y, z;
};

template <class F>
F dot(FloatVec3<F> a, FloatVec3<F> b) {
  return a.x * b.x + a.y * b.y + a.z * b.z;
}
template <class F>
FloatVec3<F> cross(FloatVec3<F> a, FloatVec3<F> b) {
  return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x};
}
template <class F>
F length(FloatVec3<F> v) {
  return std::sqrt(dot(v, v));
}
// Like bitstep::normalize: the zero vector for the zero vector.
template <class F>
FloatVec3<F> normalize(FloatVec3<F> v) {
  const F len = length(v);
  if (len > F{0}) return {v.x / len, v.y / len, v.z / len};
  return {};
}

// ---- operands ---------------------------------------------------------------


// Raw magnitudes with a bit length uniform in [min_bits, max_bits], i.e. values
// log-uniform in [2^(min_bits - 33), 2^(max_bits - 32)), of random sign if `signed_values`.
struct Domain {
  int min_bits;
  int max_bits;
  bool signed_values;
};

constexpr Domain general{16, 46, true};    // 2^-17 <= |x| < 2^14: products, sums and atan2 arguments
constexpr Domain divisor{25, 46, true};    // |d| >= 2^-8: quotients of `general` stay below 2^22
constexpr Domain positive{16, 62, false};  // 2^-17 <= x < 2^30: sqrt and rsqrt
constexpr Domain angle{16, 38, true};      // |x| < 64 rad: sin and cos, with argument reduction
constexpr Domain component{24, 33, true};  // 2^-9 <= |c| < 2: unit-ish vectors, never zero

Fixed draw_fixed(SplitMix64& rng, Domain d) {
  const uint64_t r = rng.next();
  const uint64_t span = static_cast<uint64_t>(d.max_bits - d.min_bits + 1);
  const int bits = d.min_bits + static_cast<int>(r % span);
  const int64_t m = static_cast<int64_t>(rng.next() >> (64 - bits));
  const bool negative = d.signed_values && ((r >> 40) & 1u) != 0;
  return Fixed::from_raw(negative ? -m : m);
}

// A Fixed or a Vec3 (braced initialisation evaluates left to right).
template <class Operand>
Operand draw(SplitMix64& rng, Domain d) {
  if constexpr (std::is_same_v<Operand, Vec3>) {
    return Vec3{draw_fixed(rng, d), draw_fixed(rng, d), draw_fixed(rng, d)};
  } else {
    return draw_fixed(rng, d);
  }
}

// The same value as a T (Fixed, float or double); exact for double.
template <class T>
T as(Fixed a) {
  if constexpr (std::is_same_v<T, Fixed>) {
    return a;
  } else {
    return static_cast<T>(static_cast<double>(a.raw()) * 0x1p-32);
  }
}
template <class T>
auto as(const Vec3& v) {
  if constexpr (std::is_same_v<T, Fixed>) {
    return v;
  } else {
    return FloatVec3<T>{as<T>(v.x), as<T>(v.y), as<T>(v.z)};
  }
}

// ---- timing -----------------------------------------------------------------

// Floating-point results are claimed in the register they are computed in;
// a general register would cost a move per result, more than a float add.
#if defined(__x86_64__)
#define BITSTEP_FLOAT_REGISTER "x"
#elif defined(__aarch64__)
#define BITSTEP_FLOAT_REGISTER "w"
#else
#define BITSTEP_FLOAT_REGISTER "r,m"
#endif

// Makes the compiler believe `value` is read (and memory written), at the cost
// of at most a move or a store (none on x86-64 and aarch64).
template <class T>
requires std::is_arithmetic_v<T>
inline void escape(T value) {
  if constexpr (std::is_floating_point_v<T>) {
    __asm__ __volatile__("" : : BITSTEP_FLOAT_REGISTER(value) : "memory");
  } else {
    __asm__ __volatile__("" : : "r,m"(value) : "memory");
  }
}
inline void escape(Fixed value) { escape(value.raw()); }
template <class V>
requires requires(V v) { v.z; }
inline void escape(const V& v) {
  escape(v.x);
  escape(v.y);
  escape(v.z);
}

struct Settings {
  int samples = 31;
  double sample_ns = 4e6;
};

struct Timing {
  double min_ns = 0;
  double median_ns = 0;
};

template <class X, class Op>
double time_sweeps(const std::vector<X>& a_values, const std::vector<X>& b_values, Op op, int sweeps) {
  const X* a = a_values.data();
  const X* b = b_values.data();
  const std::size_t n = a_values.size();
  const Clock::time_point start = Clock::now();
  for (int s = 0; s < sweeps; ++s) {
    // Unrolled by 4 (operand_count is a multiple of 4) so that the loop counter
    // costs less than a float add and code alignment matters less.
    for (std::size_t i = 0; i < n; i += 4) {
      escape(op(a[i], b[i]));
      escape(op(a[i + 1], b[i + 1]));
      escape(op(a[i + 2], b[i + 2]));
      escape(op(a[i + 3], b[i + 3]));
    }
  }
  const Clock::time_point stop = Clock::now();
  return std::chrono::duration<double, std::nano>(stop - start).count();
}

// Times `op` on the operands converted to T.
template <class T, class Operand, class Op>
Timing time_as(const std::vector<Operand>& a, const std::vector<Operand>& b, Op op, const Settings& settings) {
  using X = decltype(as<T>(a.front()));
  std::vector<X> xa, xb;
  for (const Operand& v : a) xa.push_back(as<T>(v));
  for (const Operand& v : b) xb.push_back(as<T>(v));

  const double warm_up_ns = std::max(time_sweeps(xa, xb, op, 1), 1.0);  // also faults the pages in
  const int sweeps = static_cast<int>(std::clamp(settings.sample_ns / warm_up_ns, 1.0, 1e5));
  std::vector<double> per_op(static_cast<std::size_t>(settings.samples));
  for (double& ns : per_op) ns = time_sweeps(xa, xb, op, sweeps) / (sweeps * static_cast<double>(xa.size()));
  std::sort(per_op.begin(), per_op.end());
  return {per_op.front(), per_op[per_op.size() / 2]};
}

struct Row {
  std::string_view operation;
  Timing fixed, single, dual;  // Fixed, float, double
};

// One case: `op(a, b)` over operand pairs of type Operand (Fixed or Vec3, and
// their float and double counterparts); unary operations ignore b.
template <class Operand, class Op>
Row measure(std::string_view operation, Domain a_domain, Domain b_domain, const Settings& settings, Op op) {
  SplitMix64 rng{operand_seed};
  std::vector<Operand> a, b;
  for (std::size_t i = 0; i < operand_count; ++i) {
    a.push_back(draw<Operand>(rng, a_domain));
    b.push_back(draw<Operand>(rng, b_domain));
  }
  return {operation, time_as<Fixed>(a, b, op, settings), time_as<float>(a, b, op, settings),
          time_as<double>(a, b, op, settings)};
}

std::vector<Row> run_cases(const Settings& s) {
  return {
      measure<Fixed>("add", general, general, s, [](auto a, auto b) { return a + b; }),
      measure<Fixed>("mul", general, general, s, [](auto a, auto b) { return a * b; }),
      measure<Fixed>("div", general, divisor, s, [](auto a, auto b) { return a / b; }),
      measure<Fixed>("sqrt", positive, positive, s, [](auto a, auto) { return sqrt(a); }),
      measure<Fixed>("rsqrt", positive, positive, s, [](auto a, auto) { return rsqrt(a); }),
      measure<Fixed>("sin", angle, angle, s, [](auto a, auto) { return sin(a); }),
      measure<Fixed>("cos", angle, angle, s, [](auto a, auto) { return cos(a); }),
      measure<Fixed>("atan2", general, general, s, [](auto y, auto x) { return atan2(y, x); }),
      measure<Vec3>("dot (Vec3)", component, component, s, [](auto a, auto b) { return dot(a, b); }),
      measure<Vec3>("cross (Vec3)", component, component, s, [](auto a, auto b) { return cross(a, b); }),
      measure<Vec3>("length (Vec3)", component, component, s, [](auto a, auto) { return length(a); }),
      measure<Vec3>("normalize (Vec3)", component, component, s, [](auto a, auto) { return normalize(a); }),
  };
}

// ---- report -----------------------------------------------------------------

std::string cpu_model() {
  std::ifstream cpuinfo("/proc/cpuinfo");
  std::string line;
  while (std::getline(cpuinfo, line)) {
    if (line.rfind("model name", 0) != 0) continue;
    const std::size_t colon = line.find(':');
    const std::size_t start = colon == std::string::npos ? colon : line.find_first_not_of(" \t", colon + 1);
    if (start != std::string::npos) return line.substr(start);
  }
  return "unknown CPU";
}

#if defined(__clang__)
constexpr const char* compiler = __VERSION__;  // "Clang 14.0.6 ..." names itself
#elif defined(__GNUC__)
constexpr const char* compiler = "gcc " __VERSION__;
#else
constexpr const char* compiler = "unknown compiler";
#endif

std::string today_utc() {
  const std::chrono::year_month_day day{std::chrono::floor<std::chrono::days>(std::chrono::system_clock::now())};
  return fmt::format("{:04}-{:02}-{:02}", static_cast<int>(day.year()), static_cast<unsigned>(day.month()),
                     static_cast<unsigned>(day.day()));
}

double ratio(const Row& row) { return row.fixed.min_ns / row.single.min_ns; }

std::string csv_text(const std::vector<Row>& rows) {
  std::string out =
      "operation,fixed_ns_per_op,float_ns_per_op,double_ns_per_op,fixed_over_float,"
      "fixed_ns_median,float_ns_median,double_ns_median\n";
  for (const Row& r : rows) {
    out += fmt::format("{},{:.3f},{:.3f},{:.3f},{:.2f},{:.3f},{:.3f},{:.3f}\n", r.operation, r.fixed.min_ns,
                       r.single.min_ns, r.dual.min_ns, ratio(r), r.fixed.median_ns, r.single.median_ns,
                       r.dual.median_ns);
  }
  return out;
}

}  // namespace

int run_bench_fixed(int argc, char** argv) {
  Settings settings;
  std::string csv_path;
  CLI::App app("ns/op of fixed-point operations next to float and double", "bitstep bench fixed");
  app.add_flag_callback("--quick", [&settings] { settings = {9, 1e6}; }, "fewer samples");
  app.add_option("--csv", csv_path, "also write the table as CSV")->type_name("FILE");
  if (const std::optional<int> code = cli::parse(app, "bench fixed", argc, argv)) return *code;
  // Opened (under its temporary name) before the run: an unwritable path
  // fails at once; renamed into place only when whole.
  AtomicFile csv;
  std::string reason;
  if (!csv_path.empty() && !csv.open(csv_path, reason)) {
    fmt::print(stderr, "bitstep bench fixed: {}\n", reason);
    return exit_code::output_failed;
  }
#if !defined(__OPTIMIZE__)
  fmt::print(stderr, "bitstep bench fixed: warning: unoptimised build, the numbers mean little\n");
#endif

  fmt::print("machine: {} | 128-bit: {} | compiler: {} | {}{}\n\n", cpu_model(), wide_backend_name, compiler,
             today_utc(), checked_build ? " | checked build" : "");
  const std::vector<Row> rows = run_cases(settings);

  fmt::print("| operation | Fixed ns/op | float ns/op | double ns/op | Fixed/float |\n");
  fmt::print("|---|---:|---:|---:|---:|\n");
  for (const Row& r : rows) {
    fmt::print("| {} | {:.2f} | {:.2f} | {:.2f} | {:.1f} |\n", r.operation, r.fixed.min_ns, r.single.min_ns,
               r.dual.min_ns, ratio(r));
  }
  fmt::print("\nminimum of {} samples of ~{:.0f} ms over {} independent operands (throughput, loop included)\n",
             settings.samples, settings.sample_ns * 1e-6, operand_count);

  if (!csv_path.empty()) {
    const std::string text = csv_text(rows);
    std::fwrite(text.data(), 1, text.size(), csv.stream());
    if (!csv.commit(reason)) {
      fmt::print(stderr, "bitstep bench fixed: {}\n", reason);
      return exit_code::output_failed;
    }
  }
  return 0;
}

}  // namespace bitstep
