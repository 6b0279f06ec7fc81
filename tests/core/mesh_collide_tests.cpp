// Static triangle meshes in motion (core/collide_mesh.cpp): bodies slide,
// roll and land on meshes as on a box ground, with no bump at the edges
// between triangles, against the analytic answers.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cmath>
#include <vector>

#include "core/query.h"
#include "core/triangle_mesh.h"
#include "tests/core/test_world.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::TestWorld;
using bitstep::test::to_double;

namespace {

// An n x m grid of `cell` m squares in the x-z plane from (x0, 0, z0), two
// triangles each, facing +y; turned by `tilt` about the origin.
std::shared_ptr<const TriangleMesh> grid_mesh(int n, int m, Fixed cell, Fixed x0, Fixed z0) {
  std::vector<Vec3> vertices;
  std::vector<uint32_t> indices;
  for (int j = 0; j <= m; ++j) {
    for (int i = 0; i <= n; ++i)
      vertices.push_back({x0 + cell * Fixed::from_int(i), Fixed{}, z0 + cell * Fixed::from_int(j)});
  }
  const auto at = [&](int i, int j) { return static_cast<uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < m; ++j) {
    for (int i = 0; i < n; ++i) {
      indices.insert(indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j)});
      indices.insert(indices.end(), {at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)});
    }
  }
  return build_triangle_mesh(vertices, indices).value();
}

BodyId add_mesh(TestWorld& t, std::shared_ptr<const TriangleMesh> mesh, Quat tilt = {}, Material material = {}) {
  BodyDef def;
  def.type = BodyType::static_body;
  def.pose.orientation = tilt;
  Shape shape;
  shape.type = ShapeType::mesh;
  shape.mesh = std::move(mesh);
  def.shapes.push_back(shape);
  def.material = material;
  return t.world.create_body(def).value();
}

Material sliding(Fixed mu) { return {mu, mu, Fixed{}, Fixed{}}; }

}  // namespace

TEST_CASE("Mesh: a box sliding across 1 m triangles stops where the analytic answer says, without a bump",
          "[mesh][motion]") {
  // 5.009 m/s, mu 0.3: it stops after the integrator's own distance
  // (test::euler_stop_distance: 4.2210 m; v^2 / (2 mu g) = 4.2627 m), in
  // v / (mu g) = 1.70 s.
  for (const bool on_mesh : {true, false}) {
    TestWorld t;
    if (on_mesh) {
      add_mesh(t, grid_mesh(20, 6, Fixed::one(), -2.0_fx, -3.0_fx), {}, sliding(0.3_fx));
    } else {
      t.add_ground(sliding(0.3_fx));
    }
    const BodyId box = t.add_box({Fixed{}, 0.25_fx, Fixed{}}, {0.25_fx, 0.25_fx, 0.25_fx}, sliding(0.3_fx));
    t.world.set_velocity(box, {5.0_fx, Fixed{}, 0.3_fx}, {});  // across the squares' diagonals too
    double fastest_up = 0, highest = 0;
    for (int step = 0; step < 180; ++step) {
      t.world.step();
      const Body& b = t.world.body(box);
      if (step > 2) fastest_up = std::max(fastest_up, std::abs(to_double(b.linear_velocity.y)));
      highest = std::max(highest, to_double(b.pose.position.y));
    }
    const Body& b = t.world.body(box);
    const double travelled = std::hypot(to_double(b.pose.position.x), to_double(b.pose.position.z));
    const double expected = test::euler_stop_distance(std::sqrt(25.0 + 0.09), 0.3 * 9.81, 1.0 / 60);
    INFO((on_mesh ? "mesh" : "box ground") << ": travelled " << travelled << " m (analytic " << expected
                                           << "), fastest vertical " << fastest_up << " m/s, highest " << highest);
    CHECK(std::abs(travelled - expected) < 0.001 * expected);
    CHECK(fastest_up < 0.001);
    CHECK(highest < 0.25 + 0.001);
    CHECK(to_double(length(b.angular_velocity)) < 0.001);
  }
}

TEST_CASE("Mesh: a box sliding down a slope of triangles touches at its four bottom corners at every step",
          "[mesh][contact][motion]") {
  // A face on several triangles is clipped by their edges into more points
  // than four, all at one depth to within rounding; the manifold must keep
  // the face's corners (as on a plane), not a point mid-way along a side,
  // or the smaller face tips the box as edges pass under it. 0.3 m cells
  // under a 0.5 m box sliding down 20 degrees, from 8 places across them;
  // the points are compared in the box's frame at the pose they were found
  // at (the start of the step).
  const Quat tilt = test::about_degrees({Fixed{}, Fixed{}, Fixed::one()}, -20.0_fx);
  const Vec3 down_slope = rotate(tilt, {Fixed::one(), Fixed{}, Fixed{}});
  const Vec3 up = rotate(tilt, {Fixed{}, Fixed::one(), Fixed{}});
  int wrong = 0, steps = 0;
  double worst = 0;
  for (int k = 0; k < 8; ++k) {
    TestWorld t;
    add_mesh(t, grid_mesh(40, 10, 0.3_fx, -8.0_fx, -1.5_fx), tilt, sliding(0.2_fx));
    BodyDef def;
    def.pose = {up * 0.25_fx + down_slope * (Fixed::from_int(k) * 0.0375_fx - 6.0_fx) +
                    Vec3{Fixed{}, Fixed{}, Fixed::from_int(k) * 0.04_fx},
                tilt};
    def.shapes.push_back({ShapeType::box, {0.25_fx, 0.25_fx, 0.25_fx}, {}, {}, {}});
    def.material = sliding(0.2_fx);
    const BodyId box = t.world.create_body(def).value();
    for (int step = 0; step < 90; ++step) {
      const Pose before = t.world.body(box).pose;
      t.world.step();
      REQUIRE(t.world.contacts().size() == 1);
      const Manifold& m = t.world.contacts()[0].manifold;
      bool corners = m.point_count == 4;
      for (int i = 0; i < m.point_count; ++i) {
        const Vec3 d = rotate_inverse(before.orientation, m.points[static_cast<size_t>(i)].position - before.position);
        const double off =
            std::max(std::abs(std::abs(to_double(d.x)) - 0.25), std::abs(std::abs(to_double(d.z)) - 0.25));
        worst = std::max(worst, off);
        corners = corners && off < 0.001;
      }
      wrong += corners ? 0 : 1;
      ++steps;
    }
  }
  INFO(wrong << " of " << steps << " steps without the four corners; farthest point from a corner " << worst << " m");
  CHECK(wrong == 0);
}

TEST_CASE("Mesh: a box slides down a 20-degree mesh slope as far as the analytic answer", "[mesh][motion]") {
  // a = g (sin 20 - 0.2 cos 20) = 1.5117 m/s^2, for 1.5 s, on a mesh and on a box.
  const Fixed degrees = 20.0_fx;
  const Quat tilt = test::about_degrees({Fixed{}, Fixed{}, Fixed::one()}, -degrees);
  for (const bool on_mesh : {true, false}) {
    TestWorld t;
    if (on_mesh) {
      add_mesh(t, grid_mesh(16, 4, Fixed::one(), -8.0_fx, -2.0_fx), tilt, sliding(0.2_fx));
    } else {  // the same slope as a box, its top face through the origin
      BodyDef ramp;
      ramp.type = BodyType::static_body;
      ramp.pose = {rotate(tilt, {Fixed{}, -0.5_fx, Fixed{}}), tilt};
      ramp.shapes.push_back({ShapeType::box, {8.0_fx, 0.5_fx, 2.0_fx}, {}, {}, {}});
      ramp.material = sliding(0.2_fx);
      t.world.create_body(ramp);
    }
    // The box on the slope at its middle, turned with it, 1 mm above.
    const Vec3 down_slope = rotate(tilt, {Fixed::one(), Fixed{}, Fixed{}});
    const Vec3 up = rotate(tilt, {Fixed{}, Fixed::one(), Fixed{}});
    BodyDef def;
    def.pose = {up * 0.251_fx - down_slope * 4.0_fx, tilt};
    def.shapes.push_back({ShapeType::box, {0.25_fx, 0.25_fx, 0.25_fx}, {}, {}, {}});
    def.material = sliding(0.2_fx);
    const BodyId box = t.world.create_body(def).value();
    const Vec3 start = t.world.body(box).pose.position;
    for (int step = 0; step < 90; ++step) t.world.step();
    const Body& b = t.world.body(box);
    const double along = to_double(dot(b.pose.position - start, down_slope));
    const double pi = 3.14159265358979;
    const double a = 9.81 * (std::sin(20 * pi / 180) - 0.2 * std::cos(20 * pi / 180));
    // The speed is a t; the distance a dt^2 n (n + 1) / 2 after n steps of
    // the semi-implicit Euler step (the continuous a t^2 / 2 less a dt t / 2:
    // 1.1% at 90 steps, the integrator's own, slope or no slope).
    const double speed = to_double(dot(b.linear_velocity, down_slope));
    const double expected = a * (1.0 / 3600) * 90 * 91 / 2;
    INFO((on_mesh ? "mesh" : "box") << ": slid " << along << " m (analytic " << expected << "), at " << speed
                                    << " m/s (analytic " << a * 1.5 << ")");
    CHECK(std::abs(along - expected) < 0.01 * expected);
    CHECK(std::abs(speed - a * 1.5) < 0.01 * a * 1.5);
    CHECK(std::abs(to_double(dot(b.pose.position - start, up))) < 0.002);  // on the surface, not hopping
  }
}

TEST_CASE("Mesh: a ball rolls across triangles without hopping, a capsule lies still, a die lands on a face",
          "[mesh][motion]") {
  TestWorld t;
  add_mesh(t, grid_mesh(80, 16, 0.5_fx, -2.0_fx, -4.0_fx), {}, sliding(0.5_fx));
  const BodyId ball = t.add_sphere({Fixed{}, 0.3_fx, Fixed{}}, 0.3_fx, sliding(0.5_fx));
  t.world.set_velocity(ball, {4.0_fx, Fixed{}, 0.7_fx}, {});
  const Quat lying = test::about_degrees({Fixed{}, Fixed{}, Fixed::one()}, 90.0_fx);
  const BodyId pill = t.add_capsule({{2.0_fx, 0.2_fx, -1.0_fx}, lying}, 0.2_fx, 0.5_fx, sliding(0.5_fx));
  BodyDef thrown;
  thrown.pose.position = {Fixed{}, 1.5_fx, 1.5_fx};
  thrown.linear_velocity = {1.0_fx, 1.0_fx, Fixed{}};
  thrown.angular_velocity = {6.0_fx, -4.0_fx, 3.0_fx};
  thrown.shapes.push_back(test::die_hull(0.25_fx, 0.2_fx));
  thrown.material = sliding(0.5_fx);
  const BodyId die = t.world.create_body(thrown).value();
  double ball_up = 0, pill_spin = 0, die_lowest = 10;
  for (int step = 0; step < 300; ++step) {
    t.world.step();
    die_lowest = std::min(die_lowest, to_double(t.world.body(die).pose.position.y));
    ball_up = std::max(ball_up, std::abs(to_double(t.world.body(ball).linear_velocity.y)));
    pill_spin = std::max(pill_spin, to_double(length(t.world.body(pill).angular_velocity)));
  }
  INFO("ball's fastest vertical speed " << ball_up << " m/s, capsule's fastest spin " << pill_spin << " rad/s");
  CHECK(ball_up < 0.001);
  CHECK(pill_spin < 0.001);
  CHECK(std::abs(to_double(t.world.body(pill).pose.position.y) - 0.2) < 0.001);
  CHECK(to_double(t.world.body(ball).pose.position.x) > 4.0);  // rolled on over many triangles
  // The die at rest on one of its octagons (tilt under a degree), never sunk more than 1 cm.
  const Body& d = t.world.body(die);
  const Mat33 r = rotation(d.pose.orientation);
  double most_down = 0;
  for (int k = 0; k < 3; ++k) most_down = std::max(most_down, std::abs(to_double(r.column(k).y)));
  INFO("die at y " << to_double(d.pose.position.y) << ", lowest " << die_lowest << ", face cos " << most_down);
  CHECK(most_down > std::cos(3.14159265358979 / 180));
  CHECK(std::abs(to_double(d.pose.position.y) - 0.25) < 0.002);
  CHECK(die_lowest > 0.24);
  CHECK(to_double(length(d.linear_velocity)) < 0.01);
}

TEST_CASE("Mesh: a fast small box meets a mesh wall and stops at its face", "[mesh][motion]") {
  for (const Fixed speed : {20.0_fx, 100.0_fx, 500.0_fx}) {
    Settings settings;
    settings.gravity = Vec3{};
    TestWorld t(settings);
    // The grid turned to face -x at x = 10: a wall of 1 m triangles.
    const Quat facing = test::about_degrees({Fixed{}, Fixed{}, Fixed::one()}, 90.0_fx);
    BodyDef def;
    def.type = BodyType::static_body;
    def.pose = {{10.0_fx, Fixed{}, Fixed{}}, facing};
    Shape shape;
    shape.type = ShapeType::mesh;
    shape.mesh = grid_mesh(6, 6, Fixed::one(), -3.0_fx, -3.0_fx);
    def.shapes.push_back(shape);
    t.world.create_body(def);
    BodyDef body;
    body.shapes.push_back({ShapeType::box, {0.01_fx, 0.01_fx, 0.01_fx}, {}, {}, {}});
    body.mass = 0.1_fx;
    body.linear_velocity = {speed, Fixed{}, Fixed{}};
    const BodyId box = t.world.create_body(body).value();
    double farthest = -1e9;
    for (int step = 0; step < 120; ++step) {
      t.world.step();
      farthest = std::max(farthest, to_double(t.world.body(box).pose.position.x));
    }
    INFO("at " << to_double(speed) << " m/s: farthest " << farthest);
    CHECK(farthest <= 9.99 + 0.0001);
    CHECK(farthest >= 9.99 - 0.001);
  }
}

TEST_CASE("Mesh: rays, casts and overlaps meet its fronts where they meet a box ground's top", "[mesh][query]") {
  // The same surface twice: a 1 m grid mesh at y = 0 (at x < 50) and a box
  // whose top is y = 0 (at x > 50). Each query is asked at x = 3.3 and at
  // x = 53.3; the answers agree within rounding.
  TestWorld t;
  add_mesh(t, grid_mesh(20, 20, Fixed::one(), -10.0_fx, -10.0_fx));
  BodyDef ground;
  ground.type = BodyType::static_body;
  ground.pose.position = {60.0_fx, -1.0_fx, Fixed{}};
  ground.shapes.push_back({ShapeType::box, {10.0_fx, 1.0_fx, 10.0_fx}, {}, {}, {}});
  t.world.create_body(ground);
  const WorldQuery query(t.world);
  const Vec3 down{Fixed{}, -4.0_fx, Fixed{}};
  const auto near = [](Fixed a, Fixed b) { return std::abs(to_double(a - b)) < 1e-6; };
  for (const Fixed x : {3.3_fx, 53.3_fx}) {
    INFO("at x " << to_double(x));
    const Vec3 above{x, 2.0_fx, 0.7_fx};
    const auto ray = query.cast_ray(above, down);
    REQUIRE(ray.has_value());
    CHECK(near(ray->fraction, 0.5_fx));
    CHECK(ray->normal == Vec3{Fixed{}, Fixed::one(), Fixed{}});
    const auto ball = query.cast_sphere(0.5_fx, above, down);
    REQUIRE(ball.has_value());
    CHECK(near(ball->fraction, 0.375_fx));  // the centre stops 0.5 m up
    const Shape box{ShapeType::box, {0.25_fx, 0.25_fx, 0.25_fx}, {}, {}, {}};
    const auto crate =
        query.cast_shape(box, {above, test::about_degrees({Fixed{}, Fixed::one(), Fixed{}}, 30.0_fx)}, down);
    REQUIRE(crate.has_value());
    CHECK(std::abs(to_double(crate->fraction) - 1.75 / 4) < 1e-5);
    const Shape die = test::die_hull(0.25_fx, 0.2_fx);
    const auto thrown = query.cast_shape(die, {above, {}}, down);
    REQUIRE(thrown.has_value());
    CHECK(std::abs(to_double(thrown->fraction) - 1.75 / 4) < 1e-5);
    // A box a centimetre into the surface overlaps it.
    std::vector<ShapeOverlap> overlaps;
    query.overlap_shape(box, {{x, 0.24_fx, 0.7_fx}, {}}, overlaps);
    REQUIRE(overlaps.size() == 1);
    CHECK(std::abs(to_double(overlaps[0].depth) - 0.01) < 1e-6);
  }
  // One-sided: from below, a ray and a sphere pass up through the mesh.
  CHECK_FALSE(query.cast_ray({3.3_fx, -2.0_fx, 0.7_fx}, {Fixed{}, 4.0_fx, Fixed{}}).has_value());
  CHECK_FALSE(query.cast_sphere(0.2_fx, {3.3_fx, -2.0_fx, 0.7_fx}, {Fixed{}, 4.0_fx, Fixed{}}).has_value());
}
