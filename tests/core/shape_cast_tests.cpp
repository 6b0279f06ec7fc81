// Shape casts (core/shape_cast.h, WorldQuery::cast_shape): capsules and boxes
// against every shape kind with analytic answers (faces, edges, a graze
// either side of touching, thin plates, from inside), checked again over
// random pairs against the narrowphase, and the world's tree against a scan.
#include <catch2/catch.hpp>

#include <cmath>
#include <vector>

#include "core/collide.h"
#include "core/query.h"
#include "fixed/splitmix64.h"
#include "tests/core/test_world.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::about_degrees;
using bitstep::test::TestWorld;
using bitstep::test::to_double;

namespace {

const Vec3 x_axis{Fixed::one(), Fixed{}, Fixed{}}, y_axis{Fixed{}, Fixed::one(), Fixed{}},
    z_axis{Fixed{}, Fixed{}, Fixed::one()};

Shape box(Vec3 half) { return {ShapeType::box, half, {}, {}, {}}; }
Shape cube(Fixed half) { return box({half, half, half}); }
Shape capsule(Fixed radius, Fixed half_height) { return {ShapeType::capsule, {}, radius, half_height, {}}; }
Shape sphere(Fixed radius) { return {ShapeType::sphere, {}, radius, {}, {}}; }
Shape plane() { return {ShapeType::plane, {}, {}, {}, {}}; }

// Casts `moving` from `at` along `direction` for `length` against `target`.
std::optional<ShapeEntry> cast(const Shape& moving, Pose at, Vec3 direction, Fixed length, const Shape& target,
                               Pose target_pose = {}) {
  ShapeEntry entry;
  if (!shape_enters({&moving, at}, {at.position, direction, length}, {&target, target_pose}, entry)) return {};
  return entry;
}

double gap(Fixed distance, double expected) { return std::abs(to_double(distance) - expected); }

bool near(Vec3 a, Vec3 b, double tolerance) {
  return std::abs(to_double(a.x - b.x)) <= tolerance && std::abs(to_double(a.y - b.y)) <= tolerance &&
         std::abs(to_double(a.z - b.z)) <= tolerance;
}

// The deepest overlap the narrowphase finds (negative: the gap, when
// within `window`; -window when farther apart).
double deepest(const WorldShape& a, const WorldShape& b, Fixed window) {
  Manifold m;
  const int count = collide(a, b, window, m);
  double depth = -to_double(window);
  for (int i = 0; i < count; ++i) depth = std::max(depth, to_double(m.points[static_cast<size_t>(i)].depth));
  return depth;
}

const double root2 = std::sqrt(2.0);

}  // namespace

TEST_CASE("a box cast lands on a plane and on a box, face first or corner first", "[query][shape_cast]") {
  auto hit = cast(cube(0.5_fx), {{Fixed{}, 3.0_fx, Fixed{}}, {}}, -y_axis, 5.0_fx, plane());
  REQUIRE(hit);
  CHECK(hit->distance == 2.5_fx);
  CHECK(hit->normal == y_axis);
  CHECK(hit->point.y == Fixed{});
  // Turned 45 degrees about z: an edge leads, sqrt(2)/2 below the centre.
  hit = cast(cube(0.5_fx), {{Fixed{}, 3.0_fx, Fixed{}}, about_degrees(z_axis, 45.0_fx)}, -y_axis, 5.0_fx, plane());
  REQUIRE(hit);
  CHECK(gap(hit->distance, 3.0 - root2 / 2) < 1e-8);
  // Face on face: a cube onto a slab whose top is at y = 0.5.
  hit = cast(cube(0.5_fx), {{Fixed{}, 3.0_fx, Fixed{}}, {}}, -y_axis, 5.0_fx, box({2.0_fx, 0.5_fx, 2.0_fx}));
  REQUIRE(hit);
  CHECK(hit->distance == 2.0_fx);
  CHECK(hit->normal == y_axis);
  CHECK(near(hit->point, {Fixed{}, 0.5_fx, Fixed{}}, 1e-6));
  // Edge across edge: a cube turned 45 degrees about z (its leading edge
  // along z at x - sqrt(2)) against one turned about y (its edge along y
  // at x = sqrt(2)). They meet at (sqrt(2), 0, 0) after 6 - 2 sqrt(2).
  hit = cast(cube(Fixed::one()), {{6.0_fx, Fixed{}, Fixed{}}, about_degrees(z_axis, 45.0_fx)}, -x_axis, 6.0_fx,
             cube(Fixed::one()), {{}, about_degrees(y_axis, 45.0_fx)});
  REQUIRE(hit);
  CHECK(gap(hit->distance, 6.0 - 2.0 * root2) < 1e-8);
  CHECK(near(hit->normal, x_axis, 1e-8));
  CHECK(std::abs(to_double(hit->point.x) - root2) < 1e-4);
  CHECK(std::abs(to_double(hit->point.y)) < 1e-4);
  CHECK(std::abs(to_double(hit->point.z)) < 1e-4);
}

TEST_CASE("a capsule cast meets a box's face, a box's edge, a capsule and a sphere", "[query][shape_cast]") {
  const Shape pill = capsule(0.25_fx, 0.5_fx);
  // Upright onto a box's top at y = 1: its lowest point is 0.75 below its centre.
  auto hit = cast(pill, {{Fixed{}, 5.0_fx, Fixed{}}, {}}, -y_axis, 5.0_fx, cube(Fixed::one()));
  REQUIRE(hit);
  CHECK(gap(hit->distance, 3.25) < 1e-8);
  CHECK(hit->normal == y_axis);
  CHECK(near(hit->point, {Fixed{}, Fixed::one(), Fixed{}}, 1e-8));
  // Lying along z, sideways into the vertical edge of a box turned 45
  // degrees about y (the edge at x = sqrt(2)).
  const Quat along_z = about_degrees(x_axis, 90.0_fx);
  const Shape long_pill = capsule(0.25_fx, Fixed::one());
  hit = cast(long_pill, {{5.0_fx, Fixed{}, Fixed{}}, along_z}, -x_axis, 5.0_fx, cube(Fixed::one()),
             {{}, about_degrees(y_axis, 45.0_fx)});
  REQUIRE(hit);
  CHECK(gap(hit->distance, 5.0 - 0.25 - root2) < 1e-7);
  CHECK(near(hit->normal, x_axis, 1e-7));
  CHECK(near(hit->point, {Fixed::from_raw(6074001000), Fixed{}, Fixed{}}, 1e-7));  // sqrt(2) m
  // Across an upright capsule of radius 0.3: the axes cross, 0.55 apart at the touch.
  hit = cast(long_pill, {{5.0_fx, Fixed{}, Fixed{}}, along_z}, -x_axis, 5.0_fx, capsule(0.3_fx, Fixed::one()));
  REQUIRE(hit);
  CHECK(gap(hit->distance, 4.45) < 1e-8);
  CHECK(near(hit->point, {0.3_fx, Fixed{}, Fixed{}}, 1e-8));
  // Lying along x, down onto a ball of radius 1 under its side.
  hit = cast(long_pill, {{0.4_fx, 5.0_fx, Fixed{}}, about_degrees(z_axis, 90.0_fx)}, -y_axis, 5.0_fx,
             sphere(Fixed::one()));
  REQUIRE(hit);
  CHECK(gap(hit->distance, 3.75) < 1e-8);
  CHECK(near(hit->normal, y_axis, 1e-8));
  CHECK(near(hit->point, {Fixed{}, Fixed::one(), Fixed{}}, 1e-8));
  // A box down onto a lying capsule: its bottom face meets the capsule's top.
  hit = cast(cube(0.5_fx), {{Fixed{}, 5.0_fx, Fixed{}}, {}}, -y_axis, 5.0_fx, long_pill,
             {{}, about_degrees(z_axis, 90.0_fx)});
  REQUIRE(hit);
  CHECK(gap(hit->distance, 4.25) < 1e-8);
  CHECK(near(hit->normal, y_axis, 1e-8));
  CHECK(std::abs(to_double(hit->point.y) - 0.25) < 1e-8);
  CHECK(std::abs(to_double(hit->point.x)) <= 0.5);
}

TEST_CASE("a capsule grazing a box's edge: 1 mm clear misses, 1 mm in meets the edge", "[query][shape_cast]") {
  const Shape pill = capsule(0.25_fx, 0.5_fx);
  // Upright, passing the box's vertical edge at (1, z = 1): the side is
  // 1 mm clear of it at z = 1.251.
  CHECK_FALSE(cast(pill, {{5.0_fx, Fixed{}, 1.251_fx}, {}}, -x_axis, 10.0_fx, cube(Fixed::one())));
  // At z = 1.249 the axis meets the edge at 0.25 m when
  // (x - 1)^2 + 0.249^2 = 0.25^2.
  const auto hit = cast(pill, {{5.0_fx, Fixed{}, 1.249_fx}, {}}, -x_axis, 10.0_fx, cube(Fixed::one()));
  REQUIRE(hit);
  const double x = 1.0 + std::sqrt(0.0625 - 0.249 * 0.249);
  CHECK(gap(hit->distance, 5.0 - x) < 2e-6);
  CHECK(near(hit->point, {Fixed::one(), hit->point.y, Fixed::one()}, 1e-8));
  // The same graze for a box: its face 1 mm clear of the box, then 1 mm in.
  CHECK_FALSE(cast(cube(0.25_fx), {{5.0_fx, Fixed{}, 1.251_fx}, {}}, -x_axis, 10.0_fx, cube(Fixed::one())));
  const auto box_hit = cast(cube(0.25_fx), {{5.0_fx, Fixed{}, 1.249_fx}, {}}, -x_axis, 10.0_fx, cube(Fixed::one()));
  REQUIRE(box_hit);
  CHECK(box_hit->distance == 3.75_fx);
  CHECK(box_hit->normal == x_axis);
}

TEST_CASE("casts are swept, not sampled: through a 1 cm plate, and from inside at 0", "[query][shape_cast]") {
  const Shape plate = box({2.0_fx, 0.005_fx, 2.0_fx});
  auto hit = cast(cube(0.5_fx), {{0.3_fx, 5.0_fx, Fixed{}}, about_degrees(y_axis, 30.0_fx)}, -y_axis, 20.0_fx, plate);
  REQUIRE(hit);
  CHECK(gap(hit->distance, 4.495) < 1e-8);
  hit = cast(capsule(0.1_fx, 0.5_fx), {{0.3_fx, 5.0_fx, Fixed{}}, {}}, -y_axis, 20.0_fx, plate);
  REQUIRE(hit);
  CHECK(gap(hit->distance, 4.395) < 1e-8);
  // Overlapping at the start: distance 0, the normal against the path, the
  // point the cast shape's centre; also when moving away.
  for (const Vec3 direction : {x_axis, -x_axis}) {
    for (const Shape& moving : {cube(0.5_fx), capsule(0.25_fx, 0.5_fx)}) {
      hit = cast(moving, {{1.2_fx, Fixed{}, Fixed{}}, {}}, direction, 3.0_fx, cube(Fixed::one()));
      REQUIRE(hit);
      CHECK(hit->distance == Fixed{});
      CHECK(hit->normal == -direction);
      CHECK(hit->point == Vec3{1.2_fx, Fixed{}, Fixed{}});
    }
  }
  // Short of it, and moving away from it: nothing.
  for (const Shape& moving : {cube(0.5_fx), capsule(0.25_fx, 0.5_fx)}) {
    CHECK_FALSE(cast(moving, {{Fixed{}, 3.0_fx, Fixed{}}, {}}, -y_axis, 1.2_fx, cube(Fixed::one())));
    CHECK_FALSE(cast(moving, {{Fixed{}, 3.0_fx, Fixed{}}, {}}, y_axis, 10.0_fx, cube(Fixed::one())));
    CHECK_FALSE(cast(moving, {{Fixed{}, 3.0_fx, Fixed{}}, {}}, y_axis, 10.0_fx, sphere(Fixed::one())));
    CHECK_FALSE(cast(moving, {{Fixed{}, 3.0_fx, Fixed{}}, {}}, y_axis, 10.0_fx, plane()));
  }
}

TEST_CASE("over random pairs a cast stops where the narrowphase first finds them touching", "[query][shape_cast]") {
  SplitMix64 rng{17};
  auto unit = [&] { return Fixed::from_raw(static_cast<int64_t>(rng.next() % (uint64_t{1} << 32))); };  // [0, 1)
  auto signed_unit = [&] { return unit() * Fixed::from_int(2) - Fixed::one(); };
  auto orientation = [&] {
    const Vec3 axis = normalize_or({signed_unit(), signed_unit(), signed_unit()}, y_axis);
    return about_degrees(axis, unit() * Fixed::from_int(180));
  };
  auto shape_of = [&](int kind) {
    const Fixed size = 0.2_fx + unit();
    switch (kind) {
      case 0: return box({size, size * 0.5_fx + 0.1_fx, 0.3_fx + unit()});
      case 1: return capsule(size * 0.5_fx, 0.1_fx + unit());
      default: return sphere(size);
    }
  };
  int hits = 0, misses = 0;
  for (int pair = 0; pair < 400; ++pair) {
    const Shape moving = shape_of(pair % 2);
    const Shape target = shape_of((pair / 2) % 3);
    const Pose target_pose{{}, orientation()};
    const Pose start{{signed_unit() * Fixed::from_int(4), signed_unit() * Fixed::from_int(4), 4.0_fx}, orientation()};
    // Aimed near the target, past it by up to 1.5 m either side.
    const Vec3 aim{signed_unit() * 1.5_fx, signed_unit() * 1.5_fx, Fixed{}};
    const Vec3 direction = normalize(aim - start.position);
    const Fixed length = 10.0_fx;
    const WorldShape placed_target{&target, target_pose};
    const auto at = [&](Fixed travelled) {
      return WorldShape{&moving, {start.position + direction * travelled, start.orientation}};
    };
    if (deepest(at(Fixed{}), placed_target, Fixed{}) > 0) continue;  // starts inside
    const auto hit = cast(moving, start, direction, length, target, target_pose);
    if (!hit) {
      ++misses;
      for (int k = 0; k <= 400; ++k) {
        INFO("pair " << pair << " sample " << k);
        CHECK(deepest(at(length * Fixed::from_int(k) / Fixed::from_int(400)), placed_target, Fixed{}) <= 1e-9);
      }
      continue;
    }
    ++hits;
    INFO("pair " << pair << " distance " << to_double(hit->distance));
    REQUIRE(hit->distance > Fixed{});
    // Touching there (within the advance's 1 um)...
    const double touch = deepest(at(hit->distance), placed_target, 0.01_fx);
    CHECK(touch > -2e-6);
    CHECK(touch < 1e-7);
    // ... and apart everywhere before it.
    for (int k = 0; k < 100; ++k) {
      CHECK(deepest(at(hit->distance * Fixed::from_int(k) / Fixed::from_int(100)), placed_target, Fixed{}) <= 1e-9);
    }
    // The point lies on the target's surface, the normal is unit.
    CHECK(std::abs(to_double(length_sq(hit->normal)) - 1.0) < 1e-6);
  }
  CHECK(hits > 100);
  CHECK(misses > 50);
}

TEST_CASE("the world's shape casts: nearest first, every shape kind, filters, the tree as a scan", "[query][shape_cast]") {
  TestWorld t;
  const BodyId ground = t.add_ground();
  const BodyId crate = t.add_box({-3.0_fx, 0.5_fx, Fixed{}}, {0.5_fx, 0.5_fx, 0.5_fx});
  const BodyId ball = t.add_sphere({-6.0_fx, 0.5_fx, Fixed{}}, 0.5_fx);
  const BodyId post = t.add_capsule({{-9.0_fx, Fixed::one(), Fixed{}}, {}}, 0.3_fx, 0.7_fx);
  // A table: a top and a leg, one body; the cast meets the leg (shape 1).
  BodyDef table;
  table.pose.position = {-12.0_fx, 0.5_fx, Fixed{}};
  table.shapes.push_back({ShapeType::box, {1.0_fx, 0.05_fx, 1.0_fx}, {}, {}, {{Fixed{}, 0.45_fx, Fixed{}}, {}}});
  table.shapes.push_back({ShapeType::box, {0.05_fx, 0.45_fx, 0.05_fx}, {}, {}, {}});
  const BodyId table_id = t.world.create_body(table).value();
  const WorldQuery query(t.world);
  // A capsule lying along z, 0.6 m up, swept along -x: it clears the ground.
  const Shape pill = capsule(0.2_fx, 0.5_fx);
  const Pose start{{Fixed{}, 0.6_fx, Fixed{}}, about_degrees(x_axis, 90.0_fx)};
  const Vec3 translation{-20.0_fx, Fixed{}, Fixed{}};
  std::vector<QueryHit> hits;
  query.cast_shape_all(pill, start, translation, hits);
  REQUIRE(hits.size() == 4u);
  CHECK(hits[0].body == crate);
  CHECK(gap(hits[0].fraction * 20.0_fx, 3.0 - 0.5 - 0.2) < 1e-8);
  CHECK(hits[1].body == ball);
  CHECK(gap(hits[1].fraction * 20.0_fx, 6.0 - std::sqrt(0.7 * 0.7 - 0.1 * 0.1)) < 1e-7);  // the axis 0.1 m above the ball's centre
  CHECK(hits[2].body == post);
  CHECK(gap(hits[2].fraction * 20.0_fx, 9.0 - 0.5) < 1e-8);
  CHECK(hits[3].body == table_id);
  CHECK(hits[3].shape == 1u);
  CHECK(gap(hits[3].fraction * 20.0_fx, 12.0 - 0.05 - 0.2) < 1e-8);
  const auto nearest = query.cast_shape(pill, start, translation);
  REQUIRE(nearest);
  CHECK(nearest->body == crate);
  CHECK(nearest->fraction == hits[0].fraction);
  // Filters: the crate ignored, the next is the ball; lower, the ground.
  QueryFilter skip_crate;
  skip_crate.ignore = crate;
  CHECK(query.cast_shape(pill, start, translation, skip_crate)->body == ball);
  const auto low = query.cast_shape(pill, {{Fixed{}, 0.1_fx, Fixed{}}, start.orientation}, translation);
  REQUIRE(low);
  CHECK(low->body == ground);
  CHECK(low->fraction == Fixed{});
  // A sphere cast through cast_shape is cast_sphere.
  const Shape ball_shape = sphere(0.3_fx);
  const auto as_shape = query.cast_shape(ball_shape, {{Fixed{}, 0.6_fx, 0.2_fx}, {}}, translation);
  const auto as_sphere = query.cast_sphere(0.3_fx, {Fixed{}, 0.6_fx, 0.2_fx}, translation);
  REQUIRE(as_shape);
  REQUIRE(as_sphere);
  CHECK(as_shape->body == as_sphere->body);
  CHECK(as_shape->fraction == as_sphere->fraction);
  CHECK(as_shape->point == as_sphere->point);
  CHECK(as_shape->normal == as_sphere->normal);
}

TEST_CASE("the tree finds the nearest a scan of every shape finds, for box and capsule casts", "[query][shape_cast]") {
  TestWorld t;
  SplitMix64 rng{99};
  auto coordinate = [&](int64_t span) {
    return Fixed::from_raw(static_cast<int64_t>(rng.next() % static_cast<uint64_t>(span << 32)) - (span << 31));
  };
  for (int i = 0; i < 2000; ++i) {
    const Vec3 at{coordinate(100), coordinate(20), coordinate(100)};
    const Fixed size = 0.2_fx + Fixed::from_raw(static_cast<int64_t>(rng.next() % (uint64_t{1} << 32)));
    switch (i % 3) {
      case 0: t.add_box(at, {size, size * 0.5_fx, size}); break;
      case 1: t.add_sphere(at, size); break;
      default: t.add_capsule({at, about_degrees(x_axis, Fixed::from_int(i % 90))}, size * 0.5_fx, size);
    }
  }
  const WorldQuery query(t.world);
  const Shape shapes[] = {cube(0.4_fx), capsule(0.3_fx, 0.6_fx)};
  int met = 0;
  for (int r = 0; r < 100; ++r) {
    const Shape& moving = shapes[r % 2];
    const Pose start{{coordinate(120), coordinate(30), coordinate(120)}, about_degrees(y_axis, Fixed::from_int(r))};
    const Vec3 translation{coordinate(150), coordinate(30), coordinate(150)};
    const Ray path{start.position, normalize(translation), length(translation)};
    std::optional<ShapeEntry> scanned;
    uint32_t scanned_slot = 0;
    for (uint32_t slot = 0; slot < t.world.bodies().size(); ++slot) {
      const Body& body = t.world.bodies()[slot];
      ShapeEntry entry;
      if (!shape_enters({&moving, start}, path, {&body.shapes[0], compose(body.pose, body.shapes[0].local)}, entry)) {
        continue;
      }
      if (!scanned || entry.distance < scanned->distance) {
        scanned = entry;
        scanned_slot = slot;
      }
    }
    const auto hit = query.cast_shape(moving, start, translation);
    REQUIRE(hit.has_value() == scanned.has_value());
    if (!hit) continue;
    ++met;
    CHECK(hit->body.index == scanned_slot);
    CHECK(hit->point == scanned->point);
  }
  CHECK(met > 30);
}
