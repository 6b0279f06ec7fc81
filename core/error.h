// The one error type of the engine, and a result carrying a value or it.
// Every call that can refuse its input returns a Result: World's create
// calls here in core, each reader in replay/ (a scene, a replay, a state
// image, a packet), and the facade; the C API maps an Error to its statuses.
//
// An error is a place and a reason, kept apart so that each layer can name
// the place in its own terms and callers can add where they stand: World
// names a field ("body_b", "shapes.radius"), a reader a JSON path
// ("$.bodies[2].shapes[0].radius") or a byte ("byte 17"), its caller the
// file. message() joins them into the one line users see.
#pragma once

#include <optional>
#include <string>
#include <utility>
#include <variant>

namespace bitstep {

struct Error {
  std::string place;   // where, outermost first: "scene.json: $.bodies[2].radius"; may be empty
  std::string reason;  // what is wrong there: "outside 0.01..50 m"

  // "<place>: <reason>", or the reason alone when there is no place.
  std::string message() const { return place.empty() ? reason : place + ": " + reason; }

  // The same error seen from outside `outer` (a file, "body 3"): the place
  // gains `outer` in front (nothing when `outer` is empty).
  Error within(const std::string& outer) const {
    if (outer.empty()) return *this;
    return {place.empty() ? outer : outer + ": " + place, reason};
  }
};

// A value or the error that stopped it. C++20 has no std::expected; this is
// the small part of it the engine uses. value() on an error (or error() on a
// value) is a caller's bug: std::get throws bad_variant_access.
template <class T>
class Result {
 public:
  Result(T value) : state_(std::in_place_index<0>, std::move(value)) {}
  Result(Error error) : state_(std::in_place_index<1>, std::move(error)) {}

  // No operator bool: a test of a result must say ok(), never read as
  // "has an error" (what the optional<string> errors it replaced meant).
  bool ok() const { return state_.index() == 0; }

  T& value() & { return std::get<0>(state_); }
  const T& value() const& { return std::get<0>(state_); }
  T&& value() && { return std::get<0>(std::move(state_)); }
  T* operator->() { return &value(); }
  const T* operator->() const { return &value(); }
  T& operator*() & { return value(); }
  const T& operator*() const& { return value(); }

  const Error& error() const { return std::get<1>(state_); }

 private:
  std::variant<T, Error> state_;
};

// For calls that give nothing back but may refuse: `return {};` is success.
template <>
class Result<void> {
 public:
  Result() = default;
  Result(Error error) : error_(std::move(error)) {}

  bool ok() const { return !error_.has_value(); }
  const Error& error() const { return error_.value(); }

 private:
  std::optional<Error> error_;
};

}  // namespace bitstep
