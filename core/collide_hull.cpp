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
#include "core/polyhedron_contact.h"
#include "core/ray_cast.h"

namespace bitstep::collide_detail {

// Named: the unity build puts this file beside collide_box_box.cpp, whose
// unnamed namespace has a ClipVertex and a Candidate of its own.
namespace hull_pairs {

using polyhedra::Candidate;
using polyhedra::clip_capacity;
using polyhedra::EdgeQuery;
using polyhedra::face_contact;
using polyhedra::FaceQuery;
using polyhedra::Framed;
using polyhedra::place;
using polyhedra::query_edges;
using polyhedra::query_faces;
using polyhedra::sign;

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
  const auto corner = [&](size_t i) { return hull.vertices[hull.face_vertices[face.first + i]]; };
  return polyhedra::clip_segment(corner, face.count, face.normal, from, to, lo, hi);
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
using hull_pairs::hull_polyhedron;
using polyhedra::emit;

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
  std::array<polyhedra::Candidate, max_hull_vertices> candidates;
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
