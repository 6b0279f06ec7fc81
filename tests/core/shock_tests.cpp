// The shock step's phases on their own (core/shock.h): which manifolds it
// solves and in what order, which bodies it glues to several supports at
// once, and what a rank whose passes do not converge keeps. The whole step
// is tested through worlds in stacking_tests.cpp and resting_energy_tests.cpp.
#include <catch2/catch.hpp>

#include <vector>

#include "core/shock.h"

namespace bitstep {
namespace {

constexpr Vec3 up{Fixed{}, Fixed::one(), Fixed{}};
constexpr Vec3 east{Fixed::one(), Fixed{}, Fixed{}};

// A manifold between bodies a and b (normal from a to b) with one point at
// the given depth (> 0 overlapping, < 0 apart).
struct Pair {
  uint32_t a, b;
  Vec3 normal;
  Fixed depth;
};

struct Fixture {
  ShockLevels levels;
  std::vector<Manifold> manifolds;
  std::vector<ManifoldRow> rows;

  Fixture(std::vector<uint32_t> rank, std::vector<uint32_t> height, const std::vector<Pair>& pairs) {
    levels.rank = std::move(rank);
    levels.height = std::move(height);
    manifolds.resize(pairs.size());
    for (size_t i = 0; i < pairs.size(); ++i) {
      manifolds[i].normal = pairs[i].normal;
      manifolds[i].point_count = 1;
      manifolds[i].points[0].depth = pairs[i].depth;
      ManifoldRow row;
      row.a = pairs[i].a;
      row.b = pairs[i].b;
      row.count = 1;
      row.manifold = &manifolds[i];
      rows.push_back(row);
    }
  }
};

}  // namespace

// Bodies: 0 the ground; 1 a box on it; 2 a box on 1; 3 falling (no rank);
// 4 pressed against 1 from the side (a sideways chain: rank 2, height 1);
// 5 a box of height 2 touching 1 from the side; 6 a box beside 2 (rank 2,
// height 2).
TEST_CASE("the shock step solves supports, sideways chains and ranks' own contacts, in rank order", "[shock]") {
  const Settings settings;  // gravity along -y
  const Fixed apart = -0.001_fx, touching = 0.0001_fx;
  Fixture f({0, 1, 2, not_supported, 2, 3, 2}, {0, 1, 2, not_supported, 1, 2, 2},
            {
                {1, 2, up, touching},      // 0: 1 holds 2 up
                {0, 1, up, touching},      // 1: the ground holds 1 up
                {2, 3, up, touching},      // 2: 3 has no rank
                {1, 4, east, touching},    // 3: sideways within height 1
                {0, 1, up, apart},         // 4: speculative support: for the iterations
                {2, 1, -up, touching},     // 5: written the other way round: 1 holds 2 up
                {1, 5, east, touching},    // 6: between heights, not a support
                {2, 6, east, touching},    // 7: within rank 2 and height 2
                {1, 4, east, apart},       // 8: sideways and apart: solved one-sided up to touching
            });
  std::vector<ShockEntry> order;
  ShockOrderWorkspace workspace;
  order_manifolds(settings, f.levels, f.rows, order, workspace);
  std::vector<uint32_t> indices, levels;
  std::vector<bool> holds_up;
  for (const ShockEntry& e : order) {
    indices.push_back(e.index);
    levels.push_back(e.level);
    holds_up.push_back(e.holds_up);
  }
  // Rank 2 in two clusters: 2 with 6 beside it (0, 5, 7), and 4 (3, 8).
  CHECK(indices == std::vector<uint32_t>{1, 0, 5, 7, 3, 8});
  CHECK(levels == std::vector<uint32_t>{1, 2, 2, 2, 2, 2});
  CHECK(holds_up == std::vector<bool>{true, true, true, false, false, false});
}

// Two columns on one ground, 1 on 0 and 2 on 1, 3 on 0 and 4 on 3, and 5
// on 2 and 4, joining them at rank 3; 6 beside 5 and touching it. Rank by
// rank, the bodies of a rank fall into clusters joined by the rank's own
// manifolds (numbered by their lowest slot), each solved on its own: the
// two columns' ranks 1 and 2 are two clusters each, rank 3 one.
TEST_CASE("the shock step solves each rank cluster by cluster", "[shock]") {
  const Settings settings;
  const Fixed touching = 0.0001_fx;
  Fixture f({0, 1, 2, 1, 2, 3, 3}, {0, 1, 2, 1, 2, 3, 3},
            {
                {0, 3, up, touching},    // 0
                {0, 1, up, touching},    // 1
                {3, 4, up, touching},    // 2
                {1, 2, up, touching},    // 3
                {4, 5, up, touching},    // 4
                {2, 5, up, touching},    // 5
                {5, 6, east, touching},  // 6
            });
  std::vector<ShockEntry> order;
  ShockOrderWorkspace workspace;
  order_manifolds(settings, f.levels, f.rows, order, workspace);
  std::vector<uint32_t> indices, clusters, levels;
  for (const ShockEntry& e : order) {
    indices.push_back(e.index);
    clusters.push_back(e.cluster);
    levels.push_back(e.level);
  }
  CHECK(indices == std::vector<uint32_t>{1, 0, 3, 2, 4, 5, 6});
  CHECK(clusters == std::vector<uint32_t>{1, 3, 2, 4, 5, 5, 5});
  CHECK(levels == std::vector<uint32_t>{1, 1, 2, 2, 3, 3, 3});
}

// Body 1 stands on four legs on body 0 (four contacts with one support),
// body 2 on body 1 through one contact, body 3 on bodies 1 and 2.
TEST_CASE("the shock step groups a body's support contacts when it has more than one", "[shock]") {
  const Settings settings;
  const Fixed touching = 0.0001_fx;
  Fixture f({0, 1, 2, 3}, {0, 1, 2, 2},
            {
                {0, 1, up, touching},
                {1, 2, up, touching},
                {0, 1, up, touching},
                {1, 3, up, touching},
                {0, 1, up, touching},
                {2, 3, up, touching},
                {0, 1, up, touching},
            });
  std::vector<ShockEntry> order;
  ShockOrderWorkspace workspace;
  order_manifolds(settings, f.levels, f.rows, order, workspace);
  REQUIRE(order.size() == 7);
  SupportGroups groups;
  group_supports(4, f.levels.rank, f.rows, order, groups);
  CHECK(groups.several == std::vector<uint8_t>{0, 1, 0, 1});
  // Positions in `order`, whose manifolds are those of body 1's legs and of
  // body 3's two supports.
  std::vector<uint32_t> legs(groups.entries.begin() + groups.begin[1], groups.entries.begin() + groups.begin[2]);
  std::vector<uint32_t> legs_manifolds;
  for (uint32_t position : legs) legs_manifolds.push_back(order[position].index);
  CHECK(legs_manifolds == std::vector<uint32_t>{0, 2, 4, 6});
  CHECK(groups.begin[3] == groups.begin[2]);  // body 2: one support, no group
  std::vector<uint32_t> top;
  for (uint32_t k = groups.begin[3]; k < groups.begin[4]; ++k) top.push_back(order[groups.entries[k]].index);
  CHECK(top == std::vector<uint32_t>{3, 5});
}

// Two bodies of an unconverged rank: a 2 kg box whose passes left it
// faster than the iterations did, and a 1 kg one left slower.
TEST_CASE("a rank whose passes do not converge never leaves a body faster than the iterations did", "[shock]") {
  std::vector<Body> bodies(2);
  for (Body& b : bodies) b.inertia_local = Mat33::diagonal({0.1_fx, 0.1_fx, 0.1_fx});
  std::vector<SolverBody> solver(2);
  solver[0].inverse_mass = 0.5_fx;
  solver[1].inverse_mass = Fixed::one();
  const BodyRates slow{{0.001_fx, Fixed{}, Fixed{}}, {}}, fast{{Fixed{}, -0.002_fx, Fixed{}}, {Fixed{}, Fixed{}, 0.01_fx}};
  const std::vector<RankBody> before{{0, slow}, {1, fast}, {0, slow}};  // duplicates, as the rank lists them
  solver[0].velocity = fast;  // where the last pass left them
  solver[1].velocity = slow;

  SECTION("each body keeps the lower-energy velocity") {
    settle_unconverged_cluster(bodies, before, false, solver);
    CHECK(solver[0].velocity == slow);
    CHECK(solver[1].velocity == slow);
  }
  SECTION("a rank the iterations already hold gets their velocities back") {
    settle_unconverged_cluster(bodies, before, true, solver);
    CHECK(solver[0].velocity == slow);
    CHECK(solver[1].velocity == fast);
  }
}

// Body 0, a support the shock step has just stopped, and body 1 resting on
// it through one touching point at the centre (arms zero, so each row
// reads the plain difference of the velocities along its direction).
TEST_CASE("a rank is held already only if nothing approaches, slides or twists at its contacts", "[shock]") {
  Manifold manifold;
  manifold.normal = up;
  manifold.point_count = 1;
  manifold.points[0].depth = 0.0001_fx;
  ManifoldRow m;
  m.a = 0;
  m.b = 1;
  m.first = 0;
  m.count = 1;
  m.manifold = &manifold;
  m.normal.direction = up;
  m.tangent[0].direction = east;
  m.tangent[1].direction = Vec3{Fixed{}, Fixed{}, Fixed::one()};
  m.twist.axis = up;
  m.twist_radius = 0.1_fx;
  PointRow row;
  row.a = 0;
  row.b = 1;
  row.normal.direction = up;
  row.point = &manifold.points[0];
  const std::vector<PointRow> rows{row};
  std::vector<SolverBody> solver(2);
  const Fixed quiet = 0.001_fx;
  const auto moving = [&] { return moving_at_contact(solver, rows, m, quiet); };

  CHECK_FALSE(moving());
  solver[1].velocity.linear = {0.0006_fx, -0.0005_fx, Fixed{}};
  CHECK_FALSE(moving());  // slower than 1 mm/s either way
  solver[1].velocity.linear = {0.0015_fx, Fixed{}, Fixed{}};
  CHECK(moving());  // carried along by a support that has stopped: slides
  solver[0].velocity.linear = solver[1].velocity.linear;
  CHECK_FALSE(moving());  // the support moves with it
  solver[1].velocity.linear = {0.0015_fx, -0.002_fx, Fixed{}};
  CHECK(moving());  // approaching at 2 mm/s
  solver[1].velocity.linear = solver[0].velocity.linear;
  solver[1].velocity.angular = {Fixed{}, 0.02_fx, Fixed{}};
  CHECK(moving());  // twisting: 0.02 rad/s at 0.1 m is 2 mm/s
  manifold.points[0].depth = -0.001_fx;
  CHECK_FALSE(moving());  // apart: not a contact that holds anything
}

}  // namespace bitstep

namespace bitstep {
namespace {

// Runs skip_repeating_passes over the velocities a rank of one body is left
// with pass after pass (speeds along x, m/s); returns the pass it says to go
// on after at each pass, with 32 passes in all (last pass 31).
std::vector<int> skips_for(const std::vector<int>& speeds) {
  std::vector<SolverBody> solver(1);
  const std::vector<RankBody> rank{{0, {}}};
  std::vector<BodyRates> history;
  std::vector<int> next;
  for (int pass = 0; pass < static_cast<int>(speeds.size()); ++pass) {
    solver[0].velocity.linear.x = Fixed::from_int(speeds[static_cast<size_t>(pass)]);
    next.push_back(skip_repeating_passes(solver, rank, history, pass, 31));
  }
  return next;
}

}  // namespace
}  // namespace bitstep

TEST_CASE("a rank's passes that only go round a cycle are skipped, ending in the same phase", "[shock]") {
  using bitstep::skips_for;
  SECTION("period 2: skipped once a whole period repeats, to the pass of the last one's parity") {
    // 5, 1, 2, 1, 2: passes 3 and 4 repeat passes 1 and 2.
    const std::vector<int> next = skips_for({5, 1, 2, 1, 2});
    // 31 - (31 - 4) % 2 = 30: pass 31 still runs and, odd, leaves the velocity
    // of the odd passes (1), as running every pass would have.
    CHECK(next == std::vector<int>{0, 1, 2, 3, 30});
  }
  SECTION("period 4") {
    const std::vector<int> next = skips_for({9, 1, 2, 3, 4, 1, 2, 3, 4});
    CHECK(next.back() == 31 - (31 - 8) % 4);  // 28: passes 29, 30, 31 run, in phase with 9, 10, 11 of the cycle
    for (size_t p = 0; p + 1 < next.size(); ++p) CHECK(next[p] == static_cast<int>(p));
  }
  SECTION("a single repeat is not a cycle") {
    // Pass 2 equals pass 0, but pass 3 does not equal pass 1.
    const std::vector<int> next = skips_for({1, 2, 1, 3, 4, 5});
    for (size_t p = 0; p < next.size(); ++p) CHECK(next[p] == static_cast<int>(p));
  }
  SECTION("an odd period is not taken: a pass's point rows run in the direction of its parity") {
    const std::vector<int> next = skips_for({1, 2, 3, 1, 2, 3, 1, 2, 3});
    for (size_t p = 0; p < next.size(); ++p) CHECK(next[p] == static_cast<int>(p));
  }
}
