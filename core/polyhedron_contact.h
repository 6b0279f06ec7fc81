// The separating-axis pieces two polyhedra share (core/polyhedron.h), and
// a polyhedron with a mesh's triangle: each shape's corners, planes and
// edges moved into one frame, the face and edge queries, the clipping of an
// incident face to a reference face, and the choice of four points
// (collide_hull.cpp tells the method and its sources). Internal to core/.
#pragma once

#include <array>

#include "core/collide_internal.h"
#include "core/polyhedron.h"

namespace bitstep::collide_detail::polyhedra {

inline constexpr int max_faces = 2 * max_hull_vertices - 4;  // Euler, all faces triangles
inline constexpr int max_edges = 3 * max_hull_vertices - 6;
// A clipped polygon: an incident face of up to max_hull_vertices corners,
// each reference side plane adding at most one.
inline constexpr int clip_capacity = 2 * max_hull_vertices + 2;
// Feature tags of clipped-polygon edges: the incident loop's edges count
// from 0, the reference face's side planes from this.
inline constexpr uint32_t side_plane_tag = 32;

// A polyhedron's corners, face planes and edge directions in A's frame
// (x -> R x + t).
struct Framed {
  Polyhedron shape;
  size_t vertex_count = 0, face_count = 0;
  std::array<Vec3, max_hull_vertices> vertices;
  std::array<Vec3, max_faces> normals;
  std::array<Fixed, max_faces> offsets;
  std::array<Vec3, max_edges> directions;
  Vec3 inside;
};

void place(const Polyhedron& shape, const Mat33& r, Vec3 t, Framed& out);

struct FaceQuery {
  Fixed separation = Fixed::lowest();
  size_t face = 0;
};

// The face of p along whose normal q reaches least far below it: the
// separation of q's lowest corner above each face plane, the largest.
FaceQuery query_faces(const Framed& p, const Framed& q);

struct EdgeQuery {
  Fixed separation = Fixed::lowest();
  bool found = false;
  size_t edge_a = 0, edge_b = 0;
  Vec3 normal;  // unit, away from A
};

// -1, 0 or +1.
int sign(Fixed x);

// The pairs of A's and B's edges whose Gauss-map arcs cross: the arc of an
// edge joins the normals of its two faces, B's negated (the Minkowski
// difference A - B). Arcs a-b and c-d cross (Gregorius) when c and d lie
// on opposite sides of the plane of a-b, a and b on opposite sides of the
// plane of c-d, and c and b on the same sides:
//   (c . b_x_a) (d . b_x_a) < 0,  (a . d_x_c) (b . d_x_c) < 0,  (c . b_x_a) (b . d_x_c) > 0.
// Only signs count, so the planes' normals b x a and d x c may be any
// multiples of one sign: the edges' directions (with counter-clockwise
// loops, twin x face points from head to tail on both shapes, and the two
// flips cancel). The signs of B's face normals along A's edge are found
// once per A edge, for every B edge that shares the face.
//
// Of those pairs, the axis along which B lies farthest from A: across the
// two edges, turned away from A's inside.
EdgeQuery query_edges(const Framed& a, const Framed& b);

// A corner of the polygon being clipped, with the tag of the polygon edge
// that leaves it; its feature is (the previous corner's tag, its tag).
struct ClipVertex {
  Vec3 p;
  uint32_t out_edge = 0;
};

// Sutherland-Hodgman: keeps the part of the polygon with s . (x - a) <= 0.
int clip(const ClipVertex* in, int count, Vec3 s, Vec3 a, uint32_t plane_tag, ClipVertex* out);

struct Candidate {
  Vec3 p;  // A's frame, midway between the surfaces
  Fixed depth;
  FeatureId feature;
};

// Four of `count` > 4 points (choose_four), areas about `normal`.
int reduce_to_four(const Candidate* c, int count, Vec3 normal, int* chosen);

// The candidates into `out`, A's frame to the world, four at most.
int emit(const Candidate* c, int count, Vec3 normal_in_a, const Pose& pose_a, const Mat33& rot_a, Manifold& out);

// The incident face of q (most against the reference normal) clipped to
// reference face f of p; depths below p's face. kind 1: p is A.
int face_contact(const Framed& p, size_t f, const Framed& q, uint32_t kind, Fixed speculative_distance,
                 Candidate* candidates);

// The segment from..to clipped to the side planes of a convex polygon (its
// corners counter-clockwise about `normal`, corner(i) for i < count), as
// parameters 0 <= lo <= hi <= 1; false when nothing is left.
template <class Corner>
bool clip_segment(Corner corner, size_t count, Vec3 normal, Vec3 from, Vec3 to, Fixed& lo, Fixed& hi) {
  lo = Fixed{};
  hi = Fixed::one();
  for (size_t i = 0; i < count; ++i) {
    const Vec3 a = corner(i), s = cross(corner((i + 1) % count) - a, normal);  // outward in the plane
    const Fixed d_from = dot(s, from - a), d_to = dot(s, to - a);
    if (d_from > Fixed{} && d_to > Fixed{}) return false;
    if (d_from > Fixed{}) lo = max(lo, d_from / (d_from - d_to));
    if (d_to > Fixed{}) hi = min(hi, d_from / (d_from - d_to));
    if (lo > hi) return false;
  }
  return true;
}

}  // namespace bitstep::collide_detail::polyhedra
