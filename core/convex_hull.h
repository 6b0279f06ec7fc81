// Convex hulls: the hull of a set of points, built once, in exact integer
// arithmetic, and shared by every shape that uses it (immutable after
// building, so bodies, snapshots and rollback copies hold a pointer, never
// a copy). A hull is what props are made of: a die, a rock, a crate with
// bevelled edges, a ramp's wedge.
//
// Points are snapped to a grid of 2^-20 m (about 1 micrometre) before
// anything else, so that every coordinate is an integer of at most 27 bits
// (|coordinate| <= 50 m) and every orientation test (the sign of a triple
// product of differences) is exact in 128-bit integers: the builder has no
// tolerance in its topology, and the same points give the same hull on
// every build. Faces that are coplanar, exactly or within
// `hull_coplanar_tolerance`, are merged into one polygon (a cube has 6
// square faces, not 12 triangles): a face's clipping polygon is what gives
// a resting hull its manifold.
//
// Limits (each refused with a one-line reason, never silently trimmed):
//   - 4..max_hull_points input points, each coordinate within 50 m of the
//     shape's origin;
//   - at most max_hull_vertices vertices on the hull (the separating-axis
//     test is quadratic in the edges: a game's props have 8..32);
//   - not flat: its thinnest width (the least, over faces, of the farthest
//     vertex's distance behind the face) at least hull_min_width.
#pragma once

#include <cstdint>
#include <memory>
#include <vector>

#include "core/error.h"
#include "fixed/decimal.h"
#include "fixed/mat33.h"

namespace bitstep {

using namespace bitstep::literals;

inline constexpr int max_hull_points = 1024;
inline constexpr int max_hull_vertices = 32;
// The grid the points are snapped to: 2^-hull_grid_bits m.
inline constexpr int hull_grid_bits = 20;
// m: the thinnest hull, the envelope's smallest box (0.01 m half extent).
inline constexpr Fixed hull_min_width = 0.02_fx;
// m: a vertex this close to a neighbouring face's plane merges the two faces.
inline constexpr Fixed hull_coplanar_tolerance = 0.0001_fx;

struct ConvexHull {
  struct Face {
    Vec3 normal;         // unit, outward, shape frame
    Fixed offset;        // dot(normal, x) for the points x of its plane
    uint16_t first = 0;  // its loop: face_vertices[first, first + count), counter-clockwise seen from outside
    uint16_t count = 0;  // >= 3
  };
  // Each edge once. Its two faces: `face` has tail -> head in its loop,
  // `twin_face` has head -> tail.
  struct Edge {
    uint16_t tail = 0, head = 0;
    uint16_t face = 0, twin_face = 0;
  };

  std::vector<Vec3> vertices;  // shape frame, on the grid; the input's points that are corners, in input order
  std::vector<Face> faces;
  std::vector<uint16_t> face_vertices;
  std::vector<Edge> edges;
  std::vector<Vec3> edge_directions;  // unit, tail to head, by edge

  Fixed volume;        // m^3
  Vec3 centroid;       // m, shape frame
  Mat33 unit_inertia;  // per kg (m^2): the inertia tensor about the centroid, shape axes, divided by the mass
  Fixed extent;        // m: the farthest vertex's distance from the shape's origin
};

// The hull of `points` (shape frame, m), or why not ("3 points: a hull
// needs 4 to 1024", "flat: 0.004 m thick, at least 0.02 m", "40 corners,
// at most 32", "points[7].y: outside -50..50 m"). Deterministic: a pure
// function of the points and their order, and build_convex_hull(
// hull.vertices) gives the same hull again (a state image stores only the
// vertices).
Result<std::shared_ptr<const ConvexHull>> build_convex_hull(const std::vector<Vec3>& points);

}  // namespace bitstep
