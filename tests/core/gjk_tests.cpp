// GJK's distance between convex shapes (core/gjk.h) against exact answers
// computed apart in double precision: the closest points of spheres,
// capsules and boxes placed and turned at random, separated and
// overlapping. A pair of polytopes' distance is the least of its
// vertex-to-solid and edge-to-edge distances; a capsule's is its segment's
// less its radius.
#include <catch2/catch.hpp>

#include <algorithm>
#include <array>
#include <cmath>
#include <vector>

#include "core/gjk.h"
#include "core/shape_types.h"
#include "fixed/mat33.h"
#include "fixed/quat.h"
#include "fixed/splitmix64.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::to_double;

namespace {

struct D3 {
  double x, y, z;
};
D3 operator+(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
D3 operator*(D3 a, double s) { return {a.x * s, a.y * s, a.z * s}; }
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
double norm(D3 a) { return std::sqrt(dot(a, a)); }
D3 of(Vec3 v) { return {to_double(v.x), to_double(v.y), to_double(v.z)}; }

// Ericson 5.1.9: the distance between segments p1q1 and p2q2.
double segment_distance(D3 p1, D3 q1, D3 p2, D3 q2) {
  const D3 d1 = q1 - p1, d2 = q2 - p2, r = p1 - p2;
  const double a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r);
  double s = 0, t = 0;
  if (a <= 1e-18 && e <= 1e-18) return norm(p1 - p2);
  if (a <= 1e-18) {
    t = std::clamp(f / e, 0.0, 1.0);
  } else {
    const double c = dot(d1, r);
    if (e <= 1e-18) {
      s = std::clamp(-c / a, 0.0, 1.0);
    } else {
      const double b = dot(d1, d2), denom = a * e - b * b;
      s = denom > 1e-18 ? std::clamp((b * f - c * e) / denom, 0.0, 1.0) : 0.0;
      t = (b * s + f) / e;
      if (t < 0) {
        t = 0;
        s = std::clamp(-c / a, 0.0, 1.0);
      } else if (t > 1) {
        t = 1;
        s = std::clamp((b - c) / a, 0.0, 1.0);
      }
    }
  }
  return norm((p1 + d1 * s) - (p2 + d2 * t));
}

// A box as its centre, axes and half extents, in double.
struct DBox {
  D3 centre;
  std::array<D3, 3> axis;
  D3 half;
  double h(int i) const { return i == 0 ? half.x : i == 1 ? half.y : half.z; }
  D3 corner(int k) const {
    D3 p = centre;
    for (int i = 0; i < 3; ++i) p = p + axis[static_cast<size_t>(i)] * (((k >> i) & 1) != 0 ? h(i) : -h(i));
    return p;
  }
  // Distance from a point to the solid box (0 inside).
  double to(D3 p) const {
    double sq = 0;
    for (int i = 0; i < 3; ++i) {
      const double along = dot(p - centre, axis[static_cast<size_t>(i)]);
      const double out = std::max(std::abs(along) - h(i), 0.0);
      sq += out * out;
    }
    return std::sqrt(sq);
  }
  // Whether segment pq meets the solid box (slabs in its axes).
  bool hit(D3 p, D3 q) const {
    double near = 0, far = 1;
    for (int i = 0; i < 3; ++i) {
      const D3& u = axis[static_cast<size_t>(i)];
      const double o = dot(p - centre, u), d = dot(q - p, u);
      if (std::abs(d) < 1e-15) {
        if (std::abs(o) > h(i)) return false;
        continue;
      }
      double t0 = (-h(i) - o) / d, t1 = (h(i) - o) / d;
      if (t0 > t1) std::swap(t0, t1);
      near = std::max(near, t0);
      far = std::min(far, t1);
      if (near > far) return false;
    }
    return true;
  }
  // Its 12 edges as corner index pairs.
  std::vector<std::pair<D3, D3>> edges() const {
    std::vector<std::pair<D3, D3>> e;
    for (int k = 0; k < 8; ++k) {
      for (int i = 0; i < 3; ++i) {
        if (((k >> i) & 1) == 0) e.push_back({corner(k), corner(k | (1 << i))});
      }
    }
    return e;
  }
};

DBox dbox(const WorldShape& s) {
  const Mat33 r = rotation(s.pose.orientation);
  return {of(s.pose.position), {of(r.column(0)), of(r.column(1)), of(r.column(2))}, of(s.shape->half_extents)};
}

// A segment of a capsule, or a sphere's centre twice.
std::pair<D3, D3> dsegment(const WorldShape& s) {
  const Vec3 half = rotate(s.pose.orientation, Vec3{Fixed{}, s.shape->half_height, Fixed{}});
  return {of(s.pose.position - half), of(s.pose.position + half)};
}

// The exact distance between the shapes' cores (0 when they meet), and
// their radii.
struct Exact {
  double cores, radii;
};
Exact exact_distance(const WorldShape& a, const WorldShape& b) {
  const bool a_box = a.shape->type == ShapeType::box, b_box = b.shape->type == ShapeType::box;
  const double ra = a_box ? 0 : to_double(a.shape->radius), rb = b_box ? 0 : to_double(b.shape->radius);
  if (!a_box && !b_box) {
    const auto [p1, q1] = dsegment(a);
    const auto [p2, q2] = dsegment(b);
    return {segment_distance(p1, q1, p2, q2), ra + rb};
  }
  if (a_box && b_box) {
    const DBox x = dbox(a), y = dbox(b);
    for (const auto& [p, q] : x.edges()) {
      if (y.hit(p, q)) return {0, 0};
    }
    for (const auto& [p, q] : y.edges()) {
      if (x.hit(p, q)) return {0, 0};
    }
    double best = 1e300;
    for (int k = 0; k < 8; ++k) best = std::min({best, y.to(x.corner(k)), x.to(y.corner(k))});
    for (const auto& [p, q] : x.edges()) {
      for (const auto& [u, w] : y.edges()) best = std::min(best, segment_distance(p, q, u, w));
    }
    return {best, 0};
  }
  // A segment (or point) and a box: its ends to the box, and it to each edge.
  const DBox x = dbox(a_box ? a : b);
  const auto [p, q] = dsegment(a_box ? b : a);
  if (x.hit(p, q)) return {0, ra + rb};
  double best = std::min(x.to(p), x.to(q));
  for (const auto& [u, w] : x.edges()) best = std::min(best, segment_distance(p, q, u, w));
  return {best, ra + rb};
}

Fixed fixed_of(double d) { return Fixed::from_raw(static_cast<int64_t>(std::llround(d * 4294967296.0))); }

Quat random_orientation(SplitMix64& random) {
  const auto component = [&] { return Fixed::from_raw(static_cast<int64_t>(random.next() % (uint64_t{1} << 33)) - (int64_t{1} << 32)); };
  return normalize(Quat{component(), component(), component(), component()});
}

Shape random_shape(SplitMix64& random, ShapeType type) {
  const auto size = [&] { return fixed_of(0.1 + 1.4 * static_cast<double>(random.next() % 1000) / 1000.0); };
  Shape s;
  s.type = type;
  if (type == ShapeType::box) s.half_extents = {size(), size(), size()};
  if (type != ShapeType::box) s.radius = size();
  if (type == ShapeType::capsule) s.half_height = size();
  return s;
}

Vec3 random_position(SplitMix64& random, double spread) {
  const auto c = [&] { return fixed_of(spread * (static_cast<double>(random.next() % 2001) / 1000.0 - 1.0)); };
  return {c(), c(), c()};
}

}  // namespace

TEST_CASE("GJK: the distance between spheres, capsules and boxes placed at random, against the exact one", "[gjk]") {
  SplitMix64 random{2024};
  const ShapeType types[] = {ShapeType::sphere, ShapeType::capsule, ShapeType::box};
  int separated = 0, overlapping = 0;
  double worst = 0;
  for (const ShapeType ta : types) {
    for (const ShapeType tb : types) {
      for (int round = 0; round < 300; ++round) {
        const Shape sa = random_shape(random, ta), sb = random_shape(random, tb);
        // Far from the world's origin as well: GJK works about A's centre.
        const Vec3 base = round % 3 == 0 ? Vec3{fixed_of(12000.5), fixed_of(-800.25), fixed_of(3000)} : Vec3{};
        const WorldShape a{&sa, {base + random_position(random, 0.5), random_orientation(random)}};
        const WorldShape b{&sb, {base + random_position(random, round % 2 == 0 ? 4.0 : 1.5), random_orientation(random)}};
        const Exact exact = exact_distance(a, b);
        const ConvexDistance found = convex_distance(a, b);
        INFO(shape_name(ta) << " - " << shape_name(tb) << ", round " << round << ": exact cores " << exact.cores
                            << ", found " << to_double(found.distance) << " less radii " << exact.radii << " in "
                            << found.iterations << " iterations");
        CHECK(found.iterations <= 32);
        if (exact.cores == 0) {  // the cores meet
          CHECK(found.overlap);
          ++overlapping;
          continue;
        }
        if (exact.cores < 1e-3) continue;  // touching within a millimetre: either answer
        REQUIRE_FALSE(found.overlap);
        ++separated;
        const double error = std::abs(to_double(found.distance) - (exact.cores - exact.radii));
        worst = std::max(worst, error);
        CHECK(error < 1e-5);
        // The witness points: their gap is the distance, along the normal
        // (through each other when the radii overlap).
        const D3 gap = of(found.point_b) - of(found.point_a);
        CHECK(std::abs(dot(gap, of(found.normal)) - (exact.cores - exact.radii)) < 1e-4);
        CHECK(std::abs(norm(of(found.normal)) - 1.0) < 1e-6);
      }
    }
  }
  INFO("worst error " << worst << " m, " << separated << " separated, " << overlapping << " overlapping");
  CHECK(separated > 1000);
  CHECK(overlapping > 100);
}

TEST_CASE("GJK: analytic cases and the same bits every time", "[gjk]") {
  const Shape unit_box{ShapeType::box, {Fixed::one(), Fixed::one(), Fixed::one()}, {}, {}, {}};
  const Shape ball{ShapeType::sphere, {}, fixed_of(0.5), {}, {}};
  // A ball 3 m above a box's top face: 3 - 1 - 0.5 = 1.5 m, straight down.
  const WorldShape box_at_origin{&unit_box, {}};
  const WorldShape ball_above{&ball, {{Fixed{}, fixed_of(3), Fixed{}}, {}}};
  const ConvexDistance d = convex_distance(box_at_origin, ball_above);
  CHECK(d.distance == fixed_of(1.5));
  CHECK(d.normal == Vec3{Fixed{}, Fixed::one(), Fixed{}});
  CHECK(d.point_a.y == Fixed::one());
  CHECK(d.point_b.y == fixed_of(2.5));
  // Beyond a corner: sqrt(3) (2 - 1) - 0.5 from (2, 2, 2).
  const WorldShape ball_corner{&ball, {{fixed_of(2), fixed_of(2), fixed_of(2)}, {}}};
  CHECK(std::abs(to_double(convex_distance(box_at_origin, ball_corner).distance) - (std::sqrt(3.0) - 0.5)) < 1e-8);
  // A ball inside the box: the cores meet.
  const WorldShape ball_inside{&ball, {{fixed_of(0.25), Fixed{}, Fixed{}}, {}}};
  CHECK(convex_distance(box_at_origin, ball_inside).overlap);
  // Two boxes turned 45 degrees about y, 3 m apart on x: 3 - sqrt(2) - 1.
  const Quat turned = from_axis_angle({Fixed{}, Fixed::one(), Fixed{}}, fixed_of(0.7853981633974483));
  const WorldShape diamond{&unit_box, {{fixed_of(3), Fixed{}, Fixed{}}, turned}};
  const ConvexDistance boxes = convex_distance(box_at_origin, diamond);
  CHECK(std::abs(to_double(boxes.distance) - (3 - std::sqrt(2.0) - 1)) < 1e-7);
  // Run again: the same bits.
  const ConvexDistance again = convex_distance(box_at_origin, diamond);
  CHECK((again.distance == boxes.distance && again.point_a == boxes.point_a && again.normal == boxes.normal));
}
