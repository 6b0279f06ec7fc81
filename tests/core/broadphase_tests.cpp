// The broadphase reports exactly the overlapping pairs with a mover, in
// (a, b) order, whether it uses the grid or tests the few movers against all.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <vector>

#include "core/broadphase.h"
#include "fixed/decimal.h"

using namespace bitstep;
using namespace bitstep::literals;

namespace {

// A fixed linear congruential sequence (Knuth's MMIX constants).
struct Sequence {
  uint64_t state;
  int64_t below(int64_t n) {
    state = state * 6364136223846793005ull + 1442695040888963407ull;
    return static_cast<int64_t>((state >> 33) % static_cast<uint64_t>(n));
  }
};

// n boxes up to 1 m wide in a 20 m cube, every `mover_every`-th one movable,
// plus a large static proxy around them all.
std::vector<BroadphaseProxy> scatter(uint32_t n, uint32_t mover_every, uint64_t seed) {
  Sequence random{seed};
  std::vector<BroadphaseProxy> proxies;
  for (uint32_t i = 0; i < n; ++i) {
    Vec3 min{Fixed::from_ratio(random.below(20000), 1000), Fixed::from_ratio(random.below(20000), 1000),
             Fixed::from_ratio(random.below(20000), 1000)};
    Vec3 size{Fixed::from_ratio(random.below(1000) + 10, 1000), Fixed::from_ratio(random.below(1000) + 10, 1000),
              Fixed::from_ratio(random.below(1000) + 10, 1000)};
    proxies.push_back({i, {min, min + size}, i % mover_every == 0});
  }
  proxies.push_back({n, {{-1.0_fx, -1.0_fx, -1.0_fx}, {21.0_fx, 21.0_fx, 21.0_fx}}, false});
  return proxies;
}

std::vector<BodyPair> all_pairs(const std::vector<BroadphaseProxy>& proxies) {
  std::vector<BodyPair> pairs;
  for (size_t i = 0; i < proxies.size(); ++i) {
    for (size_t j = i + 1; j < proxies.size(); ++j) {
      if ((proxies[i].movable || proxies[j].movable) && proxies[i].bounds.overlaps(proxies[j].bounds)) {
        pairs.push_back({std::min(proxies[i].body, proxies[j].body), std::max(proxies[i].body, proxies[j].body)});
      }
    }
  }
  std::sort(pairs.begin(), pairs.end());
  return pairs;
}

}  // namespace

TEST_CASE("find_pairs gives every overlapping pair with a mover, by the grid and by the few-movers test",
          "[broadphase]") {
  // Movers: all (grid), one in 4 (grid), one in 100 and one in 1000 (each
  // mover against all), none.
  for (uint32_t mover_every : {1u, 4u, 100u, 1000u, 100000u}) {
    for (uint64_t seed : {1u, 2u, 3u}) {
      INFO("one mover in " << mover_every << ", seed " << seed);
      const std::vector<BroadphaseProxy> proxies = scatter(2000, mover_every, seed);
      std::vector<BodyPair> pairs;
      BroadphaseScratch scratch;
      find_pairs(proxies, pairs, scratch);
      const std::vector<BodyPair> expected = all_pairs(proxies);
      CHECK(pairs == expected);
      if (mover_every < 100000u) CHECK(!expected.empty());
    }
  }
}

TEST_CASE("find_pairs is exact whether the grid's cells pack into one sort key or not", "[broadphase]") {
  // Near the origin and at negative cells the keys pack (the cells' ranges
  // and the proxy numbers fit 64 bits); with a cluster a million metres
  // away the ranges need 3 x 20 bits besides the proxy number's, and the
  // entries are sorted as they are.
  for (const Vec3 far : {Vec3{-30.0_fx, -30.0_fx, -30.0_fx}, Vec3{1000000.0_fx, -1000000.0_fx, 1000000.0_fx}}) {
    std::vector<BroadphaseProxy> proxies = scatter(1500, 1, 7);
    for (BroadphaseProxy p : scatter(1500, 2, 8)) {
      if (p.bounds.max.x - p.bounds.min.x > 8.0_fx) continue;  // the large proxy once
      p.body += 1501;
      p.bounds = {p.bounds.min + far, p.bounds.max + far};
      proxies.push_back(p);
    }
    std::vector<BodyPair> pairs;
    BroadphaseScratch scratch;
    find_pairs(proxies, pairs, scratch);
    const std::vector<BodyPair> expected = all_pairs(proxies);
    CHECK(pairs == expected);
    CHECK(std::count_if(expected.begin(), expected.end(), [](BodyPair p) { return p.a > 1500; }) > 100);
  }
}

TEST_CASE("find_pairs packs a key whose fields fill all 64 bits", "[broadphase]") {
  // 33 0.1 m boxes (cells of 0.125 m) in one x cell (past 32 proxies the
  // grid runs), the outer two 5e7 m apart in y and z: the y and z ranges
  // take 29 bits each and the proxy numbers 6, so the empty x field sits at
  // bit 64 (it must not be shifted there). Two boxes overlap.
  const auto box = [](uint32_t body, Fixed y, Fixed z) {
    return BroadphaseProxy{body, {{0.0_fx, y, z}, {0.1_fx, y + 0.1_fx, z + 0.1_fx}}, true};
  };
  std::vector<BroadphaseProxy> proxies = {box(0, -25000000.0_fx, -25000000.0_fx), box(1, 25000000.0_fx, 25000000.0_fx),
                                          box(2, -24999999.95_fx, -24999999.95_fx)};
  for (int32_t k = 0; k < 30; ++k) {  // 1 m apart, away from the others
    proxies.push_back(box(static_cast<uint32_t>(3 + k), Fixed::from_int(k), Fixed::from_int(k)));
  }
  std::vector<BodyPair> pairs;
  BroadphaseScratch scratch;
  find_pairs(proxies, pairs, scratch);
  CHECK(pairs == all_pairs(proxies));
  CHECK(pairs == std::vector<BodyPair>{{0, 2}});
}

TEST_CASE("find_pairs tests every pair of a small scene", "[broadphase]") {
  // Up to 32 proxies every pair is tested; from 33 the grid runs. Both give
  // the same pairs.
  for (uint32_t n : {1u, 2u, 7u, 31u, 32u}) {
    for (uint32_t mover_every : {1u, 3u, 100u}) {
      INFO(n + 1 << " proxies, one mover in " << mover_every);
      const std::vector<BroadphaseProxy> proxies = scatter(n, mover_every, n);
      std::vector<BodyPair> pairs;
      BroadphaseScratch scratch;
      find_pairs(proxies, pairs, scratch);
      CHECK(pairs == all_pairs(proxies));
      CHECK(!pairs.empty());  // the large proxy holds every mover (body 0 moves)
    }
  }
}
