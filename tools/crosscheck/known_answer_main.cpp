// Standalone known-answer program for tools/crosscheck/crosscheck.sh: built by each
// cross compiler from fixed/ alone, it prints
// "<hash> <operations> <128-bit backend> <byte order>" and exits 0 only if the
// hash is the frozen value.
#include <bit>
#include <cinttypes>
#include <cstdio>

#include "fixed/known_answer.h"
#include "fixed/u128.h"

int main() {
  const bitstep::KnownAnswer answer = bitstep::run_known_answer();
  const char* byte_order = std::endian::native == std::endian::little ? "little-endian" : "big-endian";
  std::printf("%016" PRIx64 " %" PRIu64 " %s %s\n", answer.hash, answer.operations, bitstep::wide_backend_name,
              byte_order);
  return answer.hash == bitstep::expected_known_answer_hash ? 0 : 1;
}
