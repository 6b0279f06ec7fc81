// A convex polyhedron as the generic narrowphase reads it (collide_hull.cpp):
// corners, faces with their loops, and edges with the two faces they join,
// in the shape's own frame. A hull is one already (core/convex_hull.h); a
// box becomes one on the stack, with the same numbering of faces as
// box-box's feature ids (face 2k: +axis k, 2k + 1: -axis k; corner bit k
// set: + half extent along axis k), so a box and a hull meet through the
// same separating-axis test as two hulls. Internal to core/.
#pragma once

#include <array>
#include <span>

#include "core/convex_hull.h"

namespace bitstep {

struct Polyhedron {
  std::span<const Vec3> vertices;
  std::span<const ConvexHull::Face> faces;
  std::span<const uint16_t> face_vertices;
  std::span<const ConvexHull::Edge> edges;
  std::span<const Vec3> edge_directions;  // unit, tail to head
  Vec3 inside;  // a point inside it (a hull's centroid, a box's centre)
};

inline Polyhedron polyhedron_of(const ConvexHull& hull) {
  return {hull.vertices, hull.faces, hull.face_vertices, hull.edges, hull.edge_directions, hull.centroid};
}

// A box of half extents h as a polyhedron; keep it alive while its view is used.
struct BoxPolyhedron {
  std::array<Vec3, 8> vertices;
  std::array<ConvexHull::Face, 6> faces;
  explicit BoxPolyhedron(Vec3 half_extents);
  Polyhedron view() const;
};

}  // namespace bitstep
