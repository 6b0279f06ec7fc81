// Standalone known-answer program for tools/crosscheck.sh: built by each
// cross compiler from fixed/ and tools/known_answer.cpp alone, it prints the
// hash and exits 0 only if it is the frozen value.
#include <cinttypes>
#include <cstdio>

#include "tools/known_answer.h"

int main() {
  const bitstep::KnownAnswer answer = bitstep::run_known_answer();
  std::printf("%016" PRIx64 " %" PRIu64 "\n", answer.hash, answer.operations);
  return answer.hash == bitstep::expected_known_answer_hash ? 0 : 1;
}
