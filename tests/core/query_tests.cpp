// The world's queries (core/query.h, core/ray_cast.h): rays and sphere casts
// against every shape kind with analytic answers (edges, grazes, along a
// capsule's axis, from inside), the order of answers, the tree against a
// brute-force scan over 10,000 bodies, and the overlap queries.
#include <catch2/catch.hpp>

#include <algorithm>
#include <vector>

#include "core/query.h"
#include "fixed/splitmix64.h"
#include "tests/core/test_world.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::about_degrees;
using bitstep::test::TestWorld;
using bitstep::test::to_double;

namespace {

const Vec3 x_axis{Fixed::one(), Fixed{}, Fixed{}}, y_axis{Fixed{}, Fixed::one(), Fixed{}};

bool near(Vec3 a, Vec3 b, double tolerance) {
  return std::abs(to_double(a.x - b.x)) <= tolerance && std::abs(to_double(a.y - b.y)) <= tolerance &&
         std::abs(to_double(a.z - b.z)) <= tolerance;
}

// A static plane through the origin facing +y.
BodyId add_plane(TestWorld& t) {
  BodyDef def;
  def.type = BodyType::static_body;
  def.shapes.push_back({ShapeType::plane, {}, {}, {}, {}});
  return t.world.create_body(def).value();
}

}  // namespace

TEST_CASE("a ray meets a box at its face, along a face's plane, at an edge, and from inside at 0", "[query]") {
  TestWorld t;
  const BodyId box = t.add_box(Vec3{}, {Fixed::one(), Fixed::one(), Fixed::one()});
  const WorldQuery query(t.world);
  // Straight at the -x face: 4 m of 10.
  auto hit = query.cast_ray({-5.0_fx, 0.5_fx, Fixed{}}, {10.0_fx, Fixed{}, Fixed{}});
  REQUIRE(hit);
  CHECK(hit->body == box);
  CHECK(hit->shape == 0u);
  CHECK(hit->fraction == 0.4_fx);
  CHECK(hit->point == Vec3{-1.0_fx, 0.5_fx, Fixed{}});
  CHECK(hit->normal == -x_axis);
  // Along the plane of the top face (y = 1): the box is closed, so it meets the -x face's top edge.
  hit = query.cast_ray({-5.0_fx, Fixed::one(), Fixed{}}, {10.0_fx, Fixed{}, Fixed{}});
  REQUIRE(hit);
  CHECK(hit->point == Vec3{-Fixed::one(), Fixed::one(), Fixed{}});
  // A hair above it: nothing.
  CHECK_FALSE(query.cast_ray({-5.0_fx, Fixed::one() + Fixed::ulp(), Fixed{}}, {10.0_fx, Fixed{}, Fixed{}}));
  // Diagonally onto the edge x = -1, y = 1: both faces enter at once; the
  // lower axis's face (-x) is reported.
  hit = query.cast_ray({-5.0_fx, 5.0_fx, Fixed{}}, {8.0_fx, -8.0_fx, Fixed{}});
  REQUIRE(hit);
  CHECK(near(hit->point, {-Fixed::one(), Fixed::one(), Fixed{}}, 1e-8));
  CHECK(std::abs(to_double(hit->fraction) - 0.5) < 1e-8);
  CHECK(hit->normal == -x_axis);
  // From inside: fraction 0, the normal against the ray.
  hit = query.cast_ray({0.25_fx, Fixed{}, Fixed{}}, {Fixed{}, 3.0_fx, Fixed{}});
  REQUIRE(hit);
  CHECK(hit->fraction == Fixed{});
  CHECK(hit->point == Vec3{0.25_fx, Fixed{}, Fixed{}});
  CHECK(hit->normal == -y_axis);
  // Short of it, and pointing away: nothing.
  CHECK_FALSE(query.cast_ray({-5.0_fx, Fixed{}, Fixed{}}, {3.9_fx, Fixed{}, Fixed{}}));
  CHECK_FALSE(query.cast_ray({-5.0_fx, Fixed{}, Fixed{}}, {-10.0_fx, Fixed{}, Fixed{}}));
}

TEST_CASE("a ray meets a turned box where the rotated face is", "[query]") {
  TestWorld t;
  // Turned 45 degrees about z: its corner points along -x at x = -sqrt(2).
  BodyDef def;
  def.pose.orientation = about_degrees({Fixed{}, Fixed{}, Fixed::one()}, 45.0_fx);
  def.shapes.push_back({ShapeType::box, {Fixed::one(), Fixed::one(), Fixed::one()}, {}, {}, {}});
  t.world.create_body(def);
  const WorldQuery query(t.world);
  // At y = 0.5 the ray meets the face from that corner to (0, sqrt2), the
  // local +y face: y = x + sqrt2, so x = 0.5 - sqrt2, normal (-1, 1) / sqrt2.
  const auto hit = query.cast_ray({-5.0_fx, 0.5_fx, Fixed{}}, {10.0_fx, Fixed{}, Fixed{}});
  REQUIRE(hit);
  CHECK(std::abs(to_double(hit->point.x) - (0.5 - std::sqrt(2.0))) < 1e-7);
  CHECK(std::abs(to_double(hit->normal.x) + std::sqrt(0.5)) < 1e-7);
  CHECK(std::abs(to_double(hit->normal.y) - std::sqrt(0.5)) < 1e-7);
}

TEST_CASE("a ray grazing a sphere touches it, one a micron off misses", "[query]") {
  TestWorld t;
  t.add_sphere(Vec3{}, Fixed::one());
  const WorldQuery query(t.world);
  const auto hit = query.cast_ray({-5.0_fx, Fixed::one(), Fixed{}}, {10.0_fx, Fixed{}, Fixed{}});
  REQUIRE(hit);
  CHECK(near(hit->point, {Fixed{}, Fixed::one(), Fixed{}}, 1e-9));
  CHECK(near(hit->normal, y_axis, 1e-9));
  CHECK_FALSE(query.cast_ray({-5.0_fx, 1.000001_fx, Fixed{}}, {10.0_fx, Fixed{}, Fixed{}}));
  // Through the centre: the near pole, 4 m along.
  const auto through = query.cast_ray({-5.0_fx, Fixed{}, Fixed{}}, {10.0_fx, Fixed{}, Fixed{}});
  REQUIRE(through);
  CHECK(through->fraction == 0.4_fx);
  CHECK(through->normal == -x_axis);
  // From 10 km away: still exact to a micron.
  const auto far = query.cast_ray({-10000.0_fx, 0.6_fx, Fixed{}}, {20000.0_fx, Fixed{}, Fixed{}});
  REQUIRE(far);
  CHECK(std::abs(to_double(far->point.x) + 0.8) < 1e-6);
}

TEST_CASE("a ray along a capsule's axis meets its cap, across it its side, from inside it at 0", "[query]") {
  TestWorld t;
  t.add_capsule({}, 0.5_fx, Fixed::one());  // along y: the segment y -1..1, radius 0.5
  const WorldQuery query(t.world);
  auto hit = query.cast_ray({Fixed{}, 5.0_fx, Fixed{}}, {Fixed{}, -10.0_fx, Fixed{}});
  REQUIRE(hit);
  CHECK(hit->point == Vec3{Fixed{}, 1.5_fx, Fixed{}});
  CHECK(hit->normal == y_axis);
  CHECK(hit->fraction == 0.35_fx);
  // Parallel to the axis, 0.3 off it: the cap's sphere at y = 1 + sqrt(0.25 - 0.09) = 1.4.
  hit = query.cast_ray({0.3_fx, 5.0_fx, Fixed{}}, {Fixed{}, -10.0_fx, Fixed{}});
  REQUIRE(hit);
  CHECK(std::abs(to_double(hit->point.y) - 1.4) < 1e-9);
  // Across the side at y = 0.7: x = -0.5, normal -x.
  hit = query.cast_ray({-5.0_fx, 0.7_fx, Fixed{}}, {10.0_fx, Fixed{}, Fixed{}});
  REQUIRE(hit);
  CHECK(near(hit->point, {-0.5_fx, 0.7_fx, Fixed{}}, 1e-9));
  CHECK(near(hit->normal, -x_axis, 1e-9));
  // Across at y = 1.2, above the segment: the cap, x = -sqrt(0.25 - 0.04).
  hit = query.cast_ray({-5.0_fx, 1.2_fx, Fixed{}}, {10.0_fx, Fixed{}, Fixed{}});
  REQUIRE(hit);
  CHECK(std::abs(to_double(hit->point.x) + std::sqrt(0.21)) < 1e-8);
  // Inside, along the axis.
  hit = query.cast_ray({Fixed{}, 0.5_fx, Fixed{}}, {Fixed{}, 3.0_fx, Fixed{}});
  REQUIRE(hit);
  CHECK(hit->fraction == Fixed{});
  CHECK(hit->normal == -y_axis);
}

TEST_CASE("a plane is the solid half-space below it", "[query]") {
  TestWorld t;
  add_plane(t);
  const WorldQuery query(t.world);
  auto hit = query.cast_ray({Fixed::one(), 2.0_fx, Fixed{}}, {Fixed{}, -5.0_fx, Fixed{}});
  REQUIRE(hit);
  CHECK(hit->fraction == 0.4_fx);
  CHECK(hit->normal == y_axis);
  CHECK_FALSE(query.cast_ray({Fixed{}, 2.0_fx, Fixed{}}, {5.0_fx, Fixed{}, Fixed{}}));  // parallel above
  CHECK_FALSE(query.cast_ray({Fixed{}, 2.0_fx, Fixed{}}, {Fixed{}, 1.0_fx, Fixed{}}));  // away
  hit = query.cast_ray({Fixed{}, -2.0_fx, Fixed{}}, {Fixed{}, 5.0_fx, Fixed{}});       // from below: inside
  REQUIRE(hit);
  CHECK(hit->fraction == Fixed{});
}

TEST_CASE("every hit comes nearest first, then by body slot and shape index", "[query]") {
  TestWorld t;
  const BodyId far_box = t.add_box({6.0_fx, Fixed{}, Fixed{}}, {0.5_fx, 0.5_fx, 0.5_fx});
  const BodyId near_sphere = t.add_sphere({2.0_fx, Fixed{}, Fixed{}}, 0.5_fx);
  // A compound of two boxes; the ray meets its second shape first.
  BodyDef compound;
  compound.shapes.push_back({ShapeType::box, {0.5_fx, 0.5_fx, 0.5_fx}, {}, {}, {{8.0_fx, Fixed{}, Fixed{}}, {}}});
  compound.shapes.push_back({ShapeType::box, {0.5_fx, 0.5_fx, 0.5_fx}, {}, {}, {{4.0_fx, Fixed{}, Fixed{}}, {}}});
  const BodyId pair = t.world.create_body(compound).value();
  // Two spheres met at the same distance: by slot.
  const BodyId twin_a = t.add_sphere({10.0_fx, 0.0_fx, Fixed{}}, 0.5_fx);
  const BodyId twin_b = t.add_sphere({10.0_fx, 0.0_fx, Fixed{}}, 0.5_fx);
  const WorldQuery query(t.world);
  std::vector<QueryHit> hits;
  query.cast_ray_all({Fixed{}, Fixed{}, Fixed{}}, {20.0_fx, Fixed{}, Fixed{}}, hits);
  REQUIRE(hits.size() == 6u);
  CHECK(hits[0].body == near_sphere);
  CHECK((hits[1].body == pair && hits[1].shape == 1u));
  CHECK(hits[2].body == far_box);
  CHECK((hits[3].body == pair && hits[3].shape == 0u));
  CHECK(hits[4].body == twin_a);
  CHECK(hits[5].body == twin_b);
  for (size_t i = 1; i < hits.size(); ++i) CHECK(hits[i - 1].fraction <= hits[i].fraction);
  const auto nearest = query.cast_ray({Fixed{}, Fixed{}, Fixed{}}, {20.0_fx, Fixed{}, Fixed{}});
  REQUIRE(nearest);
  CHECK(nearest->body == near_sphere);
  CHECK(nearest->fraction == hits[0].fraction);
  // From beyond the compound, backwards: the twins first, the lower slot.
  const auto back = query.cast_ray({9.0_fx, Fixed{}, Fixed{}}, {Fixed{}, Fixed{}, Fixed{}});
  CHECK_FALSE(back);  // a zero translation meets nothing
  const auto twins = query.cast_ray({12.0_fx, Fixed{}, Fixed{}}, {-4.0_fx, Fixed{}, Fixed{}});
  REQUIRE(twins);
  CHECK(twins->body == twin_a);
}

TEST_CASE("a sphere cast touches a box's face, its rounded edge, a sphere and a plane", "[query]") {
  TestWorld t;
  t.add_box(Vec3{}, {Fixed::one(), Fixed::one(), Fixed::one()});
  const WorldQuery query(t.world);
  // Head on: the centre stops 0.5 m short of the face.
  auto hit = query.cast_sphere(0.5_fx, {-5.0_fx, Fixed{}, Fixed{}}, {10.0_fx, Fixed{}, Fixed{}});
  REQUIRE(hit);
  CHECK(hit->fraction == 0.35_fx);
  CHECK(hit->point == Vec3{-Fixed::one(), Fixed{}, Fixed{}});
  CHECK(hit->normal == -x_axis);
  // 0.3 m above the top face: it meets the edge (-1, 1) when its centre is
  // 0.5 m from it, at x = -1.4; the normal (-0.8, 0.6).
  hit = query.cast_sphere(0.5_fx, {-5.0_fx, 1.3_fx, Fixed{}}, {10.0_fx, Fixed{}, Fixed{}});
  REQUIRE(hit);
  CHECK(std::abs(to_double(hit->fraction) - 0.36) < 1e-8);
  CHECK(near(hit->normal, {-0.8_fx, 0.6_fx, Fixed{}}, 1e-8));
  CHECK(near(hit->point, {-Fixed::one(), Fixed::one(), Fixed{}}, 1e-8));
  // 0.6 m above: it passes.
  CHECK_FALSE(query.cast_sphere(0.5_fx, {-5.0_fx, 1.6_fx, Fixed{}}, {10.0_fx, Fixed{}, Fixed{}}));
  TestWorld u;
  u.add_sphere({Fixed{}, 3.0_fx, Fixed{}}, Fixed::one());
  add_plane(u);
  const WorldQuery other(u.world);
  // Falling onto the plane past the sphere's side, and onto the sphere.
  hit = other.cast_sphere(0.5_fx, {5.0_fx, 10.0_fx, Fixed{}}, {Fixed{}, -20.0_fx, Fixed{}});
  REQUIRE(hit);
  CHECK(hit->fraction == 0.475_fx);  // the centre stops at y = 0.5
  CHECK(hit->point == Vec3{5.0_fx, Fixed{}, Fixed{}});
  hit = other.cast_sphere(0.5_fx, {Fixed{}, 10.0_fx, Fixed{}}, {Fixed{}, -20.0_fx, Fixed{}});
  REQUIRE(hit);
  CHECK(hit->point == Vec3{Fixed{}, 4.0_fx, Fixed{}});
  CHECK(hit->fraction == 0.275_fx);
}

TEST_CASE("the tree answers as a scan of every shape would, over 10,000 bodies", "[query]") {
  TestWorld t;
  SplitMix64 rng{2026};
  auto coordinate = [&](int64_t span) {
    return Fixed::from_raw(static_cast<int64_t>(rng.next() % static_cast<uint64_t>(span << 32)) - (span << 31));
  };
  for (int i = 0; i < 10000; ++i) {
    const Vec3 at{coordinate(200), coordinate(40), coordinate(200)};
    const Fixed size = 0.2_fx + Fixed::from_raw(static_cast<int64_t>(rng.next() % (uint64_t{1} << 32)));
    switch (i % 3) {
      case 0: t.add_box(at, {size, size * 0.5_fx, size}); break;
      case 1: t.add_sphere(at, size); break;
      default: t.add_capsule({at, about_degrees({Fixed::one(), Fixed{}, Fixed{}}, Fixed::from_int(i % 90))}, size * 0.5_fx, size);
    }
  }
  const WorldQuery query(t.world);
  std::vector<QueryHit> hits;
  int met = 0;
  for (int r = 0; r < 200; ++r) {
    const Vec3 origin{coordinate(240), coordinate(60), coordinate(240)};
    const Vec3 translation{coordinate(300), coordinate(60), coordinate(300)};
    // The scan: every live shape, by slot.
    std::optional<QueryHit> scanned;
    const Fixed length = bitstep::length(translation);
    const Ray ray{origin, normalize(translation), length};
    for (uint32_t slot = 0; slot < t.world.bodies().size(); ++slot) {
      const Body& body = t.world.bodies()[slot];
      RayEntry entry;
      if (!ray_enters({&body.shapes[0], compose(body.pose, body.shapes[0].local)}, ray, Fixed{}, entry)) continue;
      if (!scanned || entry.distance / length < scanned->fraction) {
        scanned = QueryHit{{slot, body.generation}, 0, entry.distance / length, {}, entry.normal};
      }
    }
    const auto hit = query.cast_ray(origin, translation);
    REQUIRE(hit.has_value() == scanned.has_value());
    query.cast_ray_all(origin, translation, hits);
    if (!hit) {
      CHECK(hits.empty());
      continue;
    }
    ++met;
    CHECK(hit->body == scanned->body);
    CHECK(hit->fraction == scanned->fraction);
    CHECK(hit->normal == scanned->normal);
    REQUIRE_FALSE(hits.empty());
    CHECK(hits[0].body == hit->body);
  }
  CHECK(met > 50);  // the rays do meet things
}

TEST_CASE("overlap queries: bodies by their bounds, shapes by the exact test", "[query]") {
  TestWorld t;
  const BodyId ground = t.add_ground();
  const BodyId a = t.add_box({Fixed{}, 0.5_fx, Fixed{}}, {0.5_fx, 0.5_fx, 0.5_fx});
  const BodyId b = t.add_sphere({3.0_fx, 0.5_fx, Fixed{}}, 0.5_fx);
  const BodyId c = t.add_box({6.0_fx, 0.5_fx, Fixed{}}, {0.5_fx, 0.5_fx, 0.5_fx});
  const WorldQuery query(t.world);
  std::vector<BodyId> bodies;
  query.overlap_box({{-1.0_fx, 0.2_fx, -1.0_fx}, {3.0_fx, 2.0_fx, 1.0_fx}}, bodies);
  CHECK(bodies == std::vector<BodyId>{a, b});
  query.overlap_box({{-1.0_fx, -0.5_fx, -1.0_fx}, {3.0_fx, 2.0_fx, 1.0_fx}}, bodies);
  CHECK(bodies == std::vector<BodyId>{ground, a, b});
  // A sphere between a and b: overlapping a and the ground by 0.1 m, clear of b.
  Shape probe;
  probe.type = ShapeType::sphere;
  probe.radius = 0.6_fx;
  std::vector<ShapeOverlap> overlaps;
  query.overlap_shape(probe, {{1.0_fx, 0.5_fx, Fixed{}}, {}}, overlaps);
  REQUIRE(overlaps.size() == 2u);
  CHECK(overlaps[0].body == ground);
  CHECK(overlaps[1].body == a);
  CHECK(std::abs(to_double(overlaps[0].depth) - 0.1) < 1e-9);
  CHECK(std::abs(to_double(overlaps[1].depth) - 0.1) < 1e-9);
  // Exactly touching c (and above the ground): not an overlap.
  probe.radius = 0.5_fx;
  query.overlap_shape(probe, {{7.0_fx, 0.6_fx, Fixed{}}, {}}, overlaps);
  CHECK(overlaps.empty());
  // A thin slab through the bottoms of everything and the ground's top.
  Shape slab;
  slab.type = ShapeType::box;
  slab.half_extents = {10.0_fx, 0.05_fx, 10.0_fx};
  query.overlap_shape(slab, {{Fixed{}, 0.02_fx, Fixed{}}, {}}, overlaps);
  REQUIRE(overlaps.size() == 4u);
  CHECK(overlaps[0].body == ground);
  CHECK(overlaps[1].body == a);
  CHECK(overlaps[2].body == b);
  CHECK(overlaps[3].body == c);
  CHECK(std::abs(to_double(overlaps[0].depth) - 0.03) < 1e-9);
}

// The example of docs/queries.md, on a world with a ground box.
TEST_CASE("the query example of docs/queries.md runs and answers", "[query]") {
  TestWorld t;
  t.add_ground();
  t.add_box({Fixed{}, 0.5_fx, 3.0_fx}, {0.5_fx, 0.5_fx, 0.5_fx});
  const bitstep::World& world = t.world;
  const bitstep::WorldQuery query(world);  // a snapshot: build one after each step
  using namespace bitstep::literals;
  bool met = false;
  if (const auto hit = query.cast_ray({0.0_fx, 5.0_fx, 0.0_fx}, {0.0_fx, -10.0_fx, 0.0_fx})) {
    met = true;
    CHECK(hit->fraction == 0.5_fx);  // the ground's top at y = 0
    CHECK(hit->normal == y_axis);
  }
  CHECK(met);
  std::vector<bitstep::QueryHit> hits;
  query.cast_sphere_all(0.5_fx, {0.0_fx, 5.0_fx, 0.0_fx}, {10.0_fx, 0.0_fx, 0.0_fx}, hits);
  CHECK(hits.empty());
  std::vector<bitstep::BodyId> near;
  query.overlap_box({{-1.0_fx, 0.0_fx, -1.0_fx}, {1.0_fx, 2.0_fx, 1.0_fx}}, near);
  CHECK(near.size() == 1u);  // the ground (the box is at z = 3)
}

TEST_CASE("a query sees only the layers it asks for, and not the body it ignores", "[query][filter]") {
  TestWorld t;
  const BodyId near_box = t.add_box({2.0_fx, Fixed{}, Fixed{}}, {0.5_fx, 0.5_fx, 0.5_fx});
  BodyDef def;
  def.pose.position = {4.0_fx, Fixed{}, Fixed{}};
  def.shapes.push_back({ShapeType::sphere, {}, 0.5_fx, {}, {}});
  def.filter.layers = 0b100;  // layer 2
  const BodyId sphere = t.world.create_body(def).value();
  const WorldQuery query(t.world);
  const Vec3 origin{}, along{10.0_fx, Fixed{}, Fixed{}};
  CHECK(query.cast_ray(origin, along)->body == near_box);
  CHECK(query.cast_ray(origin, along, {0b100, {}})->body == sphere);   // layer 2 only
  CHECK(query.cast_ray(origin, along, {UINT32_MAX, near_box})->body == sphere);  // ignoring the box
  CHECK_FALSE(query.cast_ray(origin, along, {0b1000, {}}));           // layer 3: nobody
  std::vector<BodyId> bodies;
  query.overlap_box({{Fixed{}, -Fixed::one(), -Fixed::one()}, {5.0_fx, Fixed::one(), Fixed::one()}}, bodies, {0b1, {}});
  CHECK(bodies == std::vector<BodyId>{near_box});
}
