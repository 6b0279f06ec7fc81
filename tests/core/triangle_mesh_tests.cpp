// Static triangle meshes (core/triangle_mesh.h): planes, active edges, the
// tree's queries against brute force, and the refusals.
#include <algorithm>
#include <catch2/catch.hpp>
#include <string>
#include <vector>

#include "core/triangle_mesh.h"
#include "fixed/splitmix64.h"

using namespace bitstep;

namespace {

// An n x n grid of 1 m squares at y = height(i, j), each square two
// triangles facing up (+y).
struct Grid {
  std::vector<Vec3> vertices;
  std::vector<uint32_t> indices;
};

template <class Height>
Grid grid(int n, Height height) {
  Grid g;
  for (int j = 0; j <= n; ++j) {
    for (int i = 0; i <= n; ++i) g.vertices.push_back({Fixed::from_int(i), height(i, j), Fixed::from_int(j)});
  }
  const auto at = [&](int i, int j) { return static_cast<uint32_t>(j * (n + 1) + i); };
  for (int j = 0; j < n; ++j) {
    for (int i = 0; i < n; ++i) {
      // Counter-clockwise seen from above: (i, j) -> (i, j + 1) -> (i + 1, j).
      g.indices.insert(g.indices.end(), {at(i, j), at(i, j + 1), at(i + 1, j)});
      g.indices.insert(g.indices.end(), {at(i + 1, j), at(i, j + 1), at(i + 1, j + 1)});
    }
  }
  return g;
}

std::shared_ptr<const TriangleMesh> built(const Grid& g) {
  auto mesh = build_triangle_mesh(g.vertices, g.indices);
  if (!mesh.ok()) FAIL(mesh.error().message());
  return mesh.value();
}

std::string refusal(const std::vector<Vec3>& vertices, const std::vector<uint32_t>& indices) {
  auto mesh = build_triangle_mesh(vertices, indices);
  return mesh.ok() ? "built" : mesh.error().message();
}

}  // namespace

TEST_CASE("Mesh: a flat grid faces up, its inner edges inactive, its border active", "[mesh]") {
  const auto mesh = built(grid(10, [](int, int) { return Fixed{}; }));
  REQUIRE(mesh->triangles.size() == 200);
  int active = 0;
  for (const TriangleMesh::Triangle& t : mesh->triangles) {
    CHECK(t.normal == Vec3{Fixed{}, Fixed::one(), Fixed{}});
    CHECK(t.offset == Fixed{});
    for (int k = 0; k < 3; ++k) active += (t.active_edges >> k) & 1;
  }
  CHECK(active == 40);  // the border: 4 sides of 10 edges
}

TEST_CASE("Mesh: a ridge's edge is active, a valley's and a gentle bend's are not", "[mesh]") {
  // Heights rising to x = 2 and falling after: a roof (outward bend of 45 degrees at x = 2).
  const auto roof = built(grid(4, [](int i, int) { return Fixed::from_int(i <= 2 ? i : 4 - i); }));
  const auto valley = built(grid(4, [](int i, int) { return Fixed::from_int(i <= 2 ? -i : i - 4); }));
  const auto gentle = built(grid(4, [](int i, int) { return i <= 2 ? Fixed{} : Fixed::from_int(i - 2) / 20.0_fx; }));
  // The edges along x = 2: count the active ones away from the border (z = 1..3).
  const auto count_at_x2 = [](const TriangleMesh& mesh) {
    int n = 0;
    for (const TriangleMesh::Triangle& t : mesh.triangles) {
      for (int k = 0; k < 3; ++k) {
        const Vec3 a = mesh.vertices[t.corners[static_cast<size_t>(k)]];
        const Vec3 b = mesh.vertices[t.corners[static_cast<size_t>((k + 1) % 3)]];
        const bool on_line = a.x == 2.0_fx && b.x == 2.0_fx;
        if (on_line && ((t.active_edges >> k) & 1) != 0) ++n;
      }
    }
    return n;
  };
  CHECK(count_at_x2(*roof) == 8);  // 4 edges, each active on both of its triangles
  CHECK(count_at_x2(*valley) == 0);
  CHECK(count_at_x2(*gentle) == 0);  // 2.9 degrees: below the 5 degree line
}

TEST_CASE("Mesh: the tree finds what brute force finds, in one order", "[mesh]") {
  SplitMix64 random{4242};
  const auto noise = [&](int, int) {
    return Fixed::from_raw(static_cast<int64_t>(random.next() % (uint64_t{1} << 32)));
  };
  const Grid g = grid(40, noise);
  const auto mesh = built(g);
  for (int round = 0; round < 200; ++round) {
    const auto coordinate = [&](int span) {
      return Fixed::from_raw(static_cast<int64_t>(random.next() % (uint64_t(span) << 32)));
    };
    const Vec3 low{coordinate(40), coordinate(2), coordinate(40)};
    const Vec3 size{coordinate(5), coordinate(2), coordinate(5)};
    const Aabb box{low, low + size};
    std::vector<uint32_t> found, again, brute;
    for_each_triangle_near(*mesh, box, [&](uint32_t t) { found.push_back(t); });
    for_each_triangle_near(*mesh, box, [&](uint32_t t) { again.push_back(t); });
    for (uint32_t t = 0; t < mesh->triangles.size(); ++t) {
      const TriangleMesh::Triangle& tri = mesh->triangles[t];
      const Vec3 a = mesh->vertices[tri.corners[0]], b = mesh->vertices[tri.corners[1]],
                 c = mesh->vertices[tri.corners[2]];
      if (Aabb{min(min(a, b), c), max(max(a, b), c)}.overlaps(box)) brute.push_back(t);
    }
    CHECK(found == again);
    std::vector<uint32_t> sorted = found;
    std::sort(sorted.begin(), sorted.end());
    CHECK(sorted == brute);
  }
}

TEST_CASE("Mesh: refused arrays name the place and the reason", "[mesh]") {
  const std::vector<Vec3> square = {{}, {Fixed::one(), Fixed{}, Fixed{}}, {Fixed{}, Fixed{}, Fixed::one()}};
  CHECK(refusal(square, {0, 2, 1}) == "built");
  CHECK(refusal(square, {0, 2}) == "indices: 2 indices, not a multiple of 3");
  CHECK(refusal(square, {}) == "indices: 0 triangles: a mesh has 1 to 1048576");
  CHECK(refusal(square, {0, 2, 3}) == "indices[2]: vertex 3 of 3");
  CHECK(refusal({{}, {Fixed::one(), Fixed{}, Fixed{}}, {2.0_fx, Fixed{}, Fixed{}}}, {0, 1, 2}) ==
        "triangle 0: area below 1e-6 m^2");
  CHECK(refusal({{}, {Fixed::from_int(1001), Fixed{}, Fixed{}}, {Fixed{}, Fixed{}, Fixed::one()}}, {0, 2, 1}) ==
        "triangle 0: an edge longer than 1000 m");
  CHECK(refusal({{}, {Fixed::one(), Fixed{}, Fixed{}}, {Fixed{}, Fixed::from_int(16001), Fixed{}}}, {0, 2, 1}) ==
        "vertices[2].y: outside -16000..16000 m");
}
