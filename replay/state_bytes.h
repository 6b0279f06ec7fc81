// The state description's byte visitors (internal to replay/): a writer of
// its canonical little-endian bytes and a bounds-checked reader of them.
// state_hash.cpp and snapshot.cpp use them for the whole state;
// rollback_state.cpp for the state of a step alone: with a `BodyStatics`
// given, the fields a body keeps while it lives (described inside
// `statics`: its type, mass properties, material, damping, shapes, filter)
// are not written or read; each body's serial is (`identity`, apart from
// the other bytes), and the statics keep them by serial.
#pragma once

#include <array>
#include <cstdint>
#include <span>
#include <string>
#include <type_traits>
#include <vector>

#include "core/body.h"
#include "core/error.h"
#include "fixed/mat33.h"
#include "fixed/quat.h"

namespace bitstep::state_bytes {

// A body's static fields by its serial (replay/rollback_state.h).
class BodyStatics {
 public:
  virtual ~BodyStatics() = default;
  // Remembers the static fields of a live body not seen before.
  virtual void remember(const Body& body) = 0;
  // Sets the static fields of the body of `serial` into `body`; false when
  // they were never remembered.
  virtual bool recall(uint64_t serial, Body& body) const = 0;
};

// Values go to `put(value, count)`: its `count` low bytes, little-endian, to
// a vector or a caller's buffer (a value at a time: a byte at a time, each
// store through a pointer that may alias the sink's own count, was the
// slowest part of saving a state).
template <class Put>
struct ByteWriter {
  static constexpr bool reading = false;
  Put put;
  BodyStatics* statics_kept = nullptr;  // set: a step's state alone

  [[gnu::always_inline]] void bytes(uint64_t v, int count) { put(v, count); }
  template <class T>
  void integer(const char*, const T& value, int count, uint64_t, uint64_t) {
    bytes(static_cast<uint64_t>(value), count);
  }
  template <class T>
  void integers(const char*, const T& a, const T& b, int count, uint64_t) {
    bytes(a, count);
    bytes(b, count);
  }
  template <class E, size_t N>
  void choice(const char*, const E& value, const std::array<const char*, N>&, size_t) {
    bytes(static_cast<uint64_t>(value), 1);
  }
  template <size_t N>
  void flags(const char*, const uint8_t& bits, const std::array<const char*, N>&) {
    bytes(bits, 1);
  }
  void fixed(const char*, Fixed f) { bytes(static_cast<uint64_t>(f.raw()), 8); }
  void fixeds(const char*, const Fixed* values, size_t n) {
    for (size_t i = 0; i < n; ++i) fixed(nullptr, values[i]);
  }
  void vec(const char*, Vec3 v) {
    fixed(nullptr, v.x);
    fixed(nullptr, v.y);
    fixed(nullptr, v.z);
  }
  void quat(const char*, Quat q) {
    fixed(nullptr, q.w);
    fixed(nullptr, q.x);
    fixed(nullptr, q.y);
    fixed(nullptr, q.z);
  }
  void mat(const char*, const Mat33& m) {
    for (const Vec3& row : m.rows) vec(nullptr, row);
  }
  template <class F>
  void object(const char*, F&& describe) {
    describe();
  }
  template <class T, class F>
  void list(const char*, const std::vector<T>& items, size_t, uint64_t, const char*, F&& describe) {
    bytes(items.size(), 4);
    for (const T& item : items) describe(item);
  }
  template <class F>
  void items(const char*, size_t count, F&& describe) {
    for (size_t i = 0; i < count; ++i) describe(i);
  }
  template <class Test, class Reason>
  void require(Test&&, Reason&&) {}  // a world's own state holds
  template <class F>
  void trailing(bool present, bool, F&& describe) {
    if (present) describe();
  }
  template <class F>
  void statics(F&& describe) {
    if (statics_kept == nullptr) describe();
  }
  // A Put with serial() keeps the serials apart from the state's bytes
  // (rollback_state.cpp: the bytes peers compare name no serial).
  void identity(const Body& body) {
    if (statics_kept == nullptr) return;
    if constexpr (requires { put.serial(uint64_t{}); }) {
      put.serial(body.serial);
    } else {
      bytes(body.serial, 8);
    }
    statics_kept->remember(body);
  }
};

// Reads the state description's bytes back, little-endian, bounds-checked:
// a value outside its range, a count the bytes left could not hold, or a
// failed requirement throws an Error naming the field and the byte (in its
// reason, "... (payload byte N)": the wording users and the docs know). With
// `statics`, into a world's own vectors: a body whose serial is the one
// read keeps its static fields, another gets them from `statics`.
class ByteReader {
 public:
  static constexpr bool reading = true;
  // `marks`: a scratch kept by the caller between reads (else the reader's
  // own). `serials`: the live bodies' serials, in slot order, kept apart
  // from `bytes` (a rollback state's).
  explicit ByteReader(std::span<const uint8_t> bytes, const BodyStatics* statics = nullptr,
                      std::vector<uint8_t>* marks = nullptr, std::span<const uint8_t> serials = {})
      : bytes_(bytes), serials_(serials), statics_(statics), marks_(marks != nullptr ? marks : &own_marks_) {}

  std::vector<uint8_t>& marks(size_t n) {
    marks_->assign(n, 0);
    return *marks_;
  }

  uint64_t u64() { return take(8); }
  uint32_t u32() { return static_cast<uint32_t>(take(4)); }

  template <class T>
  void integer(const char* name, T& value, int count, uint64_t lo, uint64_t hi) {
    value = static_cast<T>(within(take(count), lo, hi, name));
  }
  template <class T>
  void integers(const char* name, T& a, T& b, int count, uint64_t hi) {
    a = static_cast<T>(within(take(count), 0, hi, name));
    b = static_cast<T>(within(take(count), 0, hi, name));
  }
  template <class E, size_t N>
  void choice(const char* name, E& value, const std::array<const char*, N>&, size_t first) {
    value = static_cast<E>(within(take(1), first, N - 1, name));
  }
  template <size_t N>
  void flags(const char* name, uint8_t& bits, const std::array<const char*, N>&) {
    bits = static_cast<uint8_t>(within(take(1), 0, (1u << N) - 1, name));
  }
  void fixed(const char*, Fixed& f) { f = Fixed::from_raw(static_cast<int64_t>(take(8))); }
  void fixeds(const char*, Fixed* values, size_t n) {
    for (size_t i = 0; i < n; ++i) fixed(nullptr, values[i]);
  }
  void vec(const char*, Vec3& v) {
    fixed(nullptr, v.x);
    fixed(nullptr, v.y);
    fixed(nullptr, v.z);
  }
  void quat(const char*, Quat& q) {
    fixed(nullptr, q.w);
    fixed(nullptr, q.x);
    fixed(nullptr, q.y);
    fixed(nullptr, q.z);
  }
  void mat(const char*, Mat33& m) {
    for (Vec3& row : m.rows) vec(nullptr, row);
  }
  template <class F>
  void object(const char*, F&& describe) {
    describe();
  }
  // A count of items of at least `item_bytes` each: never more than the
  // bytes left could hold (a corrupt count must not allocate gigabytes).
  template <class T, class F>
  void list(const char* name, std::vector<T>& items, size_t item_bytes, uint64_t hi, const char*, F&& describe) {
    const uint64_t n = take(4);
    if (n > hi) fail(std::to_string(n) + " " + name + ": more than the limit of " + std::to_string(hi));
    if (n * item_bytes > bytes_.size() - at_) {
      fail(std::to_string(n) + " " + name + ": more than the " + std::to_string(bytes_.size() - at_) +
           " bytes left could hold");
    }
    items.resize(static_cast<size_t>(n));
    for (T& item : items) {
      describe(item);
      if constexpr (std::is_same_v<T, Body>) {
        if (statics_ != nullptr && !item.alive) {  // a dead slot keeps nothing (as remove_body leaves it)
          item.serial = 0;
          item.shapes.clear();
        }
      }
    }
  }
  template <class F>
  void items(const char*, size_t count, F&& describe) {
    for (size_t i = 0; i < count; ++i) describe(i);
  }
  template <class Test, class Reason>
  void require(Test&& test, Reason&& reason) {
    if (!test()) fail(reason());
  }
  template <class F>
  void trailing(bool, bool, F&& describe) {
    if (at_ != bytes_.size()) describe();
  }
  template <class F>
  void statics(F&& describe) {
    if (statics_ == nullptr) describe();
  }
  void identity(Body& body) {
    if (statics_ == nullptr) return;
    if (serials_.size() - serial_at_ < 8) fail("more live bodies than serials");
    uint64_t serial = 0;
    for (size_t i = 0; i < 8; ++i) serial |= static_cast<uint64_t>(serials_[serial_at_ + i]) << (8 * i);
    serial_at_ += 8;
    if (serial != 0 && body.serial == serial) return;  // the same body: its static fields stand
    if (serial == 0 || !statics_->recall(serial, body)) fail("a body this world never had (serial " + std::to_string(serial) + ")");
    body.serial = serial;
  }

  bool done() const { return at_ == bytes_.size() && serial_at_ == serials_.size(); }
  [[noreturn]] void fail(const std::string& reason) const {
    throw Error{{}, reason + " (payload byte " + std::to_string(at_) + ")"};
  }

 private:
  uint64_t within(uint64_t value, uint64_t lo, uint64_t hi, const char* name) {
    if (value < lo || value > hi) fail(std::string(name != nullptr ? name : "a list item") + " out of range");
    return value;
  }
  uint64_t take(int n) {
    if (bytes_.size() - at_ < static_cast<size_t>(n)) throw Error{{}, "truncated payload"};
    uint64_t v = 0;
    for (int i = 0; i < n; ++i) v |= static_cast<uint64_t>(bytes_[at_ + static_cast<size_t>(i)]) << (8 * i);
    at_ += static_cast<size_t>(n);
    return v;
  }

  std::span<const uint8_t> bytes_, serials_;
  size_t serial_at_ = 0;
  const BodyStatics* statics_;
  std::vector<uint8_t> own_marks_;
  std::vector<uint8_t>* marks_;
  size_t at_ = 0;
};

}  // namespace bitstep::state_bytes
