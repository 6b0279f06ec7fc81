// Islands: bodies joined by touching contacts, static bodies never joining.
#include <catch2/catch.hpp>

#include "core/islands.h"
#include "tests/core/test_world.h"

using namespace bitstep;
using bitstep::test::TestWorld;

namespace {

std::vector<BodyId> add_column(TestWorld& t, Fixed x, int count) {
  std::vector<BodyId> boxes;
  for (int i = 0; i < count; ++i) {
    boxes.push_back(t.add_box({x, Fixed::from_int(i) + 0.5_fx, Fixed{}}, {0.5_fx, 0.5_fx, 0.5_fx}));
  }
  return boxes;
}

Islands islands_of(const TestWorld& t) {
  Islands islands;
  build_islands(t.world.bodies(), t.world.contacts(), t.world.joints(), islands);
  return islands;
}

}  // namespace

TEST_CASE("two stacks on one ground are two islands, each in slot order", "[islands]") {
  TestWorld t;
  const BodyId ground = t.add_ground();
  const std::vector<BodyId> left = add_column(t, -5.0_fx, 4);
  const std::vector<BodyId> right = add_column(t, 5.0_fx, 3);
  const BodyId falling = t.add_box({Fixed{}, 20.0_fx, Fixed{}}, {0.5_fx, 0.5_fx, 0.5_fx});
  t.simulate_steps(2);
  const Islands islands = islands_of(t);
  REQUIRE(islands.count() == 3);  // the falling box alone is an island too
  CHECK(islands.island_of[ground.index] == no_island);
  for (BodyId id : left) CHECK(islands.island_of[id.index] == 0);
  for (BodyId id : right) CHECK(islands.island_of[id.index] == 1);
  CHECK(islands.island_of[falling.index] == 2);
  const std::vector<uint32_t> first_island(islands.members.begin() + islands.first[0],
                                           islands.members.begin() + islands.first[1]);
  CHECK(first_island == std::vector<uint32_t>{1, 2, 3, 4});
}

TEST_CASE("removing a middle box splits its stack's island", "[islands]") {
  TestWorld t;
  t.add_ground();
  const std::vector<BodyId> column = add_column(t, Fixed{}, 6);
  t.simulate_steps(2);
  CHECK(islands_of(t).count() == 1);
  REQUIRE(t.world.remove_body(column[2]));
  t.simulate_steps(1);  // the contacts of the removed box went with it
  const Islands islands = islands_of(t);
  CHECK(islands.count() == 2);
  CHECK(islands.island_of[column[1].index] != islands.island_of[column[3].index]);
  CHECK(islands.island_of[column[2].index] == no_island);
}
