// How fuzz_capi (capi.cpp) reads its bytes as C API calls. Every read past
// the end gives 0, so any bytes are a sequence of calls, and a mutation
// changes an argument or a call without shifting the meaning of the whole
// input much. make_seeds.py writes the seeds in this format.
//
//   input    := call*                       at most max_calls calls
//   call     := u8 (the Call below, modulo its count) arguments
//   number   := u8 kind (modulo 6), then
//               0: i8            that many units (m, m/s, N...)
//               1: i64           the raw Q32.32 bits, any of them
//               2: u8 i8         bounds[u8 % 11] (negated when u8 >= 0x80),
//                                plus i8 raw units: each bound's edges
//               3: f64           a double times 2^32 as x86's cvttsd2si
//                                converts it (NaN, infinities and values
//                                past the range give INT64_MIN): what a
//                                binding that does not check would pass
//               4: u8            number_texts[u8] through bitstep_fixed_parse
//                                (0 when it is refused: "nan", "1e300")
//               5: i16           that many 2^-16 units (-0.5..0.5)
// Integers are little-endian. The arguments of each call are read in the
// order capi.cpp's Session::one reads them.
#pragma once

#include <cstdint>
#include <cstring>
#include <iterator>
#include <limits>
#include <span>
#include <string>

#include "replay/bitstep.h"

namespace bitstep::fuzz::capi_input {

inline constexpr int max_calls = 64;  // per input: keeps an input's time bounded
inline constexpr int max_steps = 64;  // steps per input, over all `step` calls

enum class Call : uint8_t {
  add_body_fragment,
  add_body_text,
  add_joint_fragment,
  add_joint_text,
  remove_body,
  remove_joint,
  set_velocity,
  apply_impulse,
  apply_force,
  drive,
  wake,
  step,
  save,
  load,
  save_state,
  load_state,
  get,
  cast_ray,
  find_body,
  null_arguments,
  recreate,
  create_body_struct,
  create_joint_struct,
  read_all,
  character,
};
inline constexpr uint8_t call_count = static_cast<uint8_t>(Call::character) + 1;

// Numbers' texts for the JSON fragments and bitstep_fixed_parse: in range,
// at and just past the envelope's edges, past Q32.32, and not numbers.
inline constexpr const char* number_texts[] = {
    "0",      "1",         "-1",     "0.5",    "1/60", "16000",      "16000.000001", "-16001", "50",   "50.01",
    "0.01",   "0.009",     "100000", "100001", "1e9",  "1e300",      "-1e300",       "nan",    "inf",  "-inf",
    "1e-300", "\"7\"",     "null",   "[]",     "-0",   "2147483647", "2147483648",   "0x10",   "",     "1/0",
    "500",    "500.00001", "100",    "-100.5", "1e6",  "1000000.1",  "90",           "360",    "1e-9", "3"};

class Reader {
 public:
  explicit Reader(std::span<const uint8_t> bytes) : bytes_(bytes) {}

  bool empty() const { return at_ >= bytes_.size(); }

  uint8_t byte() { return at_ < bytes_.size() ? bytes_[at_++] : 0; }
  uint16_t u16() { return static_cast<uint16_t>(unsigned_le(2)); }
  uint32_t u32() { return static_cast<uint32_t>(unsigned_le(4)); }

  Call call() { return static_cast<Call>(byte() % call_count); }

  // Any float's bits: NaN, infinities, denormals.
  float real() {
    const uint32_t bits = u32();
    float value;
    std::memcpy(&value, &bits, sizeof value);
    return value;
  }

  std::string number_text() { return number_texts[byte() % std::size(number_texts)]; }

  bitstep_fixed number() {
    switch (byte() % 6) {
      case 0: return static_cast<int64_t>(static_cast<int8_t>(byte())) * (int64_t{1} << 32);
      case 1: return static_cast<int64_t>(unsigned_le(8));
      case 2: return near_bound();
      case 3: return converted(f64());
      case 4: {
        bitstep_fixed value = 0;
        const std::string text = number_text();
        return bitstep_fixed_parse(text.c_str(), &value) == BITSTEP_OK ? value : 0;
      }
      default: return static_cast<int64_t>(static_cast<int16_t>(u16()));
    }
  }

 private:
  uint64_t unsigned_le(int bytes) {
    uint64_t value = 0;
    for (int i = 0; i < bytes; ++i) value |= uint64_t{byte()} << (8 * i);
    return value;
  }

  double f64() {
    const uint64_t bits = unsigned_le(8);
    double value;
    std::memcpy(&value, &bits, sizeof value);
    return value;
  }

  // cvttsd2si's answer for value * 2^32, without C++'s undefined behaviour
  // for a double outside int64_t.
  static bitstep_fixed converted(double value) {
    const double scaled = value * 4294967296.0;
    if (!(scaled >= -9223372036854775808.0 && scaled < 9223372036854775808.0)) {
      return std::numeric_limits<int64_t>::min();
    }
    return static_cast<int64_t>(scaled);
  }

  // An edge of the envelope or of Q32.32, a few raw units either side.
  bitstep_fixed near_bound() {
    static constexpr int64_t units[] = {0, 1, 100, 500, 16000, 65536, 131072, 524288, 1000000, 1048576, 2147483647};
    const uint8_t which = byte();
    const int64_t edge = units[which % std::size(units)] * (int64_t{1} << 32);
    const int64_t delta = static_cast<int8_t>(byte());
    const int64_t signed_edge = which >= 0x80 ? -edge : edge;
    int64_t value = 0;
    if (__builtin_add_overflow(signed_edge, delta, &value)) return signed_edge;
    return value;
  }

  std::span<const uint8_t> bytes_;
  size_t at_ = 0;
};

}  // namespace bitstep::fuzz::capi_input
