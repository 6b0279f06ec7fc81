// What is behind the C API's simulation handle, and the rules every C call
// follows (replay/bitstep.h): shared by the simulation's calls
// (bitstep_c.cpp) and the session's (bitstep_session_c.cpp). Not a public
// header: C sees only the opaque handle.
#pragma once

#include <initializer_list>
#include <new>
#include <optional>
#include <string>
#include <utility>

#include "replay/bitstep.h"
#include "replay/simulation.h"

// A simulation the handle owns (bitstep_create_*), or one a session owns
// (bitstep_session_simulation: the session's world, borrowed; destroying
// it does nothing, the session's destroy ends it).
struct bitstep_simulation {
  std::optional<bitstep::Simulation> owned;
  bitstep::Simulation* sim = nullptr;
  std::string last_error;

  explicit bitstep_simulation(bitstep::Simulation simulation) : owned(std::move(simulation)), sim(&*owned) {}
  explicit bitstep_simulation(bitstep::Simulation* borrowed) : sim(borrowed) {}
  bitstep_simulation(const bitstep_simulation&) = delete;
  bitstep_simulation& operator=(const bitstep_simulation&) = delete;
};

namespace bitstep::c_api {

// A failure's status, its message kept for bitstep_last_error.
inline bitstep_status fail(std::string& last_error, bitstep_status status, std::string message) {
  last_error = std::move(message);
  return status;
}

// The one mapping of the facade's Error to a status: every error it returns
// is about the input (a malformed scene, body, joint or image), so
// BITSTEP_INVALID, the message its one line.
inline bitstep_status fail(std::string& last_error, const Error& error) {
  last_error = error.message();
  return BITSTEP_INVALID;
}

// A NULL where the call needs a pointer: "get_pose: out is NULL".
inline bitstep_status null_argument(std::string& last_error, const char* call, const char* argument) {
  return fail(last_error, BITSTEP_NULL_ARGUMENT, std::string(call) + ": " + argument + " is NULL");
}

// The first NULL of a call's pointer arguments, or nullptr.
inline const char* first_null(std::initializer_list<std::pair<const void*, const char*>> arguments) {
  for (const auto& [pointer, name] : arguments) {
    if (pointer == nullptr) return name;
  }
  return nullptr;
}

// Runs `call` (returning a status) on a handle that is not NULL, every
// exception caught: no exception crosses into C.
template <typename Handle, typename Call>
bitstep_status guarded(Handle* handle, Call&& call) {
  if (handle == nullptr) return BITSTEP_NULL_ARGUMENT;
  try {
    return call();
  } catch (const std::bad_alloc&) {
    return fail(handle->last_error, BITSTEP_OUT_OF_MEMORY, "out of memory");
  } catch (const std::exception& e) {
    return fail(handle->last_error, BITSTEP_INVALID, e.what());
  }
}

inline BodyId body_of(bitstep_body b) { return {b.index, b.generation}; }
inline bitstep_body body_to_c(BodyId id) { return {id.index, id.generation}; }

}  // namespace bitstep::c_api
