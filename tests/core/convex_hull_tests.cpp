// The hull builder (core/convex_hull.h) against exact answers: boxes,
// tetrahedra and octahedra whose volume, centroid and inertia are known in
// closed form (rounded once, so equal to the bit), and random clouds checked
// in double precision: every input point inside every face's plane, the faces
// closing into a convex polyhedron (Euler, twin edges, convex
// counter-clockwise loops), the mass properties against a tetrahedron sum in
// double over the output's own faces, and the rebuild from the hull's
// vertices giving the same hull to the bit.
#include <algorithm>
#include <array>
#include <catch2/catch.hpp>
#include <cmath>
#include <string>
#include <vector>

#include "core/convex_hull.h"
#include "fixed/splitmix64.h"
#include "tests/test_support.h"

using namespace bitstep;
using bitstep::test::to_double;

// REQUIRE_QUIETLY of any expression (Catch2 decomposes only a plain comparison).
#define HULL_REQUIRE(condition, message) REQUIRE_QUIETLY((condition), message)

namespace {

struct D3 {
  double x, y, z;
};
D3 operator+(D3 a, D3 b) { return {a.x + b.x, a.y + b.y, a.z + b.z}; }
D3 operator-(D3 a, D3 b) { return {a.x - b.x, a.y - b.y, a.z - b.z}; }
double dot(D3 a, D3 b) { return a.x * b.x + a.y * b.y + a.z * b.z; }
D3 cross(D3 a, D3 b) { return {a.y * b.z - a.z * b.y, a.z * b.x - a.x * b.z, a.x * b.y - a.y * b.x}; }
double norm(D3 a) { return std::sqrt(dot(a, a)); }
double at(D3 a, int i) { return i == 0 ? a.x : (i == 1 ? a.y : a.z); }
D3 of(Vec3 v) { return {to_double(v.x), to_double(v.y), to_double(v.z)}; }

// Nearest Q32.32 value (tests only).
Fixed fx(double x) { return Fixed::from_raw(std::llround(x * 0x1p32)); }
Vec3 vec(double x, double y, double z) { return {fx(x), fx(y), fx(z)}; }

// The point as the builder snaps it: to 2^-20 m, ties to even.
D3 snapped(Vec3 v) {
  auto s = [](Fixed c) { return std::nearbyint(static_cast<double>(c.raw()) * 0x1p-12) * 0x1p-20; };
  return {s(v.x), s(v.y), s(v.z)};
}

std::vector<Vec3> box(double hx, double hy, double hz, D3 centre = {0, 0, 0}) {
  std::vector<Vec3> corners;
  for (int i = 0; i < 8; ++i) {
    corners.push_back(
        vec(centre.x + ((i & 1) ? hx : -hx), centre.y + ((i & 2) ? hy : -hy), centre.z + ((i & 4) ? hz : -hz)));
  }
  return corners;
}

std::shared_ptr<const ConvexHull> build(const std::vector<Vec3>& points) {
  auto hull = build_convex_hull(points);
  INFO((hull.ok() ? std::string("built") : hull.error().message()));
  REQUIRE(hull.ok());
  return *hull;
}

std::string refusal(const std::vector<Vec3>& points) {
  auto hull = build_convex_hull(points);
  REQUIRE_FALSE(hull.ok());
  return hull.error().message();
}

// Mass properties in double: tetrahedra from the first vertex over each
// face's fan.
struct DoubleMass {
  double volume = 0;
  D3 centroid{0, 0, 0};
  double inertia[3][3] = {};  // per unit mass, about the centroid
};

DoubleMass double_mass(const ConvexHull& h) {
  const D3 r = of(h.vertices[0]);
  double v6 = 0, s1[3] = {}, s2[3][3] = {};
  for (const auto& face : h.faces) {
    const D3 a = of(h.vertices[h.face_vertices[face.first]]) - r;
    for (int i = 1; i + 1 < face.count; ++i) {
      const D3 b = of(h.vertices[h.face_vertices[face.first + static_cast<uint16_t>(i)]]) - r;
      const D3 c = of(h.vertices[h.face_vertices[face.first + static_cast<uint16_t>(i + 1)]]) - r;
      const double d = dot(a, cross(b, c));
      const D3 s = a + b + c;
      v6 += d;
      for (int p = 0; p < 3; ++p) {
        s1[p] += d * at(s, p);
        for (int q = 0; q < 3; ++q) {
          s2[p][q] += d * (at(a, p) * at(a, q) + at(b, p) * at(b, q) + at(c, p) * at(c, q) + at(s, p) * at(s, q));
        }
      }
    }
  }
  DoubleMass m;
  m.volume = v6 / 6;
  const D3 c{s1[0] / (4 * v6), s1[1] / (4 * v6), s1[2] / (4 * v6)};
  m.centroid = r + c;
  double j[3][3];
  for (int p = 0; p < 3; ++p) {
    for (int q = 0; q < 3; ++q) j[p][q] = s2[p][q] / (20 * v6) - at(c, p) * at(c, q);
  }
  const double trace = j[0][0] + j[1][1] + j[2][2];
  for (int p = 0; p < 3; ++p) {
    for (int q = 0; q < 3; ++q) m.inertia[p][q] = (p == q ? trace : 0) - j[p][q];
  }
  return m;
}

Fixed entry(const Mat33& m, int i, int j) {
  const Vec3 row = m.rows[static_cast<std::size_t>(i)];
  return j == 0 ? row.x : (j == 1 ? row.y : row.z);
}

// The worst relative errors seen, for the report.
struct Worst {
  double volume = 0, centroid = 0, inertia = 0;
};
Worst worst;

// How far a merged face's corners are from a plane, times its area, over
// the volume: what a fan over the face can differ from the exact solid by.
double nonplanar_share(const ConvexHull& h, double volume) {
  double share = 0;
  for (const auto& face : h.faces) {
    const D3 n = of(face.normal);
    double depth = 0, area2 = 0;
    const D3 a = of(h.vertices[h.face_vertices[face.first]]);
    for (int i = 0; i < face.count; ++i) {
      const D3 v = of(h.vertices[h.face_vertices[face.first + static_cast<uint16_t>(i)]]);
      depth = std::max(depth, to_double(face.offset) - dot(n, v));
      if (i + 1 < face.count) {
        area2 += norm(cross(v - a, of(h.vertices[h.face_vertices[face.first + static_cast<uint16_t>(i + 1)]]) - a));
      }
    }
    if (depth > 1e-8) share += area2 / 2 * depth / volume;
  }
  return share;
}

// Volume, centroid and inertia against the double sum: relative to the
// hull's size (centroid: to its extent, inertia: to its largest entry). A
// merged face is not quite flat: the exact solid and the fan over the face
// differ by up to its area times its flatness, allowed for.
void check_mass(const ConvexHull& h, double relative) {
  const DoubleMass m = double_mass(h);
  const double slack = relative + 4 * nonplanar_share(h, m.volume);
  const double ev = std::abs(to_double(h.volume) - m.volume) / m.volume;
  double size = 0, largest = 0;
  for (const Vec3& v : h.vertices) size = std::max(size, norm(of(v) - m.centroid));
  double ec = norm(of(h.centroid) - m.centroid) / size, ei = 0;
  for (int p = 0; p < 3; ++p) {
    for (int q = 0; q < 3; ++q) largest = std::max(largest, std::abs(m.inertia[p][q]));
  }
  for (int p = 0; p < 3; ++p) {
    for (int q = 0; q < 3; ++q) ei = std::max(ei, std::abs(to_double(entry(h.unit_inertia, p, q)) - m.inertia[p][q]));
  }
  ei /= largest;
  // Below a few ulp the Q32.32 outputs themselves limit the precision.
  const double ulp = 0x1p-32;
  if (slack == relative) {  // the worst errors of hulls with flat faces only
    worst.volume = std::max(worst.volume, ev);
    worst.centroid = std::max(worst.centroid, ec);
    worst.inertia = std::max(worst.inertia, ei);
  }
  HULL_REQUIRE(ev <= slack + 2 * ulp / m.volume, "volume " << to_double(h.volume) << " vs " << m.volume);
  HULL_REQUIRE(ec <= slack + 2 * ulp / size, "centroid error " << ec);
  HULL_REQUIRE(ei <= slack + 4 * ulp / largest, "inertia error " << ei);
  for (int p = 0; p < 3; ++p) {
    for (int q = 0; q < 3; ++q) HULL_REQUIRE(entry(h.unit_inertia, p, q) == entry(h.unit_inertia, q, p), "symmetry");
  }
}

// The structure: Euler, edges and their faces, convex counter-clockwise
// loops, unit normals, support planes, every input point inside, every
// vertex an input point in input order.
void check_structure(const ConvexHull& h, const std::vector<Vec3>& input, double inside_tolerance) {
  const auto v = static_cast<int>(h.vertices.size()), e = static_cast<int>(h.edges.size()),
             f = static_cast<int>(h.faces.size());
  HULL_REQUIRE(v - e + f == 2, "Euler: V " << v << " E " << e << " F " << f);
  HULL_REQUIRE(v >= 4 && v <= max_hull_vertices, "vertex count " << v);
  // Vertices: input points (snapped), in input order.
  std::size_t next = 0;
  for (const Vec3& vertex : h.vertices) {
    while (next < input.size() &&
           !(snapped(input[next]).x == to_double(vertex.x) && snapped(input[next]).y == to_double(vertex.y) &&
             snapped(input[next]).z == to_double(vertex.z))) {
      ++next;
    }
    HULL_REQUIRE(next < input.size(), "a vertex that is no input point, or out of order");
    ++next;
  }
  std::vector<int> uses(h.vertices.size());
  std::size_t total = 0;
  for (const auto& face : h.faces) {
    HULL_REQUIRE(face.first == total && face.count >= 3, "face ranges");
    total += face.count;
    const D3 n = of(face.normal);
    HULL_REQUIRE(std::abs(norm(n) - 1) < 1e-8, "unit normal");
    double highest = -1e300;
    for (const Vec3& vertex : h.vertices) highest = std::max(highest, dot(n, of(vertex)));
    HULL_REQUIRE(std::abs(highest - to_double(face.offset)) < 1e-8, "support plane");
    for (int i = 0; i < face.count; ++i) {
      const auto at_loop = [&](int k) { return h.face_vertices[face.first + static_cast<uint16_t>(k % face.count)]; };
      ++uses[at_loop(i)];
      const D3 a = of(h.vertices[at_loop(i)]), b = of(h.vertices[at_loop(i + 1)]), c = of(h.vertices[at_loop(i + 2)]);
      HULL_REQUIRE(dot(cross(b - a, c - b), n) > 0, "convex counter-clockwise loop");
      HULL_REQUIRE(to_double(face.offset) - dot(n, a) <= hull_coplanar_tolerance.raw() * 0x1p-32 + 1e-8,
                   "corner on its face's plane");
      if (i == 0) HULL_REQUIRE(at_loop(0) < at_loop(1) && at_loop(0) < at_loop(face.count - 1), "loop start");
    }
  }
  REQUIRE(total == h.face_vertices.size());
  for (int u : uses) HULL_REQUIRE(u >= 2, "every vertex a corner of its faces");
  // Each loop edge once in `edges`, with its faces the right way round.
  int directed = 0;
  for (std::size_t k = 0; k < h.edges.size(); ++k) {
    const auto& edge = h.edges[k];
    HULL_REQUIRE(edge.tail < edge.head, "edge order");
    if (k > 0) {
      const auto& before = h.edges[k - 1];
      HULL_REQUIRE(before.tail < edge.tail || (before.tail == edge.tail && before.head < edge.head), "sorted edges");
    }
    auto has = [&](uint16_t face, uint16_t a, uint16_t b) {
      const auto& fc = h.faces[face];
      for (int i = 0; i < fc.count; ++i) {
        if (h.face_vertices[fc.first + static_cast<uint16_t>(i)] == a &&
            h.face_vertices[fc.first + static_cast<uint16_t>((i + 1) % fc.count)] == b) {
          return true;
        }
      }
      return false;
    };
    HULL_REQUIRE(has(edge.face, edge.tail, edge.head) && has(edge.twin_face, edge.head, edge.tail), "edge faces");
    directed += 2;
  }
  REQUIRE(static_cast<std::size_t>(directed) == h.face_vertices.size());
  // Every input point inside or on every face's plane.
  for (const Vec3& p : input) {
    for (const auto& face : h.faces) {
      HULL_REQUIRE(dot(of(face.normal), snapped(p)) <= to_double(face.offset) + inside_tolerance,
                   "a point outside a face by " << dot(of(face.normal), snapped(p)) - to_double(face.offset));
    }
  }
  HULL_REQUIRE(h.extent >= Fixed{}, "extent");
}

void check_same(const ConvexHull& a, const ConvexHull& b) {
  HULL_REQUIRE(a.vertices == b.vertices, "vertices");
  HULL_REQUIRE(a.face_vertices == b.face_vertices, "face vertices");
  HULL_REQUIRE(a.faces.size() == b.faces.size(), "face count");
  for (std::size_t i = 0; i < a.faces.size(); ++i) {
    HULL_REQUIRE(a.faces[i].normal == b.faces[i].normal && a.faces[i].offset == b.faces[i].offset &&
                     a.faces[i].first == b.faces[i].first && a.faces[i].count == b.faces[i].count,
                 "face " << i);
  }
  HULL_REQUIRE(a.edges.size() == b.edges.size(), "edge count");
  for (std::size_t i = 0; i < a.edges.size(); ++i) {
    HULL_REQUIRE(a.edges[i].tail == b.edges[i].tail && a.edges[i].head == b.edges[i].head &&
                     a.edges[i].face == b.edges[i].face && a.edges[i].twin_face == b.edges[i].twin_face,
                 "edge " << i);
  }
  HULL_REQUIRE(
      a.volume == b.volume && a.centroid == b.centroid && a.unit_inertia == b.unit_inertia && a.extent == b.extent,
      "mass properties");
}

void check_rebuild(const ConvexHull& h) { check_same(h, *build(h.vertices)); }

int quads(const ConvexHull& h) {
  return static_cast<int>(std::count_if(h.faces.begin(), h.faces.end(), [](const auto& f) { return f.count == 4; }));
}

// A random coordinate in [-size, size] m, any raw value.
Fixed random_coordinate(SplitMix64& rng, Fixed size) {
  const auto span = static_cast<uint64_t>(size.raw()) * 2 + 1;
  return Fixed::from_raw(static_cast<int64_t>(rng.next() % span) - size.raw());
}

}  // namespace

TEST_CASE("A cube's 8 corners give 6 squares, 12 edges and exact mass properties", "[convex_hull]") {
  const auto corners = box(1, 1, 1);
  const auto h = build(corners);
  CHECK(h->vertices == corners);
  CHECK(h->faces.size() == 6);
  CHECK(quads(*h) == 6);
  CHECK(h->edges.size() == 12);
  CHECK(h->volume == 8.0_fx);
  CHECK(h->centroid == Vec3::zero());
  // m (a^2 + b^2) / 12 per kg, a = b = 2.
  const Fixed i = Fixed::from_ratio(8, 12);
  CHECK(h->unit_inertia == Mat33::diagonal({i, i, i}));
  CHECK(h->extent == sqrt(3.0_fx));
  for (const auto& face : h->faces) {
    CHECK(face.offset == 1.0_fx);
    CHECK(length(face.normal) == 1.0_fx);
  }
  check_structure(*h, corners, 1e-9);
  check_rebuild(*h);
}

TEST_CASE("An offset box has its centroid at its centre and (b^2 + c^2) / 12 inertia", "[convex_hull]") {
  const auto corners = box(0.5, 1, 1.5, {3, -2, 5});
  const auto h = build(corners);
  CHECK(h->faces.size() == 6);
  CHECK(h->volume == 6.0_fx);
  CHECK(h->centroid == Vec3{3.0_fx, -2.0_fx, 5.0_fx});
  CHECK(h->unit_inertia ==
        Mat33::diagonal({Fixed::from_ratio(13, 12), Fixed::from_ratio(10, 12), Fixed::from_ratio(5, 12)}));
  check_structure(*h, corners, 1e-9);
  check_rebuild(*h);
}

TEST_CASE("A rotated, offset box has the products of inertia of R diag R^T", "[convex_hull]") {
  const double h[3] = {0.4, 0.7, 1.1};
  const D3 centre{1.5, -0.75, 2.25};
  // R = rotation about the unit axis (1, 2, 2)/3 by 0.7 rad (Rodrigues).
  const D3 k{1.0 / 3, 2.0 / 3, 2.0 / 3};
  const double s = std::sin(0.7), c = std::cos(0.7);
  double r[3][3];
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const double kk = at(k, i) * at(k, j);
      const double skew[3][3] = {{0, -k.z, k.y}, {k.z, 0, -k.x}, {-k.y, k.x, 0}};
      r[i][j] = (i == j ? c : 0) + (1 - c) * kk + s * skew[i][j];
    }
  }
  std::vector<Vec3> corners;
  for (int n = 0; n < 8; ++n) {
    const double local[3] = {(n & 1) ? h[0] : -h[0], (n & 2) ? h[1] : -h[1], (n & 4) ? h[2] : -h[2]};
    double world[3];
    for (int i = 0; i < 3; ++i) world[i] = at(centre, i) + r[i][0] * local[0] + r[i][1] * local[1] + r[i][2] * local[2];
    corners.push_back(vec(world[0], world[1], world[2]));
  }
  const auto hull = build(corners);
  CHECK(hull->vertices.size() == 8);
  CHECK(hull->faces.size() == 6);
  CHECK(quads(*hull) == 6);
  const double a2[3] = {4 * h[0] * h[0], 4 * h[1] * h[1], 4 * h[2] * h[2]};
  const double local_inertia[3] = {(a2[1] + a2[2]) / 12, (a2[0] + a2[2]) / 12, (a2[0] + a2[1]) / 12};
  CHECK(to_double(hull->volume) == Approx(8 * h[0] * h[1] * h[2]).epsilon(1e-5));
  CHECK(norm(of(hull->centroid) - centre) < 2e-6);
  double worst_inertia = 0;
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      double expected = 0;
      for (int m = 0; m < 3; ++m) expected += r[i][m] * local_inertia[m] * r[j][m];
      worst_inertia = std::max(worst_inertia, std::abs(to_double(entry(hull->unit_inertia, i, j)) - expected));
    }
  }
  // The corners are snapped to 2^-20 m: about 1e-6 of the size.
  CHECK(worst_inertia < 1e-5 * local_inertia[2]);
  // Off the diagonal, the products of inertia are far from zero.
  CHECK(std::abs(to_double(entry(hull->unit_inertia, 0, 1))) > 0.01);
  check_structure(*hull, corners, 1e-9);
  check_mass(*hull, 1e-6);
  check_rebuild(*hull);
}

TEST_CASE("A right tetrahedron's volume, centroid and inertia are the closed forms, rounded once", "[convex_hull]") {
  // Vertices 0, 2x, 2y, 2z: V = 8/6; E[x^2] = 4/10, E[xy] = 4/20; c = 1/2.
  // J_xx = 4/10 - 1/4 = 3/20, J_xy = 4/20 - 1/4 = -1/20; I_xx = 6/20, I_xy = 1/20.
  const std::vector<Vec3> points = {vec(0, 0, 0), vec(2, 0, 0), vec(0, 2, 0), vec(0, 0, 2)};
  const auto h = build(points);
  CHECK(h->faces.size() == 4);
  CHECK(h->edges.size() == 6);
  CHECK(h->volume == Fixed::from_ratio(8, 6));
  CHECK(h->centroid == Vec3{0.5_fx, 0.5_fx, 0.5_fx});
  const Fixed d = Fixed::from_ratio(6, 20), o = Fixed::from_ratio(1, 20);
  CHECK(h->unit_inertia == Mat33{{Vec3{d, o, o}, Vec3{o, d, o}, Vec3{o, o, d}}});
  check_structure(*h, points, 1e-9);
  check_mass(*h, 1e-9);
  check_rebuild(*h);
}

TEST_CASE("A regular octahedron has 8 triangles and inertia a^2 / 5 per kg", "[convex_hull]") {
  // |x| + |y| + |z| <= a: V = 4 a^3 / 3, E[x^2] = a^2 / 10, I = a^2 / 5.
  const std::vector<Vec3> points = {vec(1.5, 0, 0),  vec(-1.5, 0, 0), vec(0, 1.5, 0),
                                    vec(0, -1.5, 0), vec(0, 0, 1.5),  vec(0, 0, -1.5)};
  const auto h = build(points);
  CHECK(h->vertices.size() == 6);
  CHECK(h->faces.size() == 8);
  CHECK(h->edges.size() == 12);
  CHECK(h->volume == Fixed::from_ratio(4 * 27, 3 * 8));
  CHECK(h->centroid == Vec3::zero());
  const Fixed i = Fixed::from_ratio(9, 20);
  CHECK(h->unit_inertia == Mat33::diagonal({i, i, i}));
  CHECK(h->extent == 1.5_fx);
  check_structure(*h, points, 1e-9);
  check_rebuild(*h);
}

TEST_CASE("Interior points, duplicates and points on faces and edges are not corners", "[convex_hull]") {
  // Before the corners: a face centre, an edge midpoint, a point inside; after: a duplicate, a point inside.
  const auto corners = box(1, 1, 1);
  std::vector<Vec3> input = {vec(0, 0, 1), vec(1, 0, 1), vec(0.5, 0.5, 0.5), vec(-0.25, 0.5, -0.75)};
  input.insert(input.end(), corners.begin(), corners.end());
  input.push_back(corners[3]);  // a duplicate
  input.push_back(vec(0.999, -0.999, 0.999));
  const auto h = build(input);
  CHECK(h->vertices == corners);
  CHECK(h->faces.size() == 6);
  CHECK(quads(*h) == 6);
  CHECK(h->volume == 8.0_fx);
  check_structure(*h, input, 1e-9);
  check_rebuild(*h);
}

TEST_CASE("Corners within the coplanar tolerance merge their faces", "[convex_hull]") {
  SECTION("a cube's top corners raised and lowered by 2e-5 m: 6 faces") {
    auto corners = box(0.5, 0.5, 0.5);
    const double shift[4] = {2e-5, -2e-5, 1.5e-5, 0};
    int k = 0;
    for (Vec3& c : corners) {
      if (c.z > Fixed{}) c.z += fx(shift[k++]);
    }
    const auto h = build(corners);
    CHECK(h->vertices.size() == 8);
    CHECK(h->faces.size() == 6);
    CHECK(quads(*h) == 6);
    CHECK(h->edges.size() == 12);
    check_structure(*h, corners, 1e-9);
    check_mass(*h, 1e-6);
    check_rebuild(*h);
  }
  SECTION("a point 5e-5 m above a face's centre goes, one 2e-4 m above stays") {
    auto corners = box(0.5, 0.5, 0.5);
    auto low = corners;
    low.push_back(vec(0.1, -0.2, 0.50005));
    const auto flat = build(low);
    CHECK(flat->vertices == corners);
    CHECK(flat->faces.size() == 6);
    check_structure(*flat, low, 1e-4 + 1e-9);
    check_rebuild(*flat);
    auto high = corners;
    high.push_back(vec(0.1, -0.2, 0.5002));
    const auto peaked = build(high);
    CHECK(peaked->vertices.size() == 9);
    CHECK(peaked->faces.size() == 9);  // 5 squares and the top's 4 triangles
    check_structure(*peaked, high, 1e-9);
    check_rebuild(*peaked);
  }
  SECTION("a bevelled box: octagons and rectangles") {
    // A 2 x 2 x 1 box with its 4 vertical edges cut at 45 degrees.
    std::vector<Vec3> points;
    for (double z : {-0.5, 0.5}) {
      for (int i = 0; i < 8; ++i) {
        const double big = 1, small = 0.75;
        const double xs[8] = {small, big, big, small, -small, -big, -big, -small};
        const double ys[8] = {-big, -small, small, big, big, small, -small, -big};
        points.push_back(vec(xs[i], ys[i], z));
      }
    }
    const auto h = build(points);
    CHECK(h->vertices.size() == 16);
    CHECK(h->faces.size() == 10);
    CHECK(std::count_if(h->faces.begin(), h->faces.end(), [](const auto& f) { return f.count == 8; }) == 2);
    CHECK(quads(*h) == 8);
    CHECK(to_double(h->volume) == Approx(4 - 4 * 0.25 * 0.25 / 2).epsilon(1e-9));
    check_structure(*h, points, 1e-9);
    check_mass(*h, 1e-9);
    check_rebuild(*h);
  }
}

TEST_CASE("Refusals name the limit they break", "[convex_hull]") {
  CHECK(refusal({vec(0, 0, 0), vec(1, 0, 0), vec(0, 1, 0)}) == "3 points: a hull needs 4 to 1024");
  SplitMix64 rng{7};
  std::vector<Vec3> many;
  for (int i = 0; i < 1025; ++i) many.push_back({random_coordinate(rng, 1.0_fx), random_coordinate(rng, 1.0_fx), {}});
  CHECK(refusal(many) == "1025 points: a hull needs 4 to 1024");
  auto far = box(1, 1, 1);
  far[2].z = 50.001_fx;
  {
    auto hull = build_convex_hull(far);
    REQUIRE_FALSE(hull.ok());
    CHECK(hull.error().place == "points[2].z");
    CHECK(hull.error().reason == "outside -50..50 m");
    CHECK(hull.error().message() == "points[2].z: outside -50..50 m");
  }
  far[2].z = -50.0_fx;  // the limit itself is in
  CHECK(build_convex_hull(far).ok());
  CHECK(refusal({vec(0, 0, 1), vec(1, 0, 1), vec(0, 1, 1), vec(1, 1, 1), vec(0.5, 0.25, 1)}) ==
        "flat: 0 m thick, at least 0.02 m");
  CHECK(refusal({vec(0, 0, 0), vec(1, 1, 1), vec(2, 2, 2), vec(-1, -1, -1)}) == "flat: 0 m thick, at least 0.02 m");
  CHECK(refusal({vec(0, 0, 0), vec(0, 0, 0), vec(1, 0, 0), vec(1, 0, 0), vec(0, 1, 0)}) ==
        "flat: 0 m thick, at least 0.02 m");
  CHECK(refusal(box(1, 1, 0.005)) == "flat: 0.01 m thick, at least 0.02 m");
  CHECK(refusal(box(1, 0.00999, 1)) == "flat: 0.0199 m thick, at least 0.02 m");
  CHECK(build_convex_hull(box(1, 1, 0.01)).ok());
  // 40 points spread over a sphere (a Fibonacci lattice) are all corners.
  std::vector<Vec3> sphere;
  for (int i = 0; i < 40; ++i) {
    const double z = 1 - (2 * i + 1) / 40.0, rho = std::sqrt(1 - z * z), phi = 2.399963229728653 * i;
    sphere.push_back(vec(rho * std::cos(phi), rho * std::sin(phi), z));
  }
  CHECK(refusal(sphere) == "40 corners, at most 32");
  sphere.resize(31);
  sphere.push_back(vec(0, 0, -1));
  CHECK(build_convex_hull(sphere).ok());
}

TEST_CASE("50 m and 0.02 m hulls build with their mass properties", "[convex_hull]") {
  const auto big = build(box(50, 50, 50));
  CHECK(big->volume == 1000000.0_fx);
  CHECK(big->unit_inertia ==
        Mat33::diagonal({Fixed::from_ratio(20000, 12), Fixed::from_ratio(20000, 12), Fixed::from_ratio(20000, 12)}));
  CHECK(big->extent == sqrt(7500.0_fx));
  check_rebuild(*big);
  // A long 100 m diagonal wedge, products of inertia in the thousands.
  const std::vector<Vec3> wedge = {vec(-50, -50, -50), vec(50, 50, 50), vec(50, -50, -50), vec(-50, 50, -50),
                                   vec(50, 50, -50)};
  const auto w = build(wedge);
  check_structure(*w, wedge, 1e-8);
  check_mass(*w, 1e-9);
  check_rebuild(*w);
  const auto small = build(box(0.01, 0.01, 0.01));
  // 0.01 m snaps to 10486 grid steps: exact volume (2 10486)^3 2^-60.
  const double side = 2 * 10486 * 0x1p-20;
  CHECK(std::abs(to_double(small->volume) - side * side * side) <= 0x1p-32);
  const double expected = side * side / 6;
  CHECK(std::abs(to_double(entry(small->unit_inertia, 0, 0)) - expected) <= 0x1p-32);
  CHECK(small->unit_inertia.rows[0].y == Fixed{});
  check_structure(*small, box(0.01, 0.01, 0.01), 1e-9);
  check_rebuild(*small);
}

TEST_CASE("Random clouds give a closed convex hull of every point, rebuilt exactly", "[convex_hull]") {
  worst = {};
  SplitMix64 rng{20240611};
  int built = 0, refused_corners = 0;
  const int clouds = static_cast<int>(test::samples(600));
  for (int cloud = 0; cloud < clouds; ++cloud) {
    const int kind = cloud % 6;
    const int n = 4 + rng.below(kind == 0 ? 40 : 160);
    const Fixed size = Fixed::from_raw(static_cast<int64_t>(rng.next() % (uint64_t{49} << 32)) + (int64_t{1} << 31));
    std::vector<Vec3> points;
    if (kind == 4) {  // a few far points around a crowd of near ones: all 1024 points
      for (int i = 0; i < 1024; ++i) {
        const Fixed spread = i % 50 == 0 ? size : size / 8.0_fx;
        points.push_back(
            {random_coordinate(rng, spread), random_coordinate(rng, spread), random_coordinate(rng, spread)});
      }
    }
    if (kind == 5) points = box(to_double(size), to_double(size), to_double(size));
    for (int i = 0; i < n && kind != 4; ++i) {
      Vec3 p{random_coordinate(rng, size), random_coordinate(rng, size), random_coordinate(rng, size)};
      if (kind == 1) {  // on a coarse lattice: many coplanar and collinear points
        auto coarse = [&](Fixed c) { return round(c * 4.0_fx / size) * size / 4.0_fx; };
        p = {coarse(p.x), coarse(p.y), coarse(p.z)};
      } else if (kind == 2) {  // a flattened ellipsoid's surface
        const D3 d = of(p);
        const double r = norm(d);
        if (r == 0) continue;
        p = vec(d.x / r * to_double(size), d.y / r * to_double(size) * 0.5, d.z / r * to_double(size) * 0.2);
      } else if (kind == 5) {  // on a box's faces, 3e-5 m off them at most
        const int axis = rng.below(3);
        const double off = (static_cast<double>(rng.below(61)) - 30) * 1e-6;
        const Fixed face = rng.below(2) == 0 ? -size : size;
        (axis == 0 ? p.x : (axis == 1 ? p.y : p.z)) = face + fx(face > Fixed{} ? off : -off);
      }
      points.push_back(p);
      if (kind == 3 && i % 5 == 0) points.push_back(points[static_cast<std::size_t>(rng.below(i + 1))]);
    }
    if (points.size() < 4) continue;
    auto hull = build_convex_hull(points);
    if (!hull.ok()) {
      const std::string message = hull.error().message();
      const bool corners = message.find("corners, at most 32") != std::string::npos;
      HULL_REQUIRE(corners || message.rfind("flat: ", 0) == 0, "cloud " << cloud << ": " << message);
      refused_corners += corners ? 1 : 0;
      continue;
    }
    ++built;
    INFO("cloud " << cloud << " kind " << kind << " of " << points.size() << " points");
    check_structure(**hull, points, 1e-4 + 1e-8);
    check_mass(**hull, 1e-6);
    check_rebuild(**hull);
    if (kind == 1) {  // no near-coplanar merges on the lattice: any order gives the same solid
      std::vector<Vec3> reversed(points.rbegin(), points.rend());
      const auto other = build(reversed);
      HULL_REQUIRE(other->volume == (*hull)->volume && other->faces.size() == (*hull)->faces.size(), "order");
    }
    if (kind == 5) HULL_REQUIRE((*hull)->faces.size() == 6, "a box's 6 faces, not " << (*hull)->faces.size());
  }
  INFO("built " << built << " of " << clouds << " hulls (" << refused_corners
                << " refused for corners); worst relative errors: volume " << worst.volume << ", centroid "
                << worst.centroid << ", inertia " << worst.inertia);
  CHECK(built > clouds / 2);
}
