// The narrowphase (core/collide.h): analytic contacts for every pair of shape
// types, both orders, feature-id stability, and random poses across the world
// envelope. Tolerances are in ulps (2^-32 m) where the geometry is exact in
// Q32.32 (axis-aligned shapes), and a few hundred ulps (~1e-7 m) where
// rotations by sin/cos of 45 degrees enter.
#include <algorithm>
#include <catch2/catch.hpp>
#include <cstdint>
#include <ostream>
#include <sstream>
#include <string>
#include <vector>

#include "core/collide.h"
#include "core/convex_hull.h"
#include "core/settings.h"
#include "fixed/decimal.h"
#include "fixed/mat33.h"
#include "fixed/splitmix64.h"
#include "tests/test_support.h"

namespace bitstep {
// Catch2 prints Fixed and Vec3 in failure messages.
inline std::ostream& operator<<(std::ostream& os, Fixed f) { return os << to_string(f); }
inline std::ostream& operator<<(std::ostream& os, Vec3 v) {
  return os << '(' << v.x << ", " << v.y << ", " << v.z << ')';
}
}  // namespace bitstep

namespace {

using namespace bitstep;
using namespace bitstep::literals;

constexpr Fixed spec = 0.02_fx;                          // the default speculative distance
constexpr Fixed quarter_pi = 0.78539816339744830962_fx;  // 45 degrees
constexpr Fixed half_sqrt2 = 0.70710678118654752440_fx;  // sin 45 degrees
constexpr Fixed sqrt2 = 1.41421356237309504880_fx;
constexpr Fixed rotation_tolerance = Fixed::from_raw(256);  // ~6e-8 m: after sin/cos rotations

Fixed ulps(int64_t n) { return Fixed::from_raw(n); }
Vec3 v3(Fixed x, Fixed y, Fixed z) { return {x, y, z}; }
const Vec3 x_axis{Fixed::one(), {}, {}}, y_axis{{}, Fixed::one(), {}}, z_axis{{}, {}, Fixed::one()};
Quat about(Vec3 axis, Fixed angle) { return from_axis_angle(axis, angle); }

Shape box_shape(Fixed hx, Fixed hy, Fixed hz) {
  Shape s;
  s.type = ShapeType::box;
  s.half_extents = {hx, hy, hz};
  return s;
}
Shape cube_shape(Fixed h) { return box_shape(h, h, h); }
Shape sphere_shape(Fixed r) {
  Shape s;
  s.type = ShapeType::sphere;
  s.radius = r;
  return s;
}
Shape capsule_shape(Fixed half_height, Fixed r) {
  Shape s;
  s.type = ShapeType::capsule;
  s.half_height = half_height;
  s.radius = r;
  return s;
}
Shape plane_shape() {
  Shape s;
  s.type = ShapeType::plane;
  return s;
}

struct Placed {
  Shape shape;
  Pose pose;
  WorldShape world() const { return {&shape, pose}; }
};
Placed place(Shape s, Vec3 position, Quat orientation = Quat::identity()) { return {s, {position, orientation}}; }

Manifold run(const Placed& a, const Placed& b, Fixed speculative = spec) {
  Manifold m;
  const int n = collide(a.world(), b.world(), speculative, m);
  REQUIRE(n == m.point_count);
  REQUIRE(n >= 0);
  REQUIRE(n <= max_manifold_points);
  return m;
}

bool near(Fixed a, Fixed b, Fixed tolerance) { return abs(a - b) <= tolerance; }
bool near(Vec3 a, Vec3 b, Fixed tolerance) {
  return near(a.x, b.x, tolerance) && near(a.y, b.y, tolerance) && near(a.z, b.z, tolerance);
}

std::string describe(const Manifold& m) {
  std::ostringstream s;
  s << "normal " << m.normal << ", " << m.point_count << " points:";
  for (int i = 0; i < m.point_count; ++i) {
    const ContactPoint& p = m.points[static_cast<size_t>(i)];
    s << "\n  " << p.position << " depth " << p.depth << " feature 0x" << std::hex << p.feature << std::dec;
  }
  return s.str();
}

// The point of m at `position` (within tolerance), or nullptr.
const ContactPoint* point_at(const Manifold& m, Vec3 position, Fixed tolerance) {
  for (int i = 0; i < m.point_count; ++i) {
    if (near(m.points[static_cast<size_t>(i)].position, position, tolerance)) return &m.points[static_cast<size_t>(i)];
  }
  return nullptr;
}

// Every expected point is present with the expected depth; nothing else.
void require_points(const Manifold& m, const std::vector<Vec3>& positions, Fixed depth, Fixed position_tolerance,
                    Fixed depth_tolerance) {
  INFO(describe(m));
  REQUIRE(m.point_count == static_cast<int>(positions.size()));
  for (Vec3 p : positions) {
    INFO("expected point " << p);
    const ContactPoint* c = point_at(m, p, position_tolerance);
    REQUIRE(c != nullptr);
    CHECK(near(c->depth, depth, depth_tolerance));
    CHECK(c->normal_impulse == Fixed{});
  }
  CHECK(m.friction_impulse[0] == Fixed{});
  CHECK(m.friction_impulse[1] == Fixed{});
  CHECK(m.twist_impulse == Fixed{});
}

// a and b hold the same points (any order), positions and depths within tolerance.
bool same_points(const Manifold& a, const Manifold& b, Fixed tolerance) {
  if (a.point_count != b.point_count) return false;
  for (int i = 0; i < a.point_count; ++i) {
    const ContactPoint& p = a.points[static_cast<size_t>(i)];
    const ContactPoint* q = point_at(b, p.position, tolerance);
    if (q == nullptr || !near(p.depth, q->depth, tolerance)) return false;
  }
  return true;
}

bool identical(const Manifold& a, const Manifold& b) {
  if (a.point_count != b.point_count || !(a.normal == b.normal)) return false;
  for (int i = 0; i < a.point_count; ++i) {
    const ContactPoint& p = a.points[static_cast<size_t>(i)];
    const ContactPoint& q = b.points[static_cast<size_t>(i)];
    if (!(p.position == q.position) || p.depth != q.depth || p.feature != q.feature) return false;
  }
  return true;
}

// collide(b, a) gives the flipped normal and the same points.
void require_swap_consistent(const Placed& a, const Placed& b, Fixed tolerance) {
  const Manifold ab = run(a, b), ba = run(b, a);
  INFO("a, b: " << describe(ab) << "\nb, a: " << describe(ba));
  REQUIRE(ab.point_count == ba.point_count);
  if (ab.point_count == 0) return;
  REQUIRE(near(ab.normal, -ba.normal, tolerance));
  REQUIRE(same_points(ab, ba, tolerance));
}

std::vector<FeatureId> sorted_features(const Manifold& m) {
  std::vector<FeatureId> f;
  for (int i = 0; i < m.point_count; ++i) f.push_back(m.points[static_cast<size_t>(i)].feature);
  std::sort(f.begin(), f.end());
  return f;
}

const Placed ground_box = place(box_shape(10_fx, 0.5_fx, 10_fx), v3({}, -0.5_fx, {}));
const Placed ground_plane = place(plane_shape(), Vec3::zero());

}  // namespace

TEST_CASE("a unit cube resting exactly on a ground box: four corners, normal exactly up", "[collide]") {
  const Placed cube = place(cube_shape(0.5_fx), v3({}, 0.5_fx, {}));
  const std::vector<Vec3> corners{v3(0.5_fx, {}, 0.5_fx), v3(-0.5_fx, {}, 0.5_fx), v3(-0.5_fx, {}, -0.5_fx),
                                  v3(0.5_fx, {}, -0.5_fx)};
  const Manifold m = run(ground_box, cube);
  CHECK(m.normal == y_axis);
  require_points(m, corners, Fixed{}, ulps(2), ulps(2));

  const Manifold flipped = run(cube, ground_box);
  CHECK(flipped.normal == -y_axis);
  require_points(flipped, corners, Fixed{}, ulps(2), ulps(2));

  SECTION("1 cm overlap: depth 0.01, points midway, 5 mm below the ground's top") {
    const Placed sunk = place(cube_shape(0.5_fx), v3({}, 0.49_fx, {}));
    std::vector<Vec3> mid = corners;
    for (Vec3& p : mid) p.y = -0.005_fx;
    require_points(run(ground_box, sunk), mid, 0.01_fx, ulps(4), ulps(4));
    require_points(run(sunk, ground_box), mid, 0.01_fx, ulps(4), ulps(4));
  }
}

TEST_CASE("a cube rotated 45 degrees about y on a ground box: four points on the rotated corners", "[collide]") {
  const Placed cube = place(cube_shape(0.5_fx), v3({}, 0.5_fx, {}), about(y_axis, quarter_pi));
  const Manifold m = run(ground_box, cube);
  CHECK(m.normal == y_axis);
  require_points(m, {v3(half_sqrt2, {}, {}), v3(-half_sqrt2, {}, {}), v3({}, {}, half_sqrt2), v3({}, {}, -half_sqrt2)},
                 Fixed{}, rotation_tolerance, ulps(2));
}

TEST_CASE("a cube on another cube turned 45 degrees: the octagon reduced to 4 points", "[collide]") {
  const Placed bottom = place(cube_shape(0.5_fx), Vec3::zero());
  const Placed top = place(cube_shape(0.5_fx), v3({}, 0.995_fx, {}), about(y_axis, quarter_pi));
  const Manifold m = run(bottom, top);
  INFO(describe(m));
  REQUIRE(m.point_count == 4);
  CHECK(m.normal == y_axis);
  for (int i = 0; i < 4; ++i) {
    const ContactPoint& p = m.points[static_cast<size_t>(i)];
    CHECK(near(p.depth, 0.005_fx, ulps(4)));
    CHECK(near(p.position.y, 0.4975_fx, ulps(4)));
    // on the octagon: inside both squares, on the boundary of one of them
    CHECK(abs(p.position.x) <= 0.5_fx + rotation_tolerance);
    CHECK(abs(p.position.z) <= 0.5_fx + rotation_tolerance);
  }
  // The 4 points span a large quadrilateral: every pair at least 0.4 m apart.
  for (int i = 0; i < 4; ++i) {
    for (int j = i + 1; j < 4; ++j) {
      CHECK(length(m.points[static_cast<size_t>(i)].position - m.points[static_cast<size_t>(j)].position) > 0.4_fx);
    }
  }
}

TEST_CASE("a cube balanced on an edge: two points at the edge's ends", "[collide]") {
  const Placed cube = place(cube_shape(0.5_fx), v3({}, half_sqrt2, {}), about(z_axis, quarter_pi));
  const Manifold m = run(ground_box, cube);
  CHECK(near(m.normal, y_axis, ulps(2)));
  require_points(m, {v3({}, {}, 0.5_fx), v3({}, {}, -0.5_fx)}, Fixed{}, rotation_tolerance, rotation_tolerance);
}

TEST_CASE("two boxes crossing edge to edge: one point between the edges", "[collide]") {
  // A's top edge runs along x at height sqrt2/2; B's bottom edge along z at
  // sqrt2/2 - 0.01: they cross at x = z = 0 with 1 cm overlap.
  const Placed a = place(cube_shape(0.5_fx), Vec3::zero(), about(x_axis, quarter_pi));
  const Placed b = place(cube_shape(0.5_fx), v3({}, sqrt2 - 0.01_fx, {}), about(z_axis, quarter_pi));
  const Manifold m = run(a, b);
  INFO(describe(m));
  REQUIRE(m.point_count == 1);
  CHECK(near(m.normal, y_axis, rotation_tolerance));
  CHECK(near(m.points[0].position, v3({}, half_sqrt2 - 0.005_fx, {}), rotation_tolerance));
  CHECK(near(m.points[0].depth, 0.01_fx, rotation_tolerance));
  CHECK((m.points[0].feature >> 16) == 3u);  // an edge-edge id
  require_swap_consistent(a, b, rotation_tolerance);
}

// A box's face lying 10 mm deep across a long box's edge (a ragdoll's chest
// on a stair's edge), turned in its face plane by a small angle either way
// and tilted 0.25 degrees along the edge. The edge-edge axis separates least
// (the long box's far ends reach deeper along the face normal), but its one
// point sat at one end of the nearly parallel edges or the other as the
// angle changed sign, 32 cm apart: the face's clipped contact instead, two
// points along the edge with the same feature ids at every angle.
TEST_CASE("a box lying across a long box's edge: the face's two points, whichever way it is turned", "[collide]") {
  const Placed stair = place(box_shape(0.25_fx, 0.25_fx, 2.0_fx), Vec3::zero());
  const Vec3 edge{0.25_fx, 0.25_fx, Fixed{}};
  const Fixed degree = 0.017453292519943295_fx;
  const Quat leaning = about(z_axis, -40.0_fx * degree);  // its face (-y) faces the edge from beyond it
  std::vector<FeatureId> first_features;
  for (const Fixed turn : {-1.7_fx, -0.5_fx, 0.5_fx, 1.7_fx}) {
    const Vec3 face_normal = rotate(leaning, -y_axis);
    const Vec3 across = rotate(leaning, x_axis);
    const Quat pose = about(across, 0.25_fx * degree) * about(face_normal, turn * degree) * leaning;
    const Vec3 normal = rotate(pose, -y_axis);
    const Placed chest = place(box_shape(0.12_fx, 0.1_fx, 0.16_fx), edge - normal * (0.1_fx - 0.01_fx), pose);
    const Manifold m = run(stair, chest);
    INFO("turned " << turn << " degrees: " << describe(m));
    REQUIRE(m.point_count == 2);
    CHECK(near(m.normal, -normal, 0.0001_fx));  // the chest's face normal, from the stair to the chest
    for (int i = 0; i < 2; ++i) {
      const ContactPoint& p = m.points[static_cast<size_t>(i)];
      CHECK(near(p.depth, 0.01_fx, 0.001_fx));
      CHECK(abs(p.position.z) > 0.15_fx);  // at the ends of the chest's face along the edge
    }
    CHECK(m.points[0].position.z * m.points[1].position.z < Fixed{});  // one at each end
    if (first_features.empty()) first_features = sorted_features(m);
    CHECK(sorted_features(m) == first_features);
    require_swap_consistent(stair, chest, rotation_tolerance);
  }
}

TEST_CASE("separated boxes: nothing beyond the speculative distance, negative depth within it", "[collide]") {
  const Placed far = place(cube_shape(0.5_fx), v3({}, 0.53_fx, {}));
  CHECK(run(ground_box, far).point_count == 0);
  CHECK(run(far, ground_box).point_count == 0);
  const Placed near_cube = place(cube_shape(0.5_fx), v3({}, 0.51_fx, {}));
  const Manifold m = run(ground_box, near_cube);
  CHECK(m.normal == y_axis);
  require_points(m,
                 {v3(0.5_fx, 0.005_fx, 0.5_fx), v3(-0.5_fx, 0.005_fx, 0.5_fx), v3(-0.5_fx, 0.005_fx, -0.5_fx),
                  v3(0.5_fx, 0.005_fx, -0.5_fx)},
                 -0.01_fx, ulps(2), ulps(2));
  // Edge-edge apart by 3 cm (beyond) and 1 cm (within).
  const Placed a = place(cube_shape(0.5_fx), Vec3::zero(), about(x_axis, quarter_pi));
  CHECK(run(a, place(cube_shape(0.5_fx), v3({}, sqrt2 + 0.03_fx, {}), about(z_axis, quarter_pi))).point_count == 0);
  const Manifold e = run(a, place(cube_shape(0.5_fx), v3({}, sqrt2 + 0.01_fx, {}), about(z_axis, quarter_pi)));
  REQUIRE(e.point_count == 1);
  CHECK(near(e.points[0].depth, -0.01_fx, rotation_tolerance));
  // Far apart sideways (world envelope corner): nothing, no overflow.
  CHECK(run(place(cube_shape(50_fx), v3(-16000_fx, -16000_fx, 16000_fx)),
            place(cube_shape(50_fx), v3(16000_fx, 16000_fx, -16000_fx)))
            .point_count == 0);
}

TEST_CASE("box-box: swapping the boxes flips the normal and keeps the points", "[collide]") {
  const Placed cube = place(cube_shape(0.5_fx), v3({}, 0.49_fx, {}));
  require_swap_consistent(ground_box, cube, ulps(4));
  require_swap_consistent(ground_box, place(cube_shape(0.5_fx), v3({}, 0.5_fx, {}), about(y_axis, quarter_pi)),
                          rotation_tolerance);
  require_swap_consistent(ground_box, place(cube_shape(0.5_fx), v3({}, half_sqrt2, {}), about(z_axis, quarter_pi)),
                          rotation_tolerance);
}

TEST_CASE("box-box feature ids: identical input gives identical bits, a 1 mm move keeps the ids", "[collide]") {
  struct Scene {
    const char* name;
    Placed a, b;
  };
  const Scene scenes[] = {
      {"resting", ground_box, place(cube_shape(0.5_fx), v3({}, 0.499_fx, {}))},
      {"rotated 45", ground_box, place(cube_shape(0.5_fx), v3({}, 0.499_fx, {}), about(y_axis, quarter_pi))},
      {"rotated 10, overhanging", place(cube_shape(0.5_fx), Vec3::zero()),
       place(box_shape(0.4_fx, 0.5_fx, 0.3_fx), v3(0.3_fx, 0.998_fx, 0.1_fx), about(y_axis, 0.1745_fx))},
      {"octagon reduced to 4", place(cube_shape(0.5_fx), Vec3::zero()),
       place(cube_shape(0.5_fx), v3({}, 0.995_fx, {}), about(y_axis, 0.7_fx))},
      {"on an edge", ground_box, place(cube_shape(0.5_fx), v3({}, half_sqrt2, {}), about(z_axis, quarter_pi))},
      {"edge-edge", place(cube_shape(0.5_fx), Vec3::zero(), about(x_axis, quarter_pi)),
       place(cube_shape(0.5_fx), v3({}, sqrt2 - 0.01_fx, {}), about(z_axis, quarter_pi))},
  };
  for (const Scene& s : scenes) {
    INFO(s.name);
    const Manifold m = run(s.a, s.b);
    INFO(describe(m));
    REQUIRE(m.point_count > 0);
    CHECK(identical(m, run(s.a, s.b)));
    Placed moved = s.b;
    moved.pose.position += v3(0.001_fx, -0.001_fx, 0.001_fx);
    const Manifold after = run(s.a, moved);
    INFO("after a 1 mm move: " << describe(after));
    CHECK(sorted_features(m) == sorted_features(after));
    for (int i = 0; i < m.point_count; ++i) {  // the same id names nearly the same point
      for (int j = 0; j < after.point_count; ++j) {
        if (m.points[static_cast<size_t>(i)].feature == after.points[static_cast<size_t>(j)].feature) {
          CHECK(length(m.points[static_cast<size_t>(i)].position - after.points[static_cast<size_t>(j)].position) <
                0.003_fx);
        }
      }
    }
    std::vector<FeatureId> f = sorted_features(m);
    CHECK(std::adjacent_find(f.begin(), f.end()) == f.end());  // distinct within a manifold
  }
}

TEST_CASE("box on a plane: the bottom corners, on a tilted plane too", "[collide]") {
  const Placed cube = place(cube_shape(0.5_fx), v3({}, 0.5_fx, {}));
  const std::vector<Vec3> corners{v3(0.5_fx, {}, 0.5_fx), v3(-0.5_fx, {}, 0.5_fx), v3(-0.5_fx, {}, -0.5_fx),
                                  v3(0.5_fx, {}, -0.5_fx)};
  const Manifold m = run(cube, ground_plane);
  CHECK(m.normal == -y_axis);
  require_points(m, corners, Fixed{}, Fixed{}, Fixed{});
  const Manifold flipped = run(ground_plane, cube);
  CHECK(flipped.normal == y_axis);
  require_points(flipped, corners, Fixed{}, Fixed{}, Fixed{});

  SECTION("a plane tilted 30 degrees about z, the box resting on it 1 cm deep") {
    const Quat tilt = about(z_axis, 0.52359877559829887308_fx);
    const Vec3 n = rotate(tilt, y_axis);  // (-1/2, sqrt3/2, 0)
    const Placed slope = place(plane_shape(), v3(3_fx, 2_fx, 1_fx), tilt);
    const Placed box = place(cube_shape(0.5_fx), v3(3_fx, 2_fx, 1_fx) + n * 0.49_fx, tilt);
    const Manifold s = run(slope, box);
    CHECK(near(s.normal, n, ulps(4)));
    std::vector<Vec3> expected;
    for (Fixed x : {0.5_fx, -0.5_fx}) {
      for (Fixed z : {0.5_fx, -0.5_fx}) expected.push_back(v3(3_fx, 2_fx, 1_fx) + rotate(tilt, v3(x, -0.005_fx, z)));
    }
    require_points(s, expected, 0.01_fx, rotation_tolerance, rotation_tolerance);
    require_swap_consistent(slope, box, Fixed{});
  }
  SECTION("tilted box: only the corners within the speculative distance") {
    const Placed tilted = place(cube_shape(0.5_fx), v3({}, half_sqrt2 - 0.001_fx, {}), about(z_axis, quarter_pi));
    const Manifold t = run(tilted, ground_plane);
    require_points(t, {v3({}, -0.0005_fx, 0.5_fx), v3({}, -0.0005_fx, -0.5_fx)}, 0.001_fx, rotation_tolerance,
                   rotation_tolerance);
  }
}

TEST_CASE("spheres on a plane, a box and a sphere: analytic depth, normal and point", "[collide]") {
  const Placed ball = place(sphere_shape(0.5_fx), v3(1_fx, 0.4_fx, 2_fx));
  SECTION("plane") {
    const Manifold m = run(ball, ground_plane);
    CHECK(m.normal == -y_axis);
    require_points(m, {v3(1_fx, -0.05_fx, 2_fx)}, 0.1_fx, Fixed{}, Fixed{});
    require_swap_consistent(ball, ground_plane, Fixed{});
    CHECK(run(place(sphere_shape(0.5_fx), v3({}, 0.53_fx, {})), ground_plane).point_count == 0);
  }
  SECTION("box face") {
    const Manifold m = run(ground_box, place(sphere_shape(0.5_fx), v3(1_fx, 0.49_fx, 2_fx)));
    CHECK(m.normal == y_axis);
    require_points(m, {v3(1_fx, -0.005_fx, 2_fx)}, 0.01_fx, Fixed{}, Fixed{});
  }
  SECTION("box edge: the normal points from the edge to the centre") {
    // Edge of a unit box at x = y = 0.5; the centre 0.3, 0.4 beyond it: distance 0.5.
    const Placed box = place(cube_shape(0.5_fx), Vec3::zero());
    const Manifold m = run(place(sphere_shape(0.6_fx), v3(0.8_fx, 0.9_fx, 0.1_fx)), box);
    CHECK(near(m.normal, v3(-0.6_fx, -0.8_fx, {}), ulps(2)));
    require_points(m, {v3(0.5_fx - 0.03_fx, 0.5_fx - 0.04_fx, 0.1_fx)}, 0.1_fx, ulps(4), ulps(4));
    require_swap_consistent(box, place(sphere_shape(0.6_fx), v3(0.8_fx, 0.9_fx, 0.1_fx)), Fixed{});
  }
  SECTION("centre inside the box: pushed out through the nearest face") {
    const Manifold m =
        run(place(cube_shape(0.5_fx), Vec3::zero()), place(sphere_shape(0.2_fx), v3(0.1_fx, 0.4_fx, {})));
    CHECK(m.normal == y_axis);
    // face at 0.5, sphere's far surface at 0.2 below the centre (0.2): depth 0.3
    require_points(m, {v3(0.1_fx, 0.35_fx, {})}, 0.3_fx, ulps(2), Fixed{});
  }
  SECTION("rotated box") {
    const Placed box = place(cube_shape(0.5_fx), Vec3::zero(), about(z_axis, quarter_pi));  // a corner edge up
    const Manifold m = run(box, place(sphere_shape(0.25_fx), v3({}, half_sqrt2 + 0.2_fx, 0.3_fx)));
    CHECK(near(m.normal, y_axis, ulps(2)));
    require_points(m, {v3({}, half_sqrt2 - 0.025_fx, 0.3_fx)}, 0.05_fx, rotation_tolerance, rotation_tolerance);
  }
  SECTION("sphere") {
    // Radii 0.5 and 0.3, centres 0.7 apart along (0.6, 0.8, 0): depth 0.1.
    const Placed a = place(sphere_shape(0.5_fx), v3(10_fx, {}, {}));
    const Placed b = place(sphere_shape(0.3_fx), v3(10.42_fx, 0.56_fx, {}));
    const Manifold m = run(a, b);
    CHECK(near(m.normal, v3(0.6_fx, 0.8_fx, {}), ulps(2)));
    require_points(m, {v3(10_fx + 0.27_fx, 0.36_fx, {})}, 0.1_fx, ulps(4), ulps(4));
    require_swap_consistent(a, b, ulps(4));
    const Manifold same = run(a, a);  // concentric: a fixed direction
    CHECK(same.normal == y_axis);
  }
}

TEST_CASE("capsules on a box: lying gives two points, standing one", "[collide]") {
  const Placed table = place(box_shape(2_fx, 0.5_fx, 2_fx), Vec3::zero());
  const Quat lying = about(z_axis, 1.57079632679489661923_fx);  // axis along -x
  SECTION("lying") {
    const Placed log = place(capsule_shape(1_fx, 0.25_fx), v3(0.2_fx, 0.745_fx, 0.1_fx), lying);
    const Manifold m = run(log, table);
    CHECK(near(m.normal, -y_axis, ulps(2)));
    require_points(m, {v3(1.2_fx, 0.4975_fx, 0.1_fx), v3(-0.8_fx, 0.4975_fx, 0.1_fx)}, 0.005_fx, rotation_tolerance,
                   rotation_tolerance);
    require_swap_consistent(log, table, Fixed{});
  }
  SECTION("lying over the table's edge: the second point at the edge") {
    const Placed log = place(capsule_shape(1_fx, 0.25_fx), v3(1.5_fx, 0.745_fx, {}), lying);
    require_points(run(table, log), {v3(2_fx, 0.4975_fx, {}), v3(0.5_fx, 0.4975_fx, {})}, 0.005_fx, rotation_tolerance,
                   rotation_tolerance);
  }
  SECTION("standing") {
    const Placed post = place(capsule_shape(1_fx, 0.25_fx), v3(0.3_fx, 1.74_fx, {}));
    const Manifold m = run(table, post);
    CHECK(m.normal == y_axis);
    require_points(m, {v3(0.3_fx, 0.495_fx, {})}, 0.01_fx, ulps(2), ulps(2));
  }
  SECTION("tilted 30 degrees: one point at the lower end") {
    const Quat tilt = about(z_axis, 0.52359877559829887308_fx);
    const Vec3 lower_end = rotate(tilt, v3({}, -1_fx, {}));
    const Placed post = place(capsule_shape(1_fx, 0.25_fx), v3({}, 0.74_fx, {}) - lower_end, tilt);
    const Manifold m = run(post, table);
    CHECK(near(m.normal, -y_axis, ulps(2)));
    require_points(m, {v3({}, 0.495_fx, {})}, 0.01_fx, rotation_tolerance, rotation_tolerance);
  }
  SECTION("end against a box edge: the normal from the edge") {
    // Segment end 0.3, 0.4 beyond the edge x = 2, y = 0.5, axis along x.
    const Placed log = place(capsule_shape(1_fx, 0.6_fx), v3(3.3_fx, 0.9_fx, {}), lying);
    const Manifold m = run(log, table);
    CHECK(near(m.normal, v3(-0.6_fx, -0.8_fx, {}), rotation_tolerance));
    require_points(m, {v3(2_fx - 0.03_fx, 0.5_fx - 0.04_fx, {})}, 0.1_fx, rotation_tolerance, rotation_tolerance);
  }
  SECTION("segment through the box") {
    const Placed post = place(capsule_shape(1_fx, 0.25_fx), v3(0.3_fx, 1.2_fx, {}));
    const Manifold m = run(table, post);
    CHECK(m.normal == y_axis);
    require_points(m, {v3(0.3_fx, 0.5_fx - 0.275_fx, {})}, 0.55_fx, ulps(2), ulps(2));
  }
}

// A forearm resting across a stair's edge, tilted by a hair one way or the
// other. Tilted outward, the segment's closest point to the box lies beyond
// the edge, in the edge's region, which gave one point at the edge; tilted
// inward the face clipped it to two (the inner end and the edge). A resting
// ragdoll's forearm flipped between the two every few steps, lost the
// inner point's impulse each time and swung. Within ~1.15 degrees of a face
// normal the edge's point is joined by the segment's ends over that face:
// the inner end is a point either way, under the same feature id. Tilted
// further, it rests on the edge alone.
TEST_CASE("a capsule lying across a box's edge: its inner end a point whichever way it tilts", "[collide]") {
  const Placed stair = place(box_shape(0.25_fx, 0.25_fx, 2.0_fx), Vec3::zero());
  const Fixed degree = 0.017453292519943295_fx;
  const Fixed r = 0.04_fx, h = 0.1_fx;
  // The segment crosses the edge x = 0.25, y = 0.25 at its middle, along x,
  // its surface 0.01 mm into the stair there; a positive tilt lowers its
  // inner end.
  const auto across_edge = [&](Fixed tilt_degrees) {
    const Quat pose = about(z_axis, 1.57079632679489661923_fx + tilt_degrees * degree);  // +y turned onto -x, tilted
    return place(capsule_shape(h, r), v3(0.25_fx, 0.25_fx + r - 0.00001_fx, {}), pose);
  };
  FeatureId inner_feature = 0;
  for (const Fixed tilt : {-1.0_fx, -0.01_fx, 0.01_fx, 1.0_fx}) {
    const Placed forearm = across_edge(tilt);
    const Manifold m = run(stair, forearm);
    INFO("tilted " << tilt << " degrees: " << describe(m));
    REQUIRE(m.point_count == 2);
    CHECK(near(m.normal, y_axis, 0.02_fx));  // from the stair to the forearm, within the tilt
    const size_t in = m.points[0].position.x < m.points[1].position.x ? 0 : 1;
    CHECK(near(m.points[in].position.x, 0.25_fx - h, 0.001_fx));  // the segment's end over the face
    CHECK(near(m.points[1 - in].position.x, 0.25_fx, 0.0001_fx));  // the edge
    // The edge's depth exact either way: over the face 0.01 mm, beyond it
    // along the edge's normal r - (r - 0.01 mm) cos(tilt).
    const Fixed angle = tilt * degree;
    const Fixed edge_depth =
        tilt > Fixed{} ? 0.00001_fx : r - (r - 0.00001_fx) * (Fixed::one() - angle * angle * 0.5_fx);
    CHECK(near(m.points[1 - in].depth, edge_depth, 0.000001_fx));
    CHECK(abs(m.points[in].depth) < 0.002_fx);
    if (tilt == -1.0_fx) inner_feature = m.points[in].feature;
    CHECK(m.points[in].feature == inner_feature);
    require_swap_consistent(stair, forearm, rotation_tolerance);
  }
  SECTION("tilted 3 degrees outward: the edge alone, its normal tilted with the forearm") {
    const Manifold m = run(stair, across_edge(-3.0_fx));
    INFO(describe(m));
    REQUIRE(m.point_count == 1);
    CHECK(abs(m.normal.x) > 0.05_fx);  // sin 3 degrees = 0.052
    CHECK(near(m.points[0].position.x, 0.25_fx, 0.001_fx));
  }
}

TEST_CASE("capsule-capsule crossing and parallel, capsule-sphere, capsule-plane", "[collide]") {
  const Quat along_x = about(z_axis, 1.57079632679489661923_fx), along_z = about(x_axis, 1.57079632679489661923_fx);
  const Placed a = place(capsule_shape(1_fx, 0.25_fx), Vec3::zero(), along_x);
  SECTION("crossing") {
    const Placed b = place(capsule_shape(1_fx, 0.25_fx), v3({}, 0.45_fx, {}), along_z);
    const Manifold m = run(a, b);
    CHECK(near(m.normal, y_axis, ulps(2)));
    require_points(m, {v3({}, 0.225_fx, {})}, 0.05_fx, rotation_tolerance, rotation_tolerance);
    require_swap_consistent(a, b, rotation_tolerance);
  }
  SECTION("parallel, overlapping from x = -0.5 to 1") {
    const Placed b = place(capsule_shape(1_fx, 0.25_fx), v3(0.5_fx, 0.45_fx, {}), along_x);
    const Manifold m = run(a, b);
    CHECK(near(m.normal, y_axis, ulps(2)));
    require_points(m, {v3(-0.5_fx, 0.225_fx, {}), v3(1_fx, 0.225_fx, {})}, 0.05_fx, rotation_tolerance,
                   rotation_tolerance);
    require_swap_consistent(a, b, rotation_tolerance);
  }
  SECTION("sphere beside a standing capsule") {
    const Placed post = place(capsule_shape(1_fx, 0.25_fx), Vec3::zero());
    const Placed ball = place(sphere_shape(0.3_fx), v3(0.5_fx, 0.3_fx, {}));
    const Manifold m = run(post, ball);
    CHECK(m.normal == x_axis);
    require_points(m, {v3(0.225_fx, 0.3_fx, {})}, 0.05_fx, Fixed{}, Fixed{});
    require_swap_consistent(post, ball, Fixed{});
    // on top: the end cap
    const Manifold top = run(place(sphere_shape(0.3_fx), v3({}, 1.5_fx, {})), post);
    CHECK(top.normal == -y_axis);
    require_points(top, {v3({}, 1.225_fx, {})}, 0.05_fx, Fixed{}, Fixed{});
  }
  SECTION("plane: lying two points, standing one") {
    const Placed lying = place(capsule_shape(1_fx, 0.25_fx), v3({}, 0.24_fx, {}), along_x);
    const Manifold m = run(lying, ground_plane);
    CHECK(m.normal == -y_axis);
    require_points(m, {v3(1_fx, -0.005_fx, {}), v3(-1_fx, -0.005_fx, {})}, 0.01_fx, rotation_tolerance, ulps(4));
    require_swap_consistent(lying, ground_plane, Fixed{});
    const Manifold standing = run(ground_plane, place(capsule_shape(1_fx, 0.25_fx), v3({}, 1.24_fx, {})));
    CHECK(standing.normal == y_axis);
    require_points(standing, {v3({}, -0.005_fx, {})}, 0.01_fx, ulps(2), ulps(2));  // 1.24 - 1 != 0.24 in ulps
  }
}

TEST_CASE("every pair of shape types in both orders gives the flipped normal and the same points", "[collide]") {
  const Shape shapes[] = {plane_shape(), box_shape(0.5_fx, 0.3_fx, 0.4_fx), sphere_shape(0.4_fx),
                          capsule_shape(0.5_fx, 0.3_fx)};
  const Quat qa = normalize(Quat{0.9_fx, 0.1_fx, 0.3_fx, -0.2_fx}),
             qb = normalize(Quat{0.7_fx, -0.4_fx, 0.2_fx, 0.5_fx});
  for (const Shape& sa : shapes) {
    for (const Shape& sb : shapes) {
      if (sa.type == ShapeType::plane && sb.type == ShapeType::plane) {
        CHECK(run(place(sa, Vec3::zero()), place(sb, Vec3::zero())).point_count == 0);
        continue;
      }
      const Placed a = place(sa, v3(100_fx, 5_fx, -200_fx), sa.type == ShapeType::plane ? Quat::identity() : qa);
      const Placed b = place(sb, v3(100.1_fx, 5.3_fx, -199.95_fx), sb.type == ShapeType::plane ? Quat::identity() : qb);
      INFO("types " << static_cast<int>(sa.type) << ", " << static_cast<int>(sb.type));
      const Manifold ab = run(a, b), ba = run(b, a);
      INFO(describe(ab) << "\n" << describe(ba));
      REQUIRE(ab.point_count > 0);
      REQUIRE(ab.point_count == ba.point_count);
      if (sa.type != sb.type) {  // the same pair function: exactly the same bits, normal negated
        CHECK(ab.normal == -ba.normal);
        CHECK(identical(ab, Manifold{-ba.normal, ba.point_count, ba.points, {}, {}, {}}));
      } else {
        CHECK(near(ab.normal, -ba.normal, rotation_tolerance));
        CHECK(same_points(ab, ba, rotation_tolerance));
      }
    }
  }
}

TEST_CASE("random poses: unit normals, at most 4 points, deterministic, no overflow", "[collide]") {
  // Sizes across the envelope (0.01 .. 50 m), positions anywhere within
  // +-16 km, the second shape near the first. Runs in the checked build too,
  // where any overflow in the narrowphase aborts.
  SplitMix64 random{0x636f6c6c696465u};
  auto uniform = [&](Fixed lo, Fixed hi) {                                          // uniform in [lo, hi]
    const Fixed unit = Fixed::from_raw(static_cast<int64_t>(random.next() >> 32));  // [0, 1)
    return lo + (hi - lo) * unit;
  };
  auto size = [&] {
    const Fixed scales[] = {0.01_fx, 0.1_fx, 1_fx, 10_fx, 50_fx};
    const int s = random.below(4);
    return uniform(scales[s], scales[s + 1]);
  };
  auto shape = [&](bool allow_plane) {
    const int type = random.below(allow_plane ? 5 : 4) + (allow_plane ? 0 : 1);
    Shape s;
    s.type = static_cast<ShapeType>(type);
    s.half_extents = {size(), size(), size()};
    s.radius = size();
    s.half_height = random.below(8) == 0 ? Fixed{} : size();
    if (s.type == ShapeType::hull) {  // a box's corners, pulled in at one end: a wedge-like hull
      const Vec3 h = s.half_extents;
      std::vector<Vec3> corners;
      for (int k = 0; k < 8; ++k) {
        const Fixed taper = (k & 2) != 0 ? 0.5_fx : 1_fx;
        corners.push_back(
            {(k & 1) != 0 ? h.x * taper : -h.x * taper, (k & 2) != 0 ? h.y : -h.y, (k & 4) != 0 ? h.z : -h.z});
      }
      auto built = build_convex_hull(corners);
      if (!built.ok()) FAIL(built.error().message());
      s.hull = built.value();
    }
    return s;
  };
  auto orientation = [&] {
    return normalize(Quat{uniform(-1_fx, 1_fx), uniform(-1_fx, 1_fx), uniform(-1_fx, 1_fx), uniform(-1_fx, 1_fx)});
  };
  auto reach = [](const Shape& s) {  // bounding radius
    switch (s.type) {
      case ShapeType::box: return s.half_extents.x + s.half_extents.y + s.half_extents.z;
      case ShapeType::sphere: return s.radius;
      case ShapeType::capsule: return s.half_height + s.radius;
      case ShapeType::plane: return Fixed{};
      case ShapeType::hull: return s.hull->extent;
      case ShapeType::mesh:
      case ShapeType::heightfield: return Fixed{};  // not made here
    }
    return Fixed{};
  };
  int contacts = 0, points = 0;
  for (int i = 0; i < 20000; ++i) {
    const Shape sa = shape(true), sb = shape(i % 2 == 0);
    const Fixed r = (reach(sa) + reach(sb)) * 1.1_fx;
    const Vec3 base{uniform(-15800_fx, 15800_fx), uniform(-15800_fx, 15800_fx), uniform(-15800_fx, 15800_fx)};
    const Vec3 offset{uniform(-r, r), uniform(-r, r), uniform(-r, r)};
    const Placed a = place(sa, base, orientation()), b = place(sb, base + offset, orientation());
    const Fixed speculative = random.below(2) == 0 ? spec : Fixed{};
    Manifold ab, ab_again, ba;
    const int n = collide(a.world(), b.world(), speculative, ab);
    collide(a.world(), b.world(), speculative, ab_again);
    const int n_swapped = collide(b.world(), a.world(), speculative, ba);
    REQUIRE_QUIETLY((n >= 0 && n <= max_manifold_points && n == ab.point_count), "count " << n);
    REQUIRE_QUIETLY(identical(ab, ab_again), "not deterministic: " << describe(ab));
    REQUIRE_QUIETLY((n == n_swapped || sa.type == sb.type), "swapped count differs, case " << i << "\n"
                                                                                           << describe(ab) << "\n"
                                                                                           << describe(ba));
    if (n == 0) continue;
    ++contacts;
    points += n;
    const Fixed norm_error = abs(length_sq(ab.normal) - Fixed::one());
    REQUIRE_QUIETLY(norm_error <= ulps(4), "normal " << ab.normal << " |n|^2 - 1 = " << norm_error.raw() << " ulp");
    for (int p = 0; p < n; ++p) {
      const ContactPoint& c = ab.points[static_cast<size_t>(p)];
      REQUIRE_QUIETLY(c.depth > -speculative, "depth " << c.depth);
      // Points lie near both shapes: within their bounding spheres plus the depth.
      REQUIRE_QUIETLY(
          (sa.type == ShapeType::plane || length(c.position - a.pose.position) <= reach(sa) + abs(c.depth) + 0.001_fx),
          "point far from a: " << describe(ab));
    }
    if (sa.type != sb.type) {
      REQUIRE_QUIETLY(((ab.normal == -ba.normal) && identical(ab, Manifold{-ba.normal, ba.point_count, ba.points, {}, {}, {}})),
                      "swap changed the points:\n"
                          << describe(ab) << "\n"
                          << describe(ba));
    }
  }
  INFO(contacts << " contacts, " << points << " points");
  CHECK(contacts > 5000);
}
