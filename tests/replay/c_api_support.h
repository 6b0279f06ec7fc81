// What the C API's tests share: a simulation from scene text, a body by
// name, and whole numbers as Q32.32.
#pragma once

#include <catch2/catch.hpp>
#include <cstring>

#include "replay/bitstep.h"

constexpr bitstep_fixed units(int64_t value) { return value * (int64_t{1} << 32); }

inline bitstep_simulation* simulation_of(const char* scene, const char* name) {
  bitstep_simulation* sim = nullptr;
  char error[256] = "";
  const bitstep_status status = bitstep_create_from_text(scene, std::strlen(scene), name, &sim, error, sizeof error);
  INFO(error);
  REQUIRE(status == BITSTEP_OK);
  return sim;
}

inline bitstep_body body(bitstep_simulation* sim, const char* name) {
  bitstep_body b{};
  REQUIRE(bitstep_find_body(sim, name, &b) == BITSTEP_OK);
  return b;
}
