// The --threads option of run, record and verify, and the pool it makes.
#include <catch2/catch.hpp>

#include <atomic>

#include "tools/cli/thread_option.h"

using namespace bitstep;

TEST_CASE("the threads option takes a count from 1 to 64 and nothing else", "[threads]") {
  int n = 0;
  CHECK(parse_threads("1", n));
  CHECK(n == 1);
  CHECK(parse_threads("64", n));
  CHECK(n == 64);
  for (const char* bad : {"0", "65", "-2", "2x", "", " 2", "1e1"}) {
    INFO(bad);
    CHECK_FALSE(parse_threads(bad, n));
  }
  CHECK(n == 64);  // a refused value leaves the count as it was
}

TEST_CASE("one thread makes no pool, more make one of that many workers", "[threads]") {
  CHECK(make_pool(1) == nullptr);
  const auto pool = make_pool(3);
  REQUIRE(pool != nullptr);
  CHECK(pool->workers() == 3);
  // Every worker runs the task once, the caller's thread as worker 0.
  struct Seen {
    std::atomic<int> mask{0};
  } seen;
  pool->run([](void* context, int worker) { static_cast<Seen*>(context)->mask |= 1 << worker; }, &seen);
  CHECK(seen.mask == 0b111);
}
