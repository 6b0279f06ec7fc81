// Static triangle meshes: a level's terrain, ramps and buildings, built
// once from vertex and index arrays and shared by pointer (immutable, as a
// hull is). A mesh is a surface, not a solid: each triangle is one-sided,
// its front the side its corners run counter-clockwise around, and bodies
// are pushed out to the front.
//
// What building adds to the arrays:
//   - each triangle's unit normal and plane;
//   - its active edges (Jolt's name): an edge is active where a body can
//     touch it before it touches a face, that is where the surface bends
//     outward there by more than `mesh_active_edge_angle`, or where the edge
//     has no neighbour (the mesh's border) or more than one. Where two
//     triangles meet flat or bend inward, a contact at that edge is really a
//     contact with the face: the narrowphase then takes the face's normal,
//     so a box sliding across a flat mesh never meets the edge between two
//     triangles (a "ghost" bump);
//   - a bounding-volume tree over the triangles, built top down by
//     splitting each node's triangles at the median of their centres along
//     the longest axis (ties by triangle index), leaves of at most 4: the
//     same tree for the same arrays on every build, and every query visits
//     it in one order.
//
// Limits (each refused with a one-line reason): 1..2^20 triangles over at
// most 2^20 vertices, each coordinate within 16,000 m of the shape's
// origin, no triangle with an index out of range, an edge longer than
// 1,000 m or an area below mesh_min_area.
#pragma once

#include <array>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/aabb.h"
#include "core/error.h"
#include "fixed/decimal.h"

namespace bitstep {

using namespace bitstep::literals;

inline constexpr uint32_t max_mesh_triangles = uint32_t{1} << 20;
inline constexpr uint32_t max_mesh_vertices = uint32_t{1} << 20;
// m^2: a triangle smaller than a 1 mm square has no direction to push along.
inline constexpr Fixed mesh_min_area = 0.000001_fx;
// An edge where the surface bends outward is active when its two faces'
// unit normals are farther apart than 5 degrees: n1 . n2 below cos 5 deg.
inline constexpr Fixed mesh_active_edge_cos = 0.9962_fx;
// m: the longest a triangle's edge may be (cross products stay in range).
inline constexpr Fixed mesh_max_edge = 1000.0_fx;

struct HeightGrid;

struct TriangleMesh {
  struct Triangle {
    std::array<uint32_t, 3> corners;  // vertex indices, counter-clockwise seen from the front
    Vec3 normal;                      // unit, toward the front
    Fixed offset;                     // dot(normal, x) on its plane
    uint8_t active_edges = 0;         // bit k: the edge from corner k to corner k + 1 is active
  };
  // A node of the tree: a leaf holds triangles [first, first + count) of
  // `order`; an inner node's children are first and first + 1 (count 0).
  struct Node {
    Aabb bounds;
    uint32_t first = 0;
    uint32_t count = 0;
  };

  std::vector<Vec3> vertices;  // the shape's frame
  std::vector<Triangle> triangles;
  std::vector<uint32_t> order;  // triangle indices, grouped by leaf
  std::vector<Node> nodes;      // nodes[0] is the root
  Aabb bounds;                  // of every vertex
  Fixed extent;                 // the farthest vertex's distance from the shape's origin
  std::shared_ptr<const HeightGrid> source_grid;  // a heightfield's grid (core/height_grid.h), or none
};

// The mesh of `vertices` and `indices` (three per triangle), or why not
// ("indices: 7 indices, not a multiple of 3", "indices[5]: vertex 12 of 10",
// "triangle 3: area below 1e-6 m^2", "vertices[2].x: outside -16000..16000 m").
// `source_grid`: the grid the arrays were made from, kept with the mesh.
Result<std::shared_ptr<const TriangleMesh>> build_triangle_mesh(
    const std::vector<Vec3>& vertices, const std::vector<uint32_t>& indices,
    std::shared_ptr<const HeightGrid> source_grid = nullptr);

// Calls visit(triangle index) for each triangle in a leaf whose bounds
// meet `box` (the mesh's frame) and whose own bounds meet it, in the
// tree's order: depth first, the first child first.
template <class Visit>
void for_each_triangle_near(const TriangleMesh& mesh, const Aabb& box, Visit&& visit) {
  uint32_t stack[64];  // a median split halves each node: 21 levels for 2^20 triangles
  int depth = 0;
  stack[depth++] = 0;
  while (depth > 0) {
    const TriangleMesh::Node& node = mesh.nodes[stack[--depth]];
    if (!node.bounds.overlaps(box)) continue;
    if (node.count == 0) {
      stack[depth++] = node.first + 1;  // popped second
      stack[depth++] = node.first;
      continue;
    }
    for (uint32_t k = node.first; k < node.first + node.count; ++k) {
      const uint32_t t = mesh.order[k];
      const TriangleMesh::Triangle& tri = mesh.triangles[t];
      const Vec3 a = mesh.vertices[tri.corners[0]], b = mesh.vertices[tri.corners[1]],
                 c = mesh.vertices[tri.corners[2]];
      if (Aabb{min(min(a, b), c), max(max(a, b), c)}.overlaps(box)) visit(t);
    }
  }
}

}  // namespace bitstep
