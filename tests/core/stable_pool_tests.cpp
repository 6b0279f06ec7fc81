// StablePool: what the shock step's one-sided copies live in. Pointers to
// them are held while more are made, so an address must never move; and a
// step that makes no more than an earlier one must reuse its blocks.
#include <catch2/catch.hpp>

#include <vector>

#include "core/stable_pool.h"

using bitstep::StablePool;

TEST_CASE("a stable pool keeps every address while it grows, and reuses its blocks after clear", "[pool]") {
  StablePool<int, 4> pool;
  std::vector<int*> made;
  for (int i = 0; i < 11; ++i) made.push_back(&pool.push(i));  // three blocks, the last one part full
  REQUIRE(pool.size() == 11);
  for (int i = 0; i < 11; ++i) CHECK(*made[static_cast<size_t>(i)] == i);  // nothing moved or was overwritten
  pool.clear();
  CHECK(pool.size() == 0);
  for (int i = 0; i < 11; ++i) CHECK(&pool.push(100 + i) == made[static_cast<size_t>(i)]);  // the same slots again
  CHECK(*made[10] == 110);
  int* twelfth = &pool.push(111);  // past what was used before: the third block's next slot
  CHECK(twelfth == made[10] + 1);
}
