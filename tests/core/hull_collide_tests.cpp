// The generic convex path (core/collide_hull.cpp) against the hand-written
// routines where both apply: a box built as a hull meets boxes, planes,
// spheres and capsules as the box does. And a hull in motion: a die thrown
// onto the ground comes to rest on a face.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "core/collide.h"
#include "core/convex_hull.h"
#include "core/world.h"
#include "fixed/quat.h"
#include "fixed/splitmix64.h"
#include "tests/core/test_world.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::to_double;

namespace {

Fixed fixed_of(double d) { return Fixed::from_raw(static_cast<int64_t>(std::llround(d * 4294967296.0))); }

double uniform(SplitMix64& random, double lo, double hi) {
  return lo + (hi - lo) * static_cast<double>(random.next() % 1000001) / 1000000.0;
}

Quat random_orientation(SplitMix64& random) {
  const auto component = [&] { return fixed_of(uniform(random, -1, 1)); };
  return normalize(Quat{component(), component(), component(), component()});
}

// Half extents on the hull's grid, 0.1..1.5 m.
Vec3 random_half_extents(SplitMix64& random) {
  const auto size = [&] { return Fixed::from_raw(fixed_of(uniform(random, 0.1, 1.5)).raw() & ~int64_t{0xFFF}); };
  return {size(), size(), size()};
}

double deepest(const Manifold& m) {
  double d = -1e9;
  for (int i = 0; i < m.point_count; ++i) d = std::max(d, to_double(m.points[static_cast<size_t>(i)].depth));
  return d;
}

// Every point of `a` has a point of `b` within `tolerance` (m), depth too.
bool same_points(const Manifold& a, const Manifold& b, double tolerance) {
  for (int i = 0; i < a.point_count; ++i) {
    const ContactPoint& p = a.points[static_cast<size_t>(i)];
    bool found = false;
    for (int j = 0; j < b.point_count && !found; ++j) {
      const ContactPoint& q = b.points[static_cast<size_t>(j)];
      const Vec3 d = p.position - q.position;
      found = std::abs(to_double(d.x)) < tolerance && std::abs(to_double(d.y)) < tolerance &&
              std::abs(to_double(d.z)) < tolerance && std::abs(to_double(p.depth - q.depth)) < tolerance;
    }
    if (!found) return false;
  }
  return true;
}

struct Agreement {
  int pairs = 0, touching = 0, same_normal = 0, same_manifold = 0;
  double worst_depth = 0;  // |deepest(generic) - deepest(hand-written)|, m, over the pairs with the same normal
};

// Compares collide(generic a, b) with collide(hand-written a, b).
void compare(const WorldShape& generic, const WorldShape& written, const WorldShape& other, Agreement& agreement) {
  const Fixed speculative = 0.02_fx;
  Manifold g, w;
  const int count_g = collide(generic, other, speculative, g);
  const int count_w = collide(written, other, speculative, w);
  ++agreement.pairs;
  INFO("pair " << agreement.pairs << ": " << count_g << " generic points, " << count_w << " hand-written");
  if (count_w == 0 && count_g == 0) return;
  // Either both touch or neither: a shape within the speculative distance
  // is found by both (a margin of 1 mm for the other's rounding).
  if (count_w == 0 || count_g == 0) {
    CHECK(std::max(deepest(g), deepest(w)) < -0.019);
    return;
  }
  ++agreement.touching;
  const double along = to_double(dot(g.normal, w.normal));
  if (along < 0.9999) return;
  ++agreement.same_normal;
  const double depth_error = std::abs(deepest(g) - deepest(w));
  agreement.worst_depth = std::max(agreement.worst_depth, depth_error);
  if (count_g == count_w && same_points(g, w, 1e-4) && same_points(w, g, 1e-4)) ++agreement.same_manifold;
}

}  // namespace

TEST_CASE("Hull contacts: a box made as a hull meets boxes as the box-box routine does", "[hull]") {
  SplitMix64 random{77};
  Agreement hull_box, hull_hull;
  for (int round = 0; round < 600; ++round) {
    const Vec3 ha = random_half_extents(random), hb = random_half_extents(random);
    const Shape box_a{ShapeType::box, ha, {}, {}, {}}, box_b{ShapeType::box, hb, {}, {}, {}};
    const Shape hull_a = test::box_hull(ha), hull_b = test::box_hull(hb);
    const Vec3 base = round % 3 == 0 ? Vec3{fixed_of(9000.5), fixed_of(-300.25), fixed_of(-4000)} : Vec3{};
    const Pose pose_a{base, random_orientation(random)};
    // B placed about as far as the two reach: touching, overlapping or apart.
    const double reach = to_double(length(ha) + length(hb));
    const Vec3 offset{fixed_of(uniform(random, -reach, reach) * 0.7), fixed_of(uniform(random, -reach, reach) * 0.7),
                      fixed_of(uniform(random, -reach, reach) * 0.7)};
    const Pose pose_b{base + offset, random_orientation(random)};
    compare({&hull_a, pose_a}, {&box_a, pose_a}, {&box_b, pose_b}, hull_box);
    // Hull against hull: both boxes as hulls (the box-box routine as the reference).
    Manifold g, w;
    const int count_g = collide({&hull_a, pose_a}, {&hull_b, pose_b}, 0.02_fx, g);
    const int count_w = collide({&box_a, pose_a}, {&box_b, pose_b}, 0.02_fx, w);
    ++hull_hull.pairs;
    if (count_g > 0 && count_w > 0) {
      ++hull_hull.touching;
      if (to_double(dot(g.normal, w.normal)) >= 0.9999) {
        ++hull_hull.same_normal;
        hull_hull.worst_depth = std::max(hull_hull.worst_depth, std::abs(deepest(g) - deepest(w)));
        if (count_g == count_w && same_points(g, w, 1e-4) && same_points(w, g, 1e-4)) ++hull_hull.same_manifold;
      }
    } else {
      CHECK(count_g == count_w);
    }
  }
  for (const Agreement* a : {&hull_box, &hull_hull}) {
    INFO(a->pairs << " pairs, " << a->touching << " touching, " << a->same_normal << " with the same normal, "
                  << a->same_manifold << " with the same points; worst depth difference " << a->worst_depth << " m");
    CHECK(a->touching > 250);
    CHECK(a->same_normal >= a->touching * 97 / 100);
    CHECK(a->same_manifold >= a->touching * 90 / 100);
    CHECK(a->worst_depth < 1e-6);
  }
}

TEST_CASE("Hull contacts: planes, spheres and capsules meet a box-shaped hull as they meet the box", "[hull]") {
  SplitMix64 random{91};
  Agreement plane, sphere, capsule;
  const Shape ground{ShapeType::plane, {}, {}, {}, {}};
  for (int round = 0; round < 400; ++round) {
    const Vec3 h = random_half_extents(random);
    const Shape box{ShapeType::box, h, {}, {}, {}};
    const Shape hull = test::box_hull(h);
    const Pose pose{{fixed_of(uniform(random, -2, 2)), fixed_of(uniform(random, -0.5, 1.5)), Fixed{}},
                    random_orientation(random)};
    compare({&hull, pose}, {&box, pose}, {&ground, Pose{}}, plane);
    const Shape ball{ShapeType::sphere, {}, fixed_of(uniform(random, 0.1, 1.0)), {}, {}};
    const Shape pill{
        ShapeType::capsule, {}, fixed_of(uniform(random, 0.1, 0.6)), fixed_of(uniform(random, 0.1, 1.0)), {}};
    // About where the ball's or capsule's surface meets the box's.
    const double reach = (to_double(h.x + h.y + h.z) / 3 + to_double(ball.radius)) * 1.2;
    const Vec3 offset{fixed_of(uniform(random, -reach, reach)), fixed_of(uniform(random, -reach, reach)),
                      fixed_of(uniform(random, -reach, reach))};
    compare({&hull, pose}, {&box, pose}, {&ball, {pose.position + offset, {}}}, sphere);
    compare({&hull, pose}, {&box, pose}, {&pill, {pose.position + offset, random_orientation(random)}}, capsule);
  }
  for (const Agreement* a : {&plane, &sphere, &capsule}) {
    INFO(a->pairs << " pairs, " << a->touching << " touching, " << a->same_normal << " with the same normal, "
                  << a->same_manifold << " with the same points; worst depth difference " << a->worst_depth << " m");
    CHECK(a->touching > 80);
    CHECK(a->same_normal >= a->touching * 97 / 100);
    CHECK(a->worst_depth < 1e-5);
  }
}

TEST_CASE("Hull in motion: a die thrown spinning onto the ground comes to rest on a face", "[hull]") {
  const Shape die = test::die_hull(0.5_fx, 0.4_fx);
  REQUIRE(die.hull->faces.size() == 14);
  for (int throw_number = 0; throw_number < 4; ++throw_number) {
    test::TestWorld t;
    t.add_ground();
    BodyDef def;
    def.pose = {{Fixed{}, 2.0_fx, Fixed{}}, {}};
    def.linear_velocity = {Fixed::from_int(3 - throw_number), 2.0_fx, Fixed::from_int(throw_number - 1)};
    def.angular_velocity = {Fixed::from_int(5 + throw_number), Fixed::from_int(7 - 2 * throw_number), 3.0_fx};
    def.shapes.push_back(die);
    const BodyId id = t.world.create_body(def).value();
    double lowest = 10;
    for (int step = 0; step < 600; ++step) {
      t.world.step();
      lowest = std::min(lowest, to_double(t.world.body(id).pose.position.y));
    }
    const Body& body = t.world.body(id);
    INFO("throw " << throw_number << ": at y " << to_double(body.pose.position.y) << ", lowest " << lowest);
    // At rest: still, on one of the six octagons (its normal straight
    // down within a degree), its centre half a metre up.
    CHECK(to_double(length(body.linear_velocity)) < 0.01);
    CHECK(to_double(length(body.angular_velocity)) < 0.01);
    const Mat33 r = rotation(body.pose.orientation);
    double most_down = 0;
    for (int k = 0; k < 3; ++k) most_down = std::max(most_down, std::abs(to_double(r.column(k).y)));
    CHECK(most_down > std::cos(1.0 * 3.14159265358979 / 180));
    CHECK(std::abs(to_double(body.pose.position.y) - 0.5) < 0.002);
    // Its centre is never nearer the ground than its faces (0.5 m) less 1 cm
    // at the hardest landing: it does not sink in on the way.
    CHECK(lowest > 0.49);
  }
}
