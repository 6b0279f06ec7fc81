// Which islands keep the iterations' velocities after the shock step
// (core/shock_groups.h). The whole effect on settled heaps is tested in
// resting_energy_tests.cpp.
#include <catch2/catch.hpp>

#include <deque>
#include <vector>

#include "core/shock_groups.h"

namespace bitstep {
namespace {

constexpr Vec3 up{Fixed{}, Fixed::one(), Fixed{}};
constexpr Vec3 east{Fixed::one(), Fixed{}, Fixed{}};
constexpr Vec3 north{Fixed{}, Fixed{}, Fixed::one()};

// Contacts with one point at the centre of each (arms zero: each row reads
// the plain difference of the two velocities along its direction), normal
// up from a to b.
struct Contacts {
  std::deque<Manifold> manifolds;  // stable addresses for the rows
  std::vector<ManifoldRow> rows;
  std::vector<PointRow> points;

  void add(uint32_t a, uint32_t b, Fixed depth) {
    Manifold& manifold = manifolds.emplace_back();
    manifold.normal = up;
    manifold.point_count = 1;
    manifold.points[0].depth = depth;
    ManifoldRow m;
    m.a = a;
    m.b = b;
    m.first = points.size();
    m.count = 1;
    m.manifold = &manifold;
    m.normal.direction = up;
    m.tangent[0].direction = east;
    m.tangent[1].direction = north;
    m.twist.axis = up;
    m.twist_radius = 0.1_fx;
    rows.push_back(m);
    PointRow row;
    row.a = a;
    row.b = b;
    row.normal.direction = up;
    row.point = &manifold.points[0];
    points.push_back(row);
  }
};

}  // namespace

// Body 0 is the ground (immovable). Island A: 1 on the ground, 2 on 1.
// Island B: 3 on the ground, 4 on 3, sliding on it at 2 mm/s in the
// iterations. Island C: 5 on the ground. Body 6 hovers 1 mm above 2 (a
// speculative contact: not part of island A).
TEST_CASE("an island the iterations hold keeps their velocities where a shock rank did not converge", "[shock]") {
  const Fixed touching = 0.0001_fx, apart = -0.001_fx;
  Contacts c;
  c.add(0, 1, touching);
  c.add(1, 2, touching);
  c.add(0, 3, touching);
  c.add(3, 4, touching);
  c.add(0, 5, touching);
  c.add(2, 6, apart);
  std::vector<SolverBody> bodies(7);
  for (size_t i = 1; i < bodies.size(); ++i) bodies[i].inverse_mass = Fixed::one();
  // The iterations' velocities: island A and C at rest but for 0.5 mm/s
  // of sinking in A (quieter than 1 mm/s), body 4 sliding, body 6 falling.
  bodies[2].velocity.linear = {Fixed{}, -0.0005_fx, Fixed{}};
  bodies[4].velocity.linear = {0.002_fx, Fixed{}, Fixed{}};
  bodies[6].velocity.linear = {Fixed{}, -0.1_fx, Fixed{}};
  std::vector<BodyRates> iterations;
  for (const SolverBody& b : bodies) iterations.push_back(b.velocity);
  ShockGroups groups;
  keep_velocities(bodies, groups);
  // What the shock step's passes left: every body moved a little.
  std::vector<BodyRates> shock;
  for (size_t i = 0; i < bodies.size(); ++i) {
    bodies[i].velocity.angular = {Fixed{}, Fixed::from_int(static_cast<int>(i)) * 0.01_fx, Fixed{}};
    shock.push_back(bodies[i].velocity);
  }
  const Fixed quiet = 0.001_fx;

  SECTION("every rank converged: the shock step's answer stands") {
    CHECK(keep_iterations_where_held(c.rows, c.points, quiet, groups, bodies) == 0);
    for (size_t i = 0; i < bodies.size(); ++i) CHECK(bodies[i].velocity == shock[i]);
  }
  SECTION("ranks of islands A and B did not converge: only A, which the iterations hold, goes back") {
    groups.unconverged = {2, 4, 4};
    CHECK(keep_iterations_where_held(c.rows, c.points, quiet, groups, bodies) == 2);
    CHECK(bodies[1].velocity == iterations[1]);
    CHECK(bodies[2].velocity == iterations[2]);
    for (size_t i : {size_t{0}, size_t{3}, size_t{4}, size_t{5}, size_t{6}}) {
      INFO("body " << i);
      CHECK(bodies[i].velocity == shock[i]);
    }
  }
  SECTION("the slide in island B is under the quiet speed: B goes back too") {
    groups.unconverged = {3};
    CHECK(keep_iterations_where_held(c.rows, c.points, 0.003_fx, groups, bodies) == 2);
    CHECK(bodies[3].velocity == iterations[3]);
    CHECK(bodies[4].velocity == iterations[4]);
    CHECK(bodies[1].velocity == shock[1]);
  }
}

}  // namespace bitstep
