// A box as a polyhedron (core/polyhedron.h): its corners and face planes
// from its half extents, on one topology written out once.
#include "core/polyhedron.h"

#include "core/collide_internal.h"

namespace bitstep {

namespace {

// Each face's loop, counter-clockwise seen from outside, by face number
// (2k: +axis k, 2k + 1: -axis k); corner i has bit k set for +h_k. For
// +x: corners 1 3 7 5 run +y then +z, and +y x +z = +x.
constexpr std::array<uint16_t, 24> box_loops = {1, 3, 7, 5,   // +x
                                                0, 4, 6, 2,   // -x
                                                2, 6, 7, 3,   // +y
                                                0, 1, 5, 4,   // -y
                                                4, 5, 7, 6,   // +z
                                                0, 2, 3, 1};  // -z

// The 12 edges from the loops: each tail -> head with tail < head, its
// `face` the one whose loop runs tail -> head.
constexpr std::array<ConvexHull::Edge, 12> make_box_edges() {
  std::array<ConvexHull::Edge, 12> edges{};
  size_t count = 0;
  for (uint16_t face = 0; face < 6; ++face) {
    for (uint16_t i = 0; i < 4; ++i) {
      const uint16_t from = box_loops[face * 4u + i], to = box_loops[face * 4u + (i + 1u) % 4u];
      if (from > to) continue;  // its twin's turn
      edges[count++] = {from, to, face, 0};
    }
  }
  for (ConvexHull::Edge& edge : edges) {  // the face that runs it head -> tail
    for (uint16_t face = 0; face < 6; ++face) {
      for (uint16_t i = 0; i < 4; ++i) {
        if (box_loops[face * 4u + i] == edge.head && box_loops[face * 4u + (i + 1u) % 4u] == edge.tail) {
          edge.twin_face = face;
        }
      }
    }
  }
  return edges;
}

constexpr std::array<ConvexHull::Edge, 12> box_edges = make_box_edges();

// Each edge joins corners that differ in one bit, set in its head (tail <
// head): it runs along + that axis.
constexpr std::array<Vec3, 12> make_box_edge_directions() {
  std::array<Vec3, 12> directions{};
  for (size_t i = 0; i < box_edges.size(); ++i) {
    const int bits = box_edges[i].tail ^ box_edges[i].head;
    directions[i] = collide_detail::unit_axis(bits == 1 ? 0 : bits == 2 ? 1 : 2);
  }
  return directions;
}

constexpr std::array<Vec3, 12> box_edge_directions = make_box_edge_directions();

}  // namespace

BoxPolyhedron::BoxPolyhedron(Vec3 h) {
  for (int i = 0; i < 8; ++i) {
    vertices[static_cast<size_t>(i)] = {(i & 1) != 0 ? h.x : -h.x, (i & 2) != 0 ? h.y : -h.y,
                                        (i & 4) != 0 ? h.z : -h.z};
  }
  for (int k = 0; k < 3; ++k) {
    const Vec3 axis = collide_detail::unit_axis(k);
    const Fixed half = collide_detail::get(h, k);
    faces[static_cast<size_t>(2 * k)] = {axis, half, static_cast<uint16_t>(8 * k), 4};
    faces[static_cast<size_t>(2 * k + 1)] = {-axis, half, static_cast<uint16_t>(8 * k + 4), 4};
  }
}

Polyhedron BoxPolyhedron::view() const { return {vertices, faces, box_loops, box_edges, box_edge_directions, Vec3{}}; }

}  // namespace bitstep
