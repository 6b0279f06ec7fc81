#include <catch2/catch.hpp>

#include "fixed/known_answer.h"

// The same >= 10^6 mixed operations give the same bits in every build; the
// frozen value lives in fixed/known_answer.h and tools/crosscheck/crosscheck.sh compares
// it across compilers, backends and CPUs.
TEST_CASE("known-answer hash over a million mixed operations is frozen", "[fixed][known-answer]") {
  const bitstep::KnownAnswer answer = bitstep::run_known_answer();
  CHECK(answer.operations >= 1000000);
  CHECK(answer.hash == bitstep::expected_known_answer_hash);
}
