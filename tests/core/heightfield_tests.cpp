// Heightfields (core/height_grid.h): the grid's triangles and refusals,
// and bodies in motion on real height grids (a slope made of heights, not
// a tilted flat mesh; bumps; a hole) against the analytic answers.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "core/height_grid.h"
#include "core/query.h"
#include "tests/core/test_world.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::TestWorld;
using bitstep::test::to_double;

namespace {

// columns x rows samples `spacing` m apart, heights from height(i, j).
template <class Height>
HeightGrid grid_of(uint32_t columns, uint32_t rows, Fixed spacing, Height&& height) {
  HeightGrid g;
  g.columns = columns;
  g.rows = rows;
  g.spacing_x = g.spacing_z = spacing;
  for (uint32_t j = 0; j < rows; ++j) {
    for (uint32_t i = 0; i < columns; ++i) g.heights.push_back(height(i, j));
  }
  return g;
}

BodyId add_heightfield(TestWorld& t, HeightGrid grid, Vec3 at, Material material = {}) {
  BodyDef def;
  def.type = BodyType::static_body;
  def.pose.position = at;
  Shape shape;
  shape.type = ShapeType::heightfield;
  shape.mesh = build_height_grid_mesh(std::move(grid)).value();
  def.shapes.push_back(shape);
  def.material = material;
  return t.world.create_body(def).value();
}

Material sliding(Fixed mu) { return {mu, mu, Fixed{}, Fixed{}}; }

// A 0.5 m box (mu 0.2) turned with a slope (`tilt`, its normal `up`), 1 mm
// above the surface point `surface`.
BodyId add_slope_box(TestWorld& t, Vec3 surface, Quat tilt, Vec3 up) {
  BodyDef def;
  def.pose = {surface + up * 0.251_fx, tilt};
  def.shapes.push_back({ShapeType::box, {0.25_fx, 0.25_fx, 0.25_fx}, {}, {}, {}});
  def.material = sliding(0.2_fx);
  return t.world.create_body(def).value();
}

std::string refusal(HeightGrid g) {
  const auto built = build_height_grid_mesh(std::move(g));
  return built.ok() ? "built" : built.error().place + ": " + built.error().reason;
}

}  // namespace

TEST_CASE("Heightfield: a grid gives two triangles a cell, up, with no active edge where it is flat", "[heightfield]") {
  const auto flat = [](uint32_t, uint32_t) { return Fixed{}; };
  HeightGrid g = grid_of(5, 4, 0.5_fx, flat);
  g.holes = {5};  // cell (1, 1)
  const auto mesh = build_height_grid_mesh(g).value();
  CHECK(mesh->triangles.size() == 2 * (4 * 3 - 1));
  CHECK(mesh->vertices.size() == 20);
  CHECK(mesh->vertices[7] == Vec3{1.0_fx, Fixed{}, 0.5_fx});  // column 2, row 1
  REQUIRE(mesh->source_grid != nullptr);
  CHECK(*mesh->source_grid == g);
  int inner_active = 0, border_active = 0;
  for (const TriangleMesh::Triangle& t : mesh->triangles) {
    CHECK(t.normal == Vec3{Fixed{}, Fixed::one(), Fixed{}});
    for (int k = 0; k < 3; ++k) {
      if ((t.active_edges >> k & 1) == 0) continue;
      const Vec3 a = mesh->vertices[t.corners[static_cast<size_t>(k)]];
      const Vec3 b = mesh->vertices[t.corners[static_cast<size_t>((k + 1) % 3)]];
      const bool outer =
          (a.x == b.x && (a.x == Fixed{} || a.x == 2.0_fx)) || (a.z == b.z && (a.z == Fixed{} || a.z == 1.5_fx));
      ++(outer ? border_active : inner_active);
    }
  }
  // Active: the 2 (4 + 3) outer edges and the hole's 4 borders; no diagonal, no inner edge.
  CHECK(border_active == 14);
  CHECK(inner_active == 4);
}

TEST_CASE("Heightfield: refusals name the field and the reason", "[heightfield]") {
  const auto flat = [](uint32_t, uint32_t) { return Fixed{}; };
  CHECK(refusal(grid_of(1, 4, Fixed::one(), flat)) == "columns: 1, a grid has 2 to 4097");
  CHECK(refusal(grid_of(3, 5000, Fixed::one(), flat)) == "rows: 5000, a grid has 2 to 4097");
  CHECK(refusal(grid_of(1000, 1000, 0.01_fx, flat)) == "rows: 998001 cells, at most 524288");
  CHECK(refusal(grid_of(3, 3, 0.001_fx, flat)) == "spacing_x: outside 0.01..1000 m");
  CHECK(refusal(grid_of(300, 3, 100.0_fx, flat)) == "spacing_x: the grid spans more than 16000 m");
  HeightGrid g = grid_of(3, 3, Fixed::one(), flat);
  g.heights.pop_back();
  CHECK(refusal(g) == "heights: 8 heights, not 3 x 3");
  g = grid_of(3, 3, Fixed::one(), flat);
  g.heights[4] = 17000.0_fx;
  CHECK(refusal(g) == "heights[4]: outside -16000..16000 m");
  g = grid_of(3, 3, Fixed::one(), flat);
  g.holes = {1, 4};
  CHECK(refusal(g) == "holes[1]: cell 4 of 4");
  g.holes = {2, 1};
  CHECK(refusal(g) == "holes[1]: holes not ascending, or one listed twice");
  g.holes = {0, 1, 2, 3};
  CHECK(refusal(g) == "holes: every cell a hole: no ground");
  g = grid_of(3, 3, 600.0_fx, flat);
  g.heights[4] = 900.0_fx;  // an edge of sqrt(600^2 + 900^2) > 1000 m
  CHECK(refusal(g).rfind("heights: triangle ", 0) == 0);
}

TEST_CASE("Heightfield: a box slides down a slope of heights as far as the analytic answer", "[heightfield][motion]") {
  // Heights falling 20 degrees along x (h = -x tan 20), 0.5 m samples: the
  // slope's triangles are no tilted plane's but the grid's own.
  // a = g (sin 20 - 0.2 cos 20) = 1.5117 m/s^2 for 1.5 s.
  const double pi = 3.14159265358979;
  const double slope = std::tan(20 * pi / 180);
  const auto height = [&](uint32_t i, uint32_t) { return test::to_fixed(-0.5 * i * slope); };
  TestWorld t;
  add_heightfield(t, grid_of(41, 9, 0.5_fx, height), {-4.0_fx, 4.0_fx, -2.0_fx}, sliding(0.2_fx));
  const Quat tilt = test::about_degrees({Fixed{}, Fixed{}, Fixed::one()}, -20.0_fx);
  const Vec3 down_slope = rotate(tilt, {Fixed::one(), Fixed{}, Fixed{}});
  const Vec3 up = rotate(tilt, {Fixed{}, Fixed::one(), Fixed{}});
  // The surface point above x = -2 (2 m down the slope), the box 1 mm above it.
  const Vec3 surface{-2.0_fx, test::to_fixed(4.0 - 2.0 * slope), 0.3_fx};
  const BodyId box = add_slope_box(t, surface, tilt, up);
  const Vec3 start = t.world.body(box).pose.position;
  double off_surface = 0;
  for (int step = 0; step < 90; ++step) {
    t.world.step();
    off_surface = std::max(off_surface, std::abs(to_double(dot(t.world.body(box).pose.position - start, up))));
  }
  const Body& b = t.world.body(box);
  const double along = to_double(dot(b.pose.position - start, down_slope));
  const double a = 9.81 * (std::sin(20 * pi / 180) - 0.2 * std::cos(20 * pi / 180));
  const double expected = a * (1.0 / 3600) * 90 * 91 / 2;  // the semi-implicit Euler step's distance
  const double speed = to_double(dot(b.linear_velocity, down_slope));
  INFO("slid " << along << " m (analytic " << expected << ") at " << speed << " m/s (analytic " << a * 1.5
               << "); farthest off the surface " << off_surface << " m");
  CHECK(std::abs(along - expected) < 0.01 * expected);
  CHECK(std::abs(speed - a * 1.5) < 0.01 * a * 1.5);
  CHECK(off_surface < 0.002);
}

// Ten starts across the slope, so triangle edges pass under the box at
// every phase. The mesh manifold once started its four points from
// whichever clipped point rounded deepest, often one mid-way along a side
// where a triangle edge cut the face: a corner was left out, the smaller
// face tipped the box, a corner a few microns up carried load outside the
// friction cone, and boxes slid up to 11% too far (2.6% from these
// starts). The issue asks for 1%; it is 0.01% now.
TEST_CASE("Heightfield: a box slides down a slope of heights within 1% wherever it starts across it",
          "[heightfield][motion]") {
  const double pi = 3.14159265358979;
  const double slope = std::tan(20 * pi / 180);
  const auto height = [&](uint32_t i, uint32_t) { return test::to_fixed(-0.5 * i * slope); };
  const Quat tilt = test::about_degrees({Fixed{}, Fixed{}, Fixed::one()}, -20.0_fx);
  const Vec3 down_slope = rotate(tilt, {Fixed::one(), Fixed{}, Fixed{}});
  const Vec3 up = rotate(tilt, {Fixed{}, Fixed::one(), Fixed{}});
  const double a = 9.81 * (std::sin(20 * pi / 180) - 0.2 * std::cos(20 * pi / 180));
  const double expected = a * (1.0 / 3600) * 90 * 91 / 2;
  double worst = 0;
  for (int k = 0; k < 10; ++k) {
    TestWorld t;
    add_heightfield(t, grid_of(41, 21, 0.5_fx, height), {-10.0_fx, Fixed{}, -5.0_fx}, sliding(0.2_fx));
    const double x = -8 + 0.4 * k, z = -4 + 0.8 * k;
    const Vec3 surface{test::to_fixed(x), test::to_fixed(-(x + 10) * slope), test::to_fixed(z)};
    const BodyId box = add_slope_box(t, surface, tilt, up);
    const Vec3 start = t.world.body(box).pose.position;
    for (int step = 0; step < 90; ++step) t.world.step();
    const double along = to_double(dot(t.world.body(box).pose.position - start, down_slope));
    worst = std::max(worst, std::abs(along - expected) / expected);
  }
  INFO("worst relative error " << worst);
  CHECK(worst < 0.002);
}

TEST_CASE("Heightfield: a box slides across cells and diagonals without a bump and stops as analysed",
          "[heightfield][motion]") {
  // 5 m/s, mu 0.3, heading across the cells' diagonals (which run along
  // +x +z) as well as their borders: it stops after the integrator's own
  // 4.2057 m (test::euler_stop_distance; v^2 / (2 mu g) = 4.2474 m is the
  // continuous answer), on a box ground and at any heading alike.
  const auto flat = [](uint32_t, uint32_t) { return 1.0_fx; };
  double travelled_on[2] = {};
  for (const bool on_grid : {true, false}) {
    TestWorld t;
    if (on_grid) {
      add_heightfield(t, grid_of(31, 21, 0.5_fx, flat), {-3.0_fx, -1.0_fx, -5.0_fx}, sliding(0.3_fx));
    } else {
      t.add_ground(sliding(0.3_fx));
    }
    const BodyId box = t.add_box({Fixed{}, 0.25_fx, Fixed{}}, {0.25_fx, 0.25_fx, 0.25_fx}, sliding(0.3_fx));
    t.world.set_velocity(box, {4.0_fx, Fixed{}, -3.0_fx}, {});
    double fastest_up = 0;
    for (int step = 0; step < 180; ++step) {
      t.world.step();
      if (step > 2) fastest_up = std::max(fastest_up, std::abs(to_double(t.world.body(box).linear_velocity.y)));
    }
    const Body& b = t.world.body(box);
    const double travelled = std::hypot(to_double(b.pose.position.x), to_double(b.pose.position.z));
    const double expected = test::euler_stop_distance(5.0, 0.3 * 9.81, 1.0 / 60);
    INFO((on_grid ? "grid" : "box ground") << ": travelled " << travelled << " m (analytic " << expected
                                           << "), fastest vertical " << fastest_up << " m/s");
    CHECK(std::abs(travelled - expected) < 0.001 * expected);
    CHECK(fastest_up < 0.001);
    CHECK(to_double(length(b.angular_velocity)) < 0.001);
    travelled_on[on_grid ? 0 : 1] = travelled;
  }
  // The same slide on a box ground, to a tenth of a millimetre.
  CHECK(std::abs(travelled_on[0] - travelled_on[1]) < 1e-4);
}

TEST_CASE("Heightfield: a ball rolls down into a dip and up the far side, a ball falls through a hole",
          "[heightfield][motion]") {
  // A valley along x: h = 0.5 (1 + cos(2 pi x / 8)) over 0 <= x <= 8, a
  // smooth curve sampled every 0.25 m. A ball let go at rest at x = 1 rolls
  // down and up the far side: with no slip and no loss it would reach the
  // height it started from; the grid's facets and rolling friction lose a
  // little, never more than a fifth of it, and it never leaves the ground
  // upward faster than the surface would carry it.
  const double pi = 3.14159265358979;
  const auto valley = [&](uint32_t i, uint32_t) { return test::to_fixed(0.5 * (1 + std::cos(2 * pi * i * 0.25 / 8))); };
  HeightGrid g = grid_of(33, 9, 0.25_fx, valley);
  g.holes = {7 * 32 + 30};  // cell (30, 7), away from the rolling ball: the second ball's
  TestWorld t;
  add_heightfield(t, g, {Fixed{}, Fixed{}, -1.0_fx}, sliding(0.5_fx));
  const double start_height = 0.5 * (1 + std::cos(2 * pi * 1.0 / 8));
  const BodyId ball =
      t.add_sphere({Fixed::one(), test::to_fixed(start_height + 0.2 + 0.001), Fixed{}}, 0.2_fx, sliding(0.5_fx));
  // The hole is cell (30, 7): x 7.5..7.75, z 0.75..1.0 in the world; a 5 cm ball over its middle.
  const BodyId pebble = t.add_sphere({7.625_fx, 1.0_fx, 0.875_fx}, 0.05_fx, sliding(0.5_fx));
  double far_side_peak = 0;
  for (int step = 0; step < 400; ++step) {
    t.world.step();
    const Body& b = t.world.body(ball);
    if (to_double(b.pose.position.x) > 4.0) far_side_peak = std::max(far_side_peak, to_double(b.pose.position.y) - 0.2);
  }
  INFO("started at height " << start_height << ", reached " << far_side_peak << " on the far side");
  CHECK(far_side_peak < start_height + 0.002);
  CHECK(far_side_peak > 0.8 * start_height);
  INFO("pebble at y " << to_double(t.world.body(pebble).pose.position.y));
  CHECK(to_double(t.world.body(pebble).pose.position.y) < -2.0);  // through the hole, falling
}

TEST_CASE("Heightfield: rays and casts meet the grid at its heights and pass through a hole", "[heightfield][query]") {
  // A plane of heights h = 0.1 x + 0.05 z: a ray down at (x, z) meets it at h.
  const auto plane = [](uint32_t i, uint32_t j) {
    return 0.1_fx * Fixed::from_int(static_cast<int32_t>(i)) + 0.05_fx * Fixed::from_int(static_cast<int32_t>(j));
  };
  HeightGrid g = grid_of(11, 11, Fixed::one(), plane);
  g.holes = {2 * 10 + 3};  // cell (3, 2)
  TestWorld t;
  add_heightfield(t, g, {}, {});
  const WorldQuery query(t.world);
  const Vec3 down{Fixed{}, -10.0_fx, Fixed{}};
  for (const auto& [x, z] : {std::pair{1.3_fx, 7.6_fx}, std::pair{8.9_fx, 0.2_fx}, std::pair{5.5_fx, 5.5_fx}}) {
    const auto hit = query.cast_ray({x, 5.0_fx, z}, down);
    REQUIRE(hit.has_value());
    const double h = 0.1 * to_double(x) + 0.05 * to_double(z);
    INFO("at (" << to_double(x) << ", " << to_double(z) << "): hit at " << 5 - 10 * to_double(hit->fraction));
    CHECK(std::abs(5 - 10 * to_double(hit->fraction) - h) < 1e-6);
    const double n = std::sqrt(1 + 0.01 + 0.0025);
    CHECK(std::abs(to_double(hit->normal.x) + 0.1 / n) < 1e-6);
    CHECK(std::abs(to_double(hit->normal.y) - 1 / n) < 1e-6);
  }
  CHECK_FALSE(query.cast_ray({3.5_fx, 5.0_fx, 2.5_fx}, down).has_value());                          // the hole
  CHECK_FALSE(query.cast_ray({3.5_fx, -5.0_fx, 3.5_fx}, {Fixed{}, 10.0_fx, Fixed{}}).has_value());  // from below
  const auto ball = query.cast_sphere(0.5_fx, {5.5_fx, 5.0_fx, 5.5_fx}, down);
  REQUIRE(ball.has_value());
  // The centre stops 0.5 m from the plane along its normal: 0.5 n_y^-1 above it.
  const double lift = 0.5 * std::sqrt(1 + 0.01 + 0.0025);
  CHECK(std::abs(5 - 10 * to_double(ball->fraction) - (0.825 + lift)) < 1e-5);
}
