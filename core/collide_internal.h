// The narrowphase's insides: one function per pair of shape types, and the
// small geometric helpers they share. collide() (core/collide.cpp) swaps the
// two shapes so that each pair is written once, in the order
//   mesh > hull > capsule > sphere > box > plane
// (the first argument has the higher rank), and flips the normal back.
//
// Every pair function fills `out` (normal from its first shape to its second,
// points, feature ids; impulses stay zero) and returns the point count. The
// conventions are those of core/collide.h and core/manifold.h: depth > 0 is
// overlap, points lie midway between the two surfaces, and only points with
// depth > -speculative_distance are reported.
//
// Work is done relative to one of the shapes' centres (or in a box's frame),
// never with absolute world coordinates in products, and every pair first
// rejects shapes whose centres are farther apart than their sizes allow, so
// nothing overflows for positions up to 16 km (the world envelope).
#pragma once

#include "core/collide.h"
#include "core/settings.h"
#include "fixed/mat33.h"

namespace bitstep::collide_detail {

// --- tolerances (unit in brackets) ------------------------------------------

// Axis choice hysteresis (box-box and capsule-box): a candidate axis replaces
// the preferred one only if its separation is larger by
//   axis_relative_tolerance * |preferred separation| + axis_absolute_tolerance.
// The preference order is: a face of the first shape, a face of the second,
// an edge-edge axis. Like Box2D (0.1 * linear slop) and qu3e (0.95 / 0.01),
// this keeps the reference face from flipping between steps when two axes
// are nearly as good (a resting stack has both boxes' faces at separation ~0,
// and a box turned about the normal has edge axes equal to the face axis),
// and the relative part grows with the overlap so that a deep contact does
// not flip either. The chosen axis's separation is never more than this
// margin below the true one.
inline constexpr Fixed axis_relative_tolerance = 0.05_fx;    // 1
inline constexpr Fixed axis_absolute_tolerance = 0.0005_fx;  // m (0.1 x the default penetration slop)

// A candidate axis of a separating-axis test: its separation and which one.
struct Axis {
  Fixed separation;  // m, > 0: apart along this axis
  int index = -1;
};

// How much better a later-preferred axis must be than one of `separation`.
inline Fixed margin(Fixed separation) {
  return mul_add(axis_relative_tolerance, abs(separation), axis_absolute_tolerance);
}

// Edge-edge axes a x b with |a x b|^2 below this are skipped: the edges are
// within ~0.06 degrees of parallel and a face axis describes the contact.
inline constexpr Fixed parallel_cross_sq_tolerance = 0.000001_fx;  // 1 (sin^2 of the angle)

// Box-box: an edge-edge axis this close to a face normal of either box
// (sin^2 of the angle between them; 0.0004 is about 1.15 degrees) is that
// face's contact, clipped. Two nearly parallel edges, one lying along the other
// box's face, touch along a segment; their closest points jump from one end
// of it to the other as the angle between them changes sign. A ragdoll's
// chest lying across a stair's edge (the edges a degree or two apart, the
// normal a fraction of a degree from the chest's face normal) would rock
// between two points far apart, lose its warm start every step and creep
// on for ever. The edge axis wins on separation there only because the
// face axis counts the whole box: a long stair reaches deeper at its far
// ends, which the clipping leaves out.
inline constexpr Fixed face_aligned_edge_sq_tolerance = 0.0004_fx;  // 1

// Capsule-capsule: segments this close to parallel (sin^2 of the angle;
// 0.0004 is about 1.15 degrees, Jolt's capsule projection slop 0.02) that
// overlap along their axis by more than `min_overlap_length` give two points,
// so a capsule lying on another one does not roll by itself.
inline constexpr Fixed capsule_parallel_sq_tolerance = 0.0004_fx;  // 1
inline constexpr Fixed min_overlap_length = 0.0001_fx;             // m

// Segment lengths^2 below this count as points in closest-point queries.
inline constexpr Fixed degenerate_length_sq = 0.00000001_fx;  // m^2

inline constexpr Fixed half = 0.5_fx;

// --- pair functions ------------------------------------------------------------

int collide_box_box(const WorldShape& a, const WorldShape& b, Fixed speculative_distance, Manifold& out);
int collide_box_plane(const WorldShape& box, const WorldShape& plane, Fixed speculative_distance, Manifold& out);
int collide_sphere_sphere(const WorldShape& a, const WorldShape& b, Fixed speculative_distance, Manifold& out);
int collide_sphere_box(const WorldShape& sphere, const WorldShape& box, Fixed speculative_distance, Manifold& out);
int collide_sphere_plane(const WorldShape& sphere, const WorldShape& plane, Fixed speculative_distance, Manifold& out);
int collide_capsule_capsule(const WorldShape& a, const WorldShape& b, Fixed speculative_distance, Manifold& out);
int collide_capsule_box(const WorldShape& capsule, const WorldShape& box, Fixed speculative_distance, Manifold& out);
int collide_capsule_sphere(const WorldShape& capsule, const WorldShape& sphere, Fixed speculative_distance,
                           Manifold& out);
int collide_capsule_plane(const WorldShape& capsule, const WorldShape& plane, Fixed speculative_distance,
                          Manifold& out);
int collide_hull_hull(const WorldShape& a, const WorldShape& b, Fixed speculative_distance, Manifold& out);
int collide_hull_box(const WorldShape& hull, const WorldShape& box, Fixed speculative_distance, Manifold& out);
int collide_hull_sphere(const WorldShape& hull, const WorldShape& sphere, Fixed speculative_distance, Manifold& out);
int collide_hull_capsule(const WorldShape& hull, const WorldShape& capsule, Fixed speculative_distance, Manifold& out);
int collide_hull_plane(const WorldShape& hull, const WorldShape& plane, Fixed speculative_distance, Manifold& out);
int collide_mesh_box(const WorldShape& mesh, const WorldShape& box, Fixed speculative_distance, Manifold& out);
int collide_mesh_hull(const WorldShape& mesh, const WorldShape& hull, Fixed speculative_distance, Manifold& out);
int collide_mesh_sphere(const WorldShape& mesh, const WorldShape& sphere, Fixed speculative_distance, Manifold& out);
int collide_mesh_capsule(const WorldShape& mesh, const WorldShape& capsule, Fixed speculative_distance, Manifold& out);

// --- feature ids -----------------------------------------------------------------
//
// Box-box (bits): kind << 16 | p << 12 | q << 8 | r << 4 | s, with
//   kind 1: face contact, reference face on A;  kind 2: reference face on B;
//           p = reference face, q = incident face (face = 2 * axis + (negative side)),
//           r, s = the two clipped-polygon edges meeting at the point (its
//           incoming and outgoing edge): 0..3 the incident face's edges, 4..7 the
//           reference face's side planes. An incident vertex is (edge m-1, edge m),
//           an incident edge clipped by a side plane is (edge, plane) or (plane,
//           edge), a reference corner is (plane, plane). This is qu3e's
//           q3FeaturePair in another encoding: it does not change when the boxes
//           move a little, only when the clipping topology changes.
//   kind 3: edge-edge, p = A's edge, q = B's edge (edge = 4 * axis + sign bits of
//           the two other coordinates), r = s = 0.
// Box-plane: the box vertex (bit k set: + half extent along axis k).
// Capsule-plane: 0 for the -half_height end, 1 for the +half_height end.
// Capsule-capsule: 0 for one closest point, 1 and 2 for the two ends of the
// overlap of parallel segments.
// Capsule-box: 0 for one closest point, 1 for the point on a box edge when
// the segment passes through the box, 16 + 2 * face + end for the segment
// clipped to a face (end 0: towards -half_height).
// Hull-hull and hull-box (collide_hull.cpp; the box as a polyhedron,
// core/polyhedron.h): kind << 24 | p << 18 | q << 12 | r << 6 | s for a
// face contact, kind 1 with the reference face on A, 2 on B, p and q the
// reference and incident faces, r and s the clipped polygon's edges at the
// point (0..31 the incident loop's edges, 32 + i the reference face's side
// plane i); 3 << 24 | A's edge << 12 | B's edge for an edge contact.
// Hull-plane: the hull's corner. Hull-capsule: 0 for one point, 16 + end
// for the segment clipped to a face; hull-sphere: 0.
// Sphere-*, capsule-sphere: 0 (one point; a sphere rolling across features
// keeps its warm start).
constexpr FeatureId box_feature(uint32_t kind, uint32_t p, uint32_t q, uint32_t r, uint32_t s) {
  return kind << 16 | p << 12 | q << 8 | r << 4 | s;
}

// --- helpers -------------------------------------------------------------------

constexpr Fixed get(Vec3 v, int k) { return k == 0 ? v.x : (k == 1 ? v.y : v.z); }
constexpr void set(Vec3& v, int k, Fixed value) {
  if (k == 0)
    v.x = value;
  else if (k == 1)
    v.y = value;
  else
    v.z = value;
}
constexpr Vec3 row(const Mat33& m, int k) { return m.rows[static_cast<size_t>(k)]; }
constexpr Vec3 unit_axis(int k) {
  Vec3 v;
  set(v, k, Fixed::one());
  return v;
}
// a * b - c * d, rounded once.
constexpr Fixed det2(Fixed a, Fixed b, Fixed c, Fixed d) {
  return Fixed::from_raw(raw::mul_sub_mul<Wide>(a.raw(), b.raw(), c.raw(), d.raw()));
}
// +1 or -1 as Fixed; zero counts as positive (ties go one fixed way).
constexpr Fixed sign_of(Fixed v) { return v < Fixed{} ? -Fixed::one() : Fixed::one(); }

// Appends a point; the caller keeps the count <= max_manifold_points.
inline void add_point(Manifold& out, Vec3 position, Fixed depth, FeatureId feature) {
  ContactPoint& p = out.points[static_cast<size_t>(out.point_count++)];
  p.position = position;
  p.depth = depth;
  p.feature = feature;
}

// Keeps four of `count` > 4 contact points (ties to the lower index): the
// deepest; the one farthest from it; then the one making the largest
// triangle with those two on each side of the line through them. This keeps
// the deepest point (the one that most needs pushing out) and spans the
// largest area (the most stable support), as Jolt's PruneContactPoints and
// Box2D v3's reduction do. depth(i), distance_sq(i, j) and area(i, j, k)
// (twice the signed area of the triangle i j k about the normal) are the
// caller's geometry. Writes the chosen indices in increasing order.
template <class Depth, class DistanceSq, class Area>
int choose_four(int count, Depth depth, DistanceSq distance_sq, Area area, int* chosen) {
  int deepest = 0;
  for (int i = 1; i < count; ++i) {
    if (depth(i) > depth(deepest)) deepest = i;
  }
  int farthest = -1;
  Fixed farthest_sq{};
  for (int i = 0; i < count; ++i) {
    const Fixed d_sq = distance_sq(deepest, i);
    if (d_sq > farthest_sq) {
      farthest_sq = d_sq;
      farthest = i;
    }
  }
  int n = 0;
  chosen[n++] = deepest;
  if (farthest < 0) return n;  // all points coincide
  chosen[n++] = farthest;
  int left = -1, right = -1;
  Fixed left_area{}, right_area{};
  for (int i = 0; i < count; ++i) {
    const Fixed a = area(deepest, farthest, i);
    if (a > left_area) {
      left_area = a;
      left = i;
    }
    if (a < right_area) {
      right_area = a;
      right = i;
    }
  }
  if (left >= 0) chosen[n++] = left;
  if (right >= 0) chosen[n++] = right;
  for (int i = 1; i < n; ++i) {  // insertion sort: output in polygon order
    for (int j = i; j > 0 && chosen[j - 1] > chosen[j]; --j) {
      const int swap = chosen[j];
      chosen[j] = chosen[j - 1];
      chosen[j - 1] = swap;
    }
  }
  return n;
}

// clamp(numerator / denominator, 0, 1) for denominator > 0, dividing only when
// the quotient lies inside (so it cannot overflow).
Fixed clamped_ratio(Fixed numerator, Fixed denominator);

// Beyond any ray or cast (m): path_ratio clamps quotients that would pass it.
inline constexpr Fixed far_distance = Fixed::from_int(1 << 20);

// gap / rate (|rate| <= 1, rate != 0) for distances along a ray or a cast's
// path, or +-far_distance where the quotient would pass it: |rate|
// far_distance cannot overflow, and the comparison keeps the division
// inside Q32.32.
Fixed path_ratio(Fixed gap, Fixed rate);

// Closest points of the segments p1 + s d1 and p2 + t d2, s, t in [0, 1]
// (Ericson, Real-Time Collision Detection 5.1.9). Parallel segments give
// s = 0 and the matching t. Inputs relative to a nearby origin (lengths and
// offsets up to a few hundred metres).
struct SegmentParams {
  Fixed s, t;
};
SegmentParams closest_segment_params(Vec3 p1, Vec3 d1, Vec3 p2, Vec3 d2);

// The parameter in [0, 1] of the point of segment p + t d closest to the line
// point q (clamped projection); a degenerate segment gives 0.
Fixed closest_param_to_point(Vec3 p, Vec3 d, Vec3 q);

// One point between a ball of radius_a at point_a and one of radius_b at
// point_b (both relative to `origin`): sphere-sphere, capsule-sphere,
// capsule-capsule. Normal from a to b, or the unit `fallback` when the
// points coincide.
int collide_points_with_radii(Vec3 origin, Vec3 point_a, Fixed radius_a, Vec3 point_b, Fixed radius_b, Vec3 fallback,
                              Fixed speculative_distance, Manifold& out);

// A shape's rotation matrix: the one it carries, else computed.
inline Mat33 axes_of(const WorldShape& s) { return s.axes ? *s.axes : rotation(s.pose.orientation); }

// Unit outward normal of a plane shape: its local +y in the world.
Vec3 plane_normal(const WorldShape& plane);

}  // namespace bitstep::collide_detail
