#include "fixed/checked.h"

#include <cinttypes>
#include <cstdio>
#include <cstdlib>

namespace bitstep {

namespace {
// Raw values printed as in the "raw:" text form: sign and hex magnitude.
void print_raw(int64_t v) {
  const uint64_t u = static_cast<uint64_t>(v);
  if (v < 0) {
    std::fprintf(stderr, "raw:-%" PRIx64, uint64_t{0} - u);
  } else {
    std::fprintf(stderr, "raw:%" PRIx64, u);
  }
}
}  // namespace

void fixed_fault(const char* operation, const char* reason, int64_t a, int64_t b) {
  std::fprintf(stderr, "bitstep checked: %s: %s (a=", operation, reason);
  print_raw(a);
  std::fprintf(stderr, ", b=");
  print_raw(b);
  std::fprintf(stderr, ")\n");
  std::abort();
}

}  // namespace bitstep
