// The generic convex path: a hull against every shape, and a box against a
// hull, over polyhedra (core/polyhedron.h) and support functions.
//
// Two polyhedra (hull-hull, hull-box): the separating axis test of
// Gregorius ("The Separating Axis Test between Convex Polyhedra", GDC
// 2013), as Jolt and Box2D's polygon collider run it. The candidate axes
// are each face normal of either shape, and the cross product of each pair
// of edges whose arcs cross on the Gauss map (the only edge pairs that can
// form a face of the Minkowski difference; the rest are skipped without a
// square root). All of it runs in A's frame, B's corners and planes moved
// into it once. Then, as box-box does: a face axis clips the incident face
// (the other shape's face most against the normal) to the reference face's
// side planes, up to four points kept by area; an edge axis gives one point
// between the two edges.
//
// A hull with a ball or a capsule: GJK (core/gjk.h) on the cores, the
// hull's own corners and the capsule's segment, when they are apart (the
// usual case: the radius meets the hull); when the core reaches inside the
// hull, its faces' planes decide (the least deep face). A capsule lying
// along a face gets its segment clipped to that face: two points, so it
// does not rock.
//
// A hull and a plane: its corners below the plane, four kept by area.
#include <array>

#include "core/collide_internal.h"
#include "core/gjk.h"
#include "core/polyhedron.h"
#include "core/ray_cast.h"

namespace bitstep::collide_detail {

// Named: the unity build puts this file beside collide_box_box.cpp, whose
// unnamed namespace has a ClipVertex and a Candidate of its own.
namespace hull_pairs {

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

void place(const Polyhedron& shape, const Mat33& r, Vec3 t, Framed& out) {
  out.shape = shape;
  out.vertex_count = shape.vertices.size();
  out.face_count = shape.faces.size();
  for (size_t i = 0; i < out.vertex_count; ++i) out.vertices[i] = r * shape.vertices[i] + t;
  for (size_t f = 0; f < out.face_count; ++f) {
    const ConvexHull::Face& face = shape.faces[f];
    out.normals[f] = r * face.normal;
    out.offsets[f] = face.offset + dot(out.normals[f], t);  // n' . (R x + t) = n . x + n' . t
  }
  for (size_t e = 0; e < shape.edges.size(); ++e) out.directions[e] = r * shape.edge_directions[e];
  out.inside = r * shape.inside + t;
}

struct FaceQuery {
  Fixed separation = Fixed::lowest();
  size_t face = 0;
};

// The face of p along whose normal q reaches least far below it: the
// separation of q's lowest corner above each face plane, the largest.
FaceQuery query_faces(const Framed& p, const Framed& q) {
  FaceQuery best;
  for (size_t f = 0; f < p.face_count; ++f) {
    Fixed lowest = Fixed::max();
    for (size_t j = 0; j < q.vertex_count; ++j) lowest = min(lowest, dot(p.normals[f], q.vertices[j]));
    const Fixed separation = lowest - p.offsets[f];
    if (separation > best.separation) best = {separation, f};
  }
  return best;
}

struct EdgeQuery {
  Fixed separation = Fixed::lowest();
  bool found = false;
  size_t edge_a = 0, edge_b = 0;
  Vec3 normal;  // unit, away from A
};

// -1, 0 or +1.
int sign(Fixed x) { return x < Fixed{} ? -1 : (x > Fixed{} ? 1 : 0); }

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
EdgeQuery query_edges(const Framed& a, const Framed& b) {
  EdgeQuery best;
  std::array<int, max_faces> b_side;  // sign(n_B . direction_A), by B's face
  for (size_t i = 0; i < a.shape.edges.size(); ++i) {
    const ConvexHull::Edge& ea = a.shape.edges[i];
    const Vec3 tail_a = a.vertices[ea.tail];
    const Vec3 direction_a = a.directions[i];
    for (size_t g = 0; g < b.face_count; ++g) b_side[g] = sign(dot(b.normals[g], direction_a));
    for (size_t j = 0; j < b.shape.edges.size(); ++j) {
      const ConvexHull::Edge& eb = b.shape.edges[j];
      // c . b_x_a = -b_side[face], d . b_x_a = -b_side[twin] (c, d negated).
      const int cba = -b_side[eb.face], dba = -b_side[eb.twin_face];
      if (cba * dba >= 0) continue;
      const Vec3 direction_b = b.directions[j];
      const int adc = sign(dot(a.normals[ea.face], direction_b)), bdc = sign(dot(a.normals[ea.twin_face], direction_b));
      if (adc * bdc >= 0 || cba * bdc <= 0) continue;
      const Vec3 axis = cross(direction_a, direction_b);
      if (length_sq(axis) < parallel_cross_sq_tolerance) continue;  // parallel edges: a face axis decides
      Vec3 normal = normalize(axis);
      if (dot(normal, tail_a - a.inside) < Fixed{}) normal = -normal;
      const Fixed separation = dot(normal, b.vertices[eb.tail] - tail_a);
      if (separation > best.separation) best = {separation, true, i, j, normal};
    }
  }
  return best;
}

// A corner of the polygon being clipped, with the tag of the polygon edge
// that leaves it; its feature is (the previous corner's tag, its tag).
struct ClipVertex {
  Vec3 p;
  uint32_t out_edge = 0;
};

// Sutherland-Hodgman: keeps the part of the polygon with s . (x - a) <= 0.
int clip(const ClipVertex* in, int count, Vec3 s, Vec3 a, uint32_t plane_tag, ClipVertex* out) {
  int kept = 0;
  for (int i = 0; i < count && kept < clip_capacity - 1; ++i) {
    const ClipVertex& from = in[i];
    const ClipVertex& to = in[i + 1 < count ? i + 1 : 0];
    const Fixed d_from = dot(s, from.p - a), d_to = dot(s, to.p - a);
    const bool from_inside = d_from <= Fixed{}, to_inside = d_to <= Fixed{};
    if (from_inside) out[kept++] = from;
    if (from_inside != to_inside) {
      // x = from + (to - from) d_from / (d_from - d_to): the signs differ, so
      // the divisor is not zero and the ratio lies in [0, 1].
      const Fixed denominator = d_from - d_to;
      const Vec3 delta = to.p - from.p;
      const Vec3 x{from.p.x + mul_div(delta.x, d_from, denominator), from.p.y + mul_div(delta.y, d_from, denominator),
                   from.p.z + mul_div(delta.z, d_from, denominator)};
      out[kept++] = {x, from_inside ? plane_tag : from.out_edge};
    }
  }
  return kept;
}

struct Candidate {
  Vec3 p;  // A's frame, midway between the surfaces
  Fixed depth;
  FeatureId feature;
};

// Four of `count` > 4 points (choose_four), areas about `normal`.
int reduce_to_four(const Candidate* c, int count, Vec3 normal, int* chosen) {
  return choose_four(
      count, [&](int i) { return c[i].depth; }, [&](int from, int to) { return length_sq(c[to].p - c[from].p); },
      [&](int from, int to, int i) { return dot(cross(c[to].p - c[from].p, c[i].p - c[from].p), normal); }, chosen);
}

// The candidates into `out`, A's frame to the world, four at most.
int emit(const Candidate* c, int count, Vec3 normal_in_a, const Pose& pose_a, const Mat33& rot_a, Manifold& out) {
  int chosen[max_manifold_points] = {0, 1, 2, 3};
  if (count > max_manifold_points) count = reduce_to_four(c, count, normal_in_a, chosen);
  for (int k = 0; k < count; ++k) {
    const Candidate& p = c[chosen[k]];
    add_point(out, pose_a.position + rot_a * p.p, p.depth, p.feature);
  }
  return count;
}

// The incident face of q (most against the reference normal) clipped to
// reference face f of p; depths below p's face. kind 1: p is A.
int face_contact(const Framed& p, size_t f, const Framed& q, uint32_t kind, Fixed speculative_distance,
                 Candidate* candidates) {
  const Vec3 n = p.normals[f];
  size_t incident = 0;
  Fixed most_against = Fixed::max();
  for (size_t g = 0; g < q.face_count; ++g) {
    const Fixed along = dot(q.normals[g], n);
    if (along < most_against) {
      most_against = along;
      incident = g;
    }
  }
  std::array<ClipVertex, clip_capacity> buffer_1, buffer_2;
  const ConvexHull::Face& in_face = q.shape.faces[incident];
  int count = in_face.count;
  for (uint16_t i = 0; i < in_face.count; ++i) {
    buffer_1[i] = {q.vertices[q.shape.face_vertices[in_face.first + i]], i};
  }
  ClipVertex* in = buffer_1.data();
  ClipVertex* out = buffer_2.data();
  const ConvexHull::Face& ref_face = p.shape.faces[f];
  for (uint16_t i = 0; i < ref_face.count && count > 0; ++i) {
    const Vec3 a = p.vertices[p.shape.face_vertices[ref_face.first + i]];
    const Vec3 b = p.vertices[p.shape.face_vertices[ref_face.first + (i + 1u) % ref_face.count]];
    count = clip(in, count, cross(b - a, n), a, side_plane_tag + i, out);
    std::swap(in, out);
  }
  int kept = 0;
  for (int i = 0; i < count; ++i) {
    const Fixed depth = p.offsets[f] - dot(n, in[i].p);
    if (depth <= -speculative_distance) continue;
    const uint32_t previous = in[i > 0 ? i - 1 : count - 1].out_edge;
    const FeatureId feature = kind << 24 | static_cast<uint32_t>(f) << 18 | static_cast<uint32_t>(incident) << 12 |
                              previous << 6 | in[i].out_edge;
    candidates[kept++] = {mul_add(n, depth * half, in[i].p), depth, feature};
  }
  return kept;
}

// One point between A's and B's edges of the query.
int edge_contact(const Framed& a, const Framed& b, const EdgeQuery& query, Candidate* candidates) {
  const ConvexHull::Edge& ea = a.shape.edges[query.edge_a];
  const ConvexHull::Edge& eb = b.shape.edges[query.edge_b];
  const Vec3 start_a = a.vertices[ea.tail], start_b = b.vertices[eb.tail];
  const Vec3 along_a = a.vertices[ea.head] - start_a, along_b = b.vertices[eb.head] - start_b;
  const SegmentParams params = closest_segment_params(start_a, along_a, start_b, along_b);
  const Vec3 point_a = mul_add(along_a, params.s, start_a), point_b = mul_add(along_b, params.t, start_b);
  const FeatureId feature = 3u << 24 | static_cast<uint32_t>(query.edge_a) << 12 | static_cast<uint32_t>(query.edge_b);
  candidates[0] = {(point_a + point_b) * half, -query.separation, feature};
  return 1;
}

// Whether the centres are farther apart than the shapes reach (per axis
// first, so that no square of a far offset is formed).
bool out_of_reach(Vec3 offset, Fixed reach) {
  if (!within_axes(offset, reach)) return true;
  return length_sq(offset) > reach * reach;
}

int collide_polyhedra(const Polyhedron& shape_a, Fixed extent_a, const WorldShape& a, const Polyhedron& shape_b,
                      Fixed extent_b, const WorldShape& b, Fixed speculative_distance, Manifold& out) {
  const Vec3 offset = b.pose.position - a.pose.position;
  if (out_of_reach(offset, extent_a + extent_b + speculative_distance)) return 0;
  const Mat33 rot_a = axes_of(a), to_a = transpose(rot_a);
  Framed fa, fb;
  place(shape_a, Mat33::identity(), Vec3{}, fa);
  place(shape_b, to_a * axes_of(b), to_a * offset, fb);

  const FaceQuery faces_a = query_faces(fa, fb);
  if (faces_a.separation > speculative_distance) return 0;
  const FaceQuery faces_b = query_faces(fb, fa);
  if (faces_b.separation > speculative_distance) return 0;
  const EdgeQuery edges = query_edges(fa, fb);
  if (edges.separation > speculative_distance) return 0;

  // The preferred axis: a face of A, then one of B, then an edge pair, each
  // taking over only when better by the hysteresis margin.
  enum class Kind { face_a, face_b, edge } kind = Kind::face_a;
  Fixed best = faces_a.separation;
  if (faces_b.separation > best + margin(best)) {
    kind = Kind::face_b;
    best = faces_b.separation;
  }
  if (edges.found && edges.separation > best + margin(best)) kind = Kind::edge;

  std::array<Candidate, clip_capacity> candidates;
  int count = 0;
  Vec3 normal;  // A's frame, from A to B
  switch (kind) {
    case Kind::face_a:
      count = face_contact(fa, faces_a.face, fb, 1, speculative_distance, candidates.data());
      normal = fa.normals[faces_a.face];
      break;
    case Kind::face_b:
      count = face_contact(fb, faces_b.face, fa, 2, speculative_distance, candidates.data());
      normal = -fb.normals[faces_b.face];
      break;
    case Kind::edge:
      count = edge_contact(fa, fb, edges, candidates.data());
      normal = edges.normal;
      break;
  }
  if (count == 0) return 0;
  out.normal = normalize(rot_a * normal);  // unit to a few ulps: the rotation adds its own
  return emit(candidates.data(), count, normal, a.pose, rot_a, out);
}

Polyhedron hull_polyhedron(const WorldShape& s) { return polyhedron_of(*s.shape->hull); }

// The hull's face whose plane `point` (hull frame) lies least far below,
// for a core that reached inside.
FaceQuery shallowest_face(const ConvexHull& hull, Vec3 first, Vec3 second) {
  FaceQuery best;
  for (size_t f = 0; f < hull.faces.size(); ++f) {
    const ConvexHull::Face& face = hull.faces[f];
    const Fixed separation = min(dot(face.normal, first), dot(face.normal, second)) - face.offset;
    if (separation > best.separation) best = {separation, f};
  }
  return best;
}

// The hull's face whose normal lies nearest `direction` (hull frame).
size_t face_toward(const ConvexHull& hull, Vec3 direction) {
  size_t best = 0;
  for (size_t f = 1; f < hull.faces.size(); ++f) {
    if (dot(hull.faces[f].normal, direction) > dot(hull.faces[best].normal, direction)) {
      best = f;
    }
  }
  return best;
}

// The segment from..to (hull frame) clipped to face f's side planes, as
// parameters 0 <= lo <= hi <= 1; false when nothing is left.
bool clip_segment_to_face(const ConvexHull& hull, size_t f, Vec3 from, Vec3 to, Fixed& lo, Fixed& hi) {
  const ConvexHull::Face& face = hull.faces[f];
  lo = Fixed{};
  hi = Fixed::one();
  for (uint16_t i = 0; i < face.count; ++i) {
    const Vec3 a = hull.vertices[hull.face_vertices[face.first + i]];
    const Vec3 b = hull.vertices[hull.face_vertices[face.first + (i + 1u) % face.count]];
    const Vec3 s = cross(b - a, face.normal);
    const Fixed d_from = dot(s, from - a), d_to = dot(s, to - a);
    if (d_from > Fixed{} && d_to > Fixed{}) return false;
    if (d_from > Fixed{}) lo = max(lo, d_from / (d_from - d_to));
    if (d_to > Fixed{}) hi = min(hi, d_from / (d_from - d_to));
    if (lo > hi) return false;
  }
  return true;
}

// Balls of radius r along the segment from..to (hull frame) between
// parameters lo and hi, against face f: a point at each end.
int segment_face_points(const ConvexHull& hull, size_t f, Vec3 from, Vec3 to, Fixed lo, Fixed hi, Fixed r,
                        Fixed speculative_distance, Candidate* candidates) {
  const ConvexHull::Face& face = hull.faces[f];
  int count = 0;
  const Fixed ends[2] = {lo, hi};
  for (int end = 0; end < 2; ++end) {
    if (end == 1 && hi == lo) break;
    const Vec3 x = mul_add(to - from, ends[end], from);
    const Fixed height = dot(face.normal, x) - face.offset;
    const Fixed depth = r - height;
    if (depth <= -speculative_distance) continue;
    // Midway between the ball's lowest point x - n r and the face's x - n height.
    candidates[count++] = {x - face.normal * ((height + r) * half), depth, static_cast<FeatureId>(16 + end)};
  }
  return count;
}

// The separating axis across a hull edge and the segment from..to (hull
// frame) along which the segment lies least deep, over the edges whose
// Gauss-map arc crosses the segment's great circle (their faces' normals
// on either side of the plane across the segment): only there is the edge
// the hull's reach along segment x edge. Separation: the segment's lower
// end above the edge, along the axis turned away from the hull's inside.
EdgeQuery segment_edge_axis(const ConvexHull& hull, Vec3 from, Vec3 to) {
  EdgeQuery best;
  const Vec3 direction = normalize(to - from);
  for (size_t i = 0; i < hull.edges.size(); ++i) {
    const ConvexHull::Edge& edge = hull.edges[i];
    const Fixed side_a = dot(hull.faces[edge.face].normal, direction);
    const Fixed side_b = dot(hull.faces[edge.twin_face].normal, direction);
    if (sign(side_a) * sign(side_b) >= 0) continue;
    const Vec3 tail = hull.vertices[edge.tail];
    const Vec3 axis = cross(direction, normalize(hull.vertices[edge.head] - tail));
    if (length_sq(axis) < parallel_cross_sq_tolerance) continue;
    Vec3 normal = normalize(axis);
    if (dot(normal, tail - hull.centroid) < Fixed{}) normal = -normal;
    const Fixed separation = min(dot(normal, from), dot(normal, to)) - dot(normal, tail);
    if (separation > best.separation) best = {separation, true, i, 0, normal};
  }
  return best;
}

// One point between the segment (swept by r) and the hull edge of `across`.
Candidate segment_edge_point(const ConvexHull& hull, const EdgeQuery& across, Vec3 from, Vec3 to, Fixed r) {
  const ConvexHull::Edge& edge = hull.edges[across.edge_a];
  const Vec3 tail = hull.vertices[edge.tail], along = hull.vertices[edge.head] - tail;
  const SegmentParams params = closest_segment_params(from, to - from, tail, along);
  const Vec3 on_segment = mul_add(to - from, params.s, from), on_edge = mul_add(along, params.t, tail);
  // Midway between the capsule's surface (on_segment - n r) and the edge.
  const Vec3 n = across.normal;
  return {(on_segment - n * r + on_edge) * half, r - across.separation, 1};
}

// A ball or capsule (its core the segment from..to in the world, a point
// when they coincide) against a hull.
int collide_hull_rounded(const WorldShape& hull_shape, const WorldShape& other, Vec3 from, Vec3 to, Fixed r,
                         Fixed speculative_distance, Manifold& out) {
  const ConvexHull& hull = *hull_shape.shape->hull;
  const Vec3 offset = other.pose.position - hull_shape.pose.position;
  if (out_of_reach(offset, hull.extent + length(to - from) + r + speculative_distance)) return 0;
  const Mat33 rot = axes_of(hull_shape), to_hull = transpose(rot);
  const Vec3 from_local = to_hull * (from - hull_shape.pose.position);
  const Vec3 to_local = to_hull * (to - hull_shape.pose.position);
  const bool segment = from != to;
  std::array<Candidate, 2> candidates;
  int count = 0;
  Vec3 normal;  // hull frame, from the hull out

  const ConvexDistance d = convex_distance(hull_shape, other);
  if (!d.overlap) {
    if (d.distance > speculative_distance) return 0;
    normal = to_hull * d.normal;
    // A capsule along the face the normal leaves: its segment clipped to it.
    const size_t along = face_toward(hull, normal);
    if (segment) {
      const Vec3 face_normal = hull.faces[along].normal;
      const Vec3 direction = normalize(to_local - from_local);
      const Fixed tilt = dot(direction, face_normal);
      Fixed lo, hi;
      if (length_sq(cross(face_normal, normal)) <= capsule_parallel_sq_tolerance &&
          tilt * tilt <= capsule_parallel_sq_tolerance &&
          clip_segment_to_face(hull, along, from_local, to_local, lo, hi) && hi - lo > min_overlap_length) {
        count =
            segment_face_points(hull, along, from_local, to_local, lo, hi, r, speculative_distance, candidates.data());
        normal = face_normal;
      }
    }
    if (count == 0) {
      const Vec3 middle = (d.point_a + d.point_b) * half;
      candidates[0] = {to_hull * (middle - hull_shape.pose.position), -d.distance, 0};
      count = 1;
    }
  } else {
    // The core reached inside: out through the face it lies least deep
    // below, or across an edge where the segment crosses it less deep.
    const FaceQuery shallowest = shallowest_face(hull, from_local, to_local);
    if (segment) {
      const EdgeQuery across = segment_edge_axis(hull, from_local, to_local);
      if (across.found && across.separation > shallowest.separation + margin(shallowest.separation)) {
        candidates[0] = segment_edge_point(hull, across, from_local, to_local, r);
        out.normal = normalize(rot * across.normal);
        return emit(candidates.data(), 1, across.normal, hull_shape.pose, rot, out);
      }
    }
    normal = hull.faces[shallowest.face].normal;
    Fixed lo = Fixed{}, hi = Fixed{};
    if (segment && !clip_segment_to_face(hull, shallowest.face, from_local, to_local, lo, hi)) {
      lo = hi = dot(normal, from_local) <= dot(normal, to_local) ? Fixed{} : Fixed::one();  // the deeper end
    }
    count = segment_face_points(hull, shallowest.face, from_local, to_local, lo, hi, r, speculative_distance,
                                candidates.data());
    if (!segment) candidates[0].feature = 0;
  }
  if (count == 0) return 0;
  out.normal = normalize(rot * normal);
  return emit(candidates.data(), count, normal, hull_shape.pose, rot, out);
}

}  // namespace hull_pairs

using hull_pairs::collide_hull_rounded;
using hull_pairs::collide_polyhedra;
using hull_pairs::emit;
using hull_pairs::hull_polyhedron;

int collide_hull_hull(const WorldShape& a, const WorldShape& b, Fixed speculative_distance, Manifold& out) {
  return collide_polyhedra(hull_polyhedron(a), a.shape->hull->extent, a, hull_polyhedron(b), b.shape->hull->extent, b,
                           speculative_distance, out);
}

int collide_hull_box(const WorldShape& hull, const WorldShape& box, Fixed speculative_distance, Manifold& out) {
  const BoxPolyhedron box_shape(box.shape->half_extents);
  return collide_polyhedra(hull_polyhedron(hull), hull.shape->hull->extent, hull, box_shape.view(),
                           length(box.shape->half_extents), box, speculative_distance, out);
}

int collide_hull_sphere(const WorldShape& hull, const WorldShape& sphere, Fixed speculative_distance, Manifold& out) {
  const Vec3 c = sphere.pose.position;
  return collide_hull_rounded(hull, sphere, c, c, sphere.shape->radius, speculative_distance, out);
}

int collide_hull_capsule(const WorldShape& hull, const WorldShape& capsule, Fixed speculative_distance, Manifold& out) {
  const Vec3 axis = axes_of(capsule).column(1) * capsule.shape->half_height;
  return collide_hull_rounded(hull, capsule, capsule.pose.position - axis, capsule.pose.position + axis,
                              capsule.shape->radius, speculative_distance, out);
}

int collide_hull_plane(const WorldShape& hull_shape, const WorldShape& plane, Fixed speculative_distance,
                       Manifold& out) {
  const ConvexHull& hull = *hull_shape.shape->hull;
  const Vec3 n = plane_normal(plane);
  const Fixed centre_height = dot(n, hull_shape.pose.position - plane.pose.position);
  if (centre_height - hull.extent >= speculative_distance) return 0;
  const Mat33 rot = axes_of(hull_shape);
  const Vec3 n_hull = transpose(rot) * n;
  std::array<hull_pairs::Candidate, max_hull_vertices> candidates;
  int count = 0;
  for (size_t v = 0; v < hull.vertices.size(); ++v) {
    const Fixed depth = -(centre_height + dot(n_hull, hull.vertices[v]));
    if (depth <= -speculative_distance) continue;
    // Midway: up from the corner by half the depth.
    candidates[static_cast<size_t>(count++)] = {mul_add(n_hull, depth * half, hull.vertices[v]), depth,
                                                static_cast<FeatureId>(v)};
  }
  if (count == 0) return 0;
  out.normal = -n;  // from the hull into the plane
  return emit(candidates.data(), count, n_hull, hull_shape.pose, rot, out);
}

}  // namespace bitstep::collide_detail
