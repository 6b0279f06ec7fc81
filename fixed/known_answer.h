// The fixed-point known-answer test: >= 10^6 mixed operations on operands from
// a seeded integer generator, folded into one 64-bit hash. Every build of
// bitstep (any compiler, optimisation level, 128-bit backend, CPU or byte
// order) must print the same value; tools/crosscheck/crosscheck.sh checks it.
#pragma once

#include <cstdint>

namespace bitstep {

struct KnownAnswer {
  uint64_t hash;
  uint64_t operations;
};

KnownAnswer run_known_answer();

// The value every build must produce, frozen when the number layer was
// written. Change it only with a commit that says why the bits moved.
inline constexpr uint64_t expected_known_answer_hash = 0xaed220f648e6e6a9;

}  // namespace bitstep
