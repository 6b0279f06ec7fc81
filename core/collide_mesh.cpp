// A static triangle mesh against a box, hull, sphere or capsule: each
// triangle near the shape (the mesh's tree, core/triangle_mesh.h) meets it
// as a one-sided convex polygon, and the triangles' points make one
// manifold.
//
// Per triangle, in the mesh's frame about the shape's centre (so products
// stay small however far the mesh reaches):
//   - a box or hull: the separating axis test over the triangle's normal
//     (one-sided: the shape is pushed to the front), the shape's face
//     normals, and each triangle edge crossed with each shape edge (every
//     pair: a triangle's Gauss map is two points, so the arc pruning of two
//     polyhedra does not apply); then the clipped face or the edge point as
//     for two hulls (polyhedron_contact.h);
//   - a sphere or capsule: GJK between the triangle and the core (a point
//     or a segment); a core that reaches the triangle's plane goes out
//     along the normal; a capsule along the face is clipped to it (2 points).
// A shape behind a triangle's plane is not touching it.
//
// No ghost bumps: a contact whose normal is not the triangle's own (an edge
// or corner contact) is kept only where the triangle's feature there is an
// active edge (the surface bends outward there, triangle_mesh.h); at an
// inactive edge it is the face's contact, along the face's normal. So a box
// sliding across a flat mesh meets faces only, never the edges between them.
//
// The manifold takes the deepest point's normal, the points whose normals
// lie within 15 degrees of it, and four of them by area, starting from the
// one as deep as the deepest and farthest out (choose_four_spread): a
// shape across a sharp ridge holds on its deeper side, and a face lying on
// several triangles keeps its corners.
#include <array>
#include <vector>

#include "core/collide_internal.h"
#include "core/gjk.h"
#include "core/polyhedron_contact.h"
#include "core/triangle_mesh.h"

namespace bitstep::collide_detail {

namespace mesh_pairs {

using polyhedra::Candidate;
using polyhedra::clip_capacity;
using polyhedra::face_contact;
using polyhedra::Framed;
using polyhedra::place;

// Points from triangles whose normals lie this close to the deepest's
// (cos 15 degrees) join its manifold.
constexpr Fixed same_surface_cos = 0.966_fx;

// A triangle's point, with the normal it pushes along (mesh frame).
struct MeshPoint {
  Candidate candidate;
  Vec3 normal;
};

// The shape in the mesh's frame about its own centre: its rotation there,
// and where its centre sits (mesh frame).
struct Relative {
  Mat33 rotation;
  Vec3 centre;
};

Relative relative_to(const WorldShape& mesh_shape, const WorldShape& other) {
  const Quat q = normalize(conjugate(mesh_shape.pose.orientation) * other.pose.orientation);
  return {rotation(q), mesh_shape.pose.apply_inverse(other.pose.position)};
}

// Triangle t about `centre`: its corners, plane and which edges are active.
struct Triangle {
  std::array<Vec3, 3> corners;
  Vec3 normal;
  Fixed offset;
  uint8_t active_edges;
  uint32_t index;
};

Triangle triangle_about(const TriangleMesh& mesh, uint32_t index, Vec3 centre) {
  const TriangleMesh::Triangle& t = mesh.triangles[index];
  Triangle out{{mesh.vertices[t.corners[0]] - centre, mesh.vertices[t.corners[1]] - centre,
                mesh.vertices[t.corners[2]] - centre},
               t.normal,
               {},
               t.active_edges,
               index};
  out.offset = dot(out.normal, out.corners[0]);
  return out;
}

bool edge_active(const Triangle& t, size_t k) { return ((t.active_edges >> k) & 1u) != 0; }

// The feature of a triangle's point: its index, then 12 bits of its own.
FeatureId mesh_feature(uint32_t triangle, uint32_t local) { return triangle << 12 | (local & 0xFFFu); }

// --- a box or hull against a triangle ---------------------------------------

// The triangle as a polyhedron of one face (its front), for the clipping.
struct TrianglePolyhedron {
  std::array<ConvexHull::Face, 1> face;
  std::array<ConvexHull::Edge, 3> edges{{{0, 1, 0, 0}, {1, 2, 0, 0}, {2, 0, 0, 0}}};
  std::array<Vec3, 3> directions;
  Polyhedron view(const Triangle& t) const {
    static constexpr std::array<uint16_t, 3> loop = {0, 1, 2};
    return {t.corners, face, loop, edges, directions, (t.corners[0] + t.corners[1] + t.corners[2]) / 3.0_fx};
  }
};

// The lowest of the points along n.
Fixed lowest_along(Vec3 n, const Vec3* points, size_t count) {
  Fixed lowest = Fixed::max();
  for (size_t i = 0; i < count; ++i) lowest = min(lowest, dot(n, points[i]));
  return lowest;
}
Fixed highest_along(Vec3 n, const Vec3* points, size_t count) {
  Fixed highest = Fixed::lowest();
  for (size_t i = 0; i < count; ++i) highest = max(highest, dot(n, points[i]));
  return highest;
}

enum class Axis { triangle, shape_face, edge };

struct Best {
  Axis axis = Axis::triangle;
  Fixed separation;
  size_t face = 0;  // the shape's face
  size_t triangle_edge = 0, shape_edge = 0;
  Vec3 normal;  // from the triangle toward the shape
};

// Whether the triangle's corners in contact with the shape's face g (within
// the speculative distance of its plane) touch an active edge: one corner
// through either edge at it, two through the edge between them.
bool touches_active_edge(const Triangle& t, const Framed& shape, size_t g, Fixed speculative_distance) {
  bool near[3];
  int count = 0;
  for (size_t i = 0; i < 3; ++i) {
    near[i] = dot(shape.normals[g], t.corners[i]) - shape.offsets[g] < speculative_distance;
    count += near[i] ? 1 : 0;
  }
  for (size_t k = 0; k < 3; ++k) {
    const size_t next = (k + 1) % 3;
    const bool involved = count == 1 ? (near[k] || near[next]) : (near[k] && near[next]);
    if (involved && edge_active(t, k)) return true;
  }
  return false;
}

void polyhedron_triangle(const Framed& shape, const Triangle& t, Fixed speculative_distance,
                         std::vector<MeshPoint>& points) {
  // One-sided: the shape's centre (the frame's origin) in front of the plane.
  if (t.offset > Fixed{}) return;
  const Vec3* sv = shape.vertices.data();
  Best best;
  best.separation = lowest_along(t.normal, sv, shape.vertex_count) - t.offset;
  best.normal = t.normal;
  if (best.separation > speculative_distance) return;
  // The shape's faces: how far the triangle lies beyond each.
  for (size_t g = 0; g < shape.face_count; ++g) {
    const Fixed separation = lowest_along(shape.normals[g], t.corners.data(), 3) - shape.offsets[g];
    if (separation > speculative_distance) return;
    if (best.axis == Axis::triangle ? separation > best.separation + margin(best.separation)
                                    : separation > best.separation) {
      best = {Axis::shape_face, separation, g, 0, 0, -shape.normals[g]};
    }
  }
  // Each triangle edge across each shape edge, turned to the front (or,
  // lying in the plane, toward the shape).
  const Fixed preferred = best.separation;
  for (size_t k = 0; k < 3; ++k) {
    const Vec3 along = normalize(t.corners[(k + 1) % 3] - t.corners[k]);
    for (size_t j = 0; j < shape.shape.edges.size(); ++j) {
      const Vec3 axis = cross(along, shape.directions[j]);
      if (length_sq(axis) < parallel_cross_sq_tolerance) continue;
      Vec3 n = normalize(axis);
      const Fixed facing = dot(n, t.normal);
      if (facing < Fixed{} || (facing == Fixed{} && dot(n, -t.corners[k]) < Fixed{})) n = -n;
      const Fixed separation = lowest_along(n, sv, shape.vertex_count) - highest_along(n, t.corners.data(), 3);
      if (separation > speculative_distance) return;
      if (separation > preferred + margin(preferred) && separation > best.separation) {
        best = {Axis::edge, separation, 0, k, j, n};
      }
    }
  }
  // At an inactive edge or corner the contact is the face's.
  const bool own_normal = dot(best.normal, t.normal) >= mesh_active_edge_cos;
  if (!own_normal) {
    const bool active = best.axis == Axis::edge ? edge_active(t, best.triangle_edge)
                                                : touches_active_edge(t, shape, best.face, speculative_distance);
    if (!active) best = {Axis::triangle, {}, 0, 0, 0, t.normal};
  }

  TrianglePolyhedron polygon;
  polygon.face[0] = {t.normal, t.offset, 0, 3};
  for (size_t k = 0; k < 3; ++k) polygon.directions[k] = normalize(t.corners[(k + 1) % 3] - t.corners[k]);
  Framed framed;
  place(polygon.view(t), Mat33::identity(), Vec3{}, framed);
  std::array<Candidate, clip_capacity> found;
  int count = 0;
  uint32_t kind = 1;
  switch (best.axis) {
    case Axis::triangle: count = face_contact(framed, 0, shape, 1, speculative_distance, found.data()); break;
    case Axis::shape_face:
      count = face_contact(shape, best.face, framed, 2, speculative_distance, found.data());
      kind = 2;
      break;
    case Axis::edge: {
      const ConvexHull::Edge& e = shape.shape.edges[best.shape_edge];
      const Vec3 start_t = t.corners[best.triangle_edge], along_t = t.corners[(best.triangle_edge + 1) % 3] - start_t;
      const Vec3 start_s = shape.vertices[e.tail], along_s = shape.vertices[e.head] - start_s;
      const SegmentParams p = closest_segment_params(start_t, along_t, start_s, along_s);
      const Vec3 on_t = mul_add(along_t, p.s, start_t), on_s = mul_add(along_s, p.t, start_s);
      found[0] = {(on_t + on_s) * half, -best.separation, 0};
      count = 1;
      kind = 3;
      break;
    }
  }
  for (int i = 0; i < count; ++i) {
    Candidate c = found[static_cast<size_t>(i)];
    // Kind, then the clipping edges (or the edge pair) of the point.
    const uint32_t local = kind == 3 ? 3u << 10 | static_cast<uint32_t>(best.triangle_edge) << 8 |
                                           static_cast<uint32_t>(best.shape_edge & 0xFF)
                                     : kind << 10 | (c.feature >> 6 & 0x1Fu) << 5 | (c.feature & 0x1Fu);
    c.feature = mesh_feature(t.index, local);
    points.push_back({c, best.normal});
  }
}

// --- a ball or capsule against a triangle ------------------------------------

struct CoreSegment {
  Vec3 from, to;  // about the shape's centre, mesh frame; equal for a ball
};

Vec3 segment_support(const void* object, Vec3 direction) {
  const CoreSegment& s = *static_cast<const CoreSegment*>(object);
  return dot(s.to - s.from, direction) > Fixed{} ? s.to : s.from;
}

// Whether the point on the triangle lies on an active edge (within 0.1 mm of it).
bool on_active_edge(const Triangle& t, Vec3 point) {
  const Fixed near_sq = 0.00000001_fx;
  for (size_t k = 0; k < 3; ++k) {
    const Vec3 a = t.corners[k], along = t.corners[(k + 1) % 3] - a;
    const Vec3 closest = mul_add(along, closest_param_to_point(a, along, point), a);
    if (edge_active(t, k) && length_sq(point - closest) <= near_sq) return true;
  }
  return false;
}

// The segment clipped to the triangle's three side planes, as parameters.
bool clip_to_triangle(const Triangle& t, Vec3 from, Vec3 to, Fixed& lo, Fixed& hi) {
  return polyhedra::clip_segment([&](size_t i) { return t.corners[i]; }, 3, t.normal, from, to, lo, hi);
}

// A ball of radius r at x against the face's plane: the point midway.
void face_point(const Triangle& t, Vec3 x, Fixed r, uint32_t local, Fixed speculative_distance,
                std::vector<MeshPoint>& points) {
  const Fixed height = dot(t.normal, x) - t.offset;
  const Fixed depth = r - height;
  if (depth <= -speculative_distance) return;
  points.push_back({{x - t.normal * ((height + r) * half), depth, mesh_feature(t.index, local)}, t.normal});
}

void rounded_triangle(const CoreSegment& core, Fixed r, const Triangle& t, Fixed speculative_distance,
                      std::vector<MeshPoint>& points) {
  if (t.offset > Fixed{}) return;  // the centre behind the plane
  const bool segment = core.from != core.to;
  const ConvexCore triangle = triangle_core(t.corners);
  const ConvexCore shape{&core, segment_support, (core.from + core.to) * half, r};
  const ConvexDistance d = convex_distance(triangle, shape);
  if (!d.overlap && d.distance > speculative_distance) return;
  const bool face_region =
      d.overlap || dot(d.normal, t.normal) >= mesh_active_edge_cos || !on_active_edge(t, d.point_a);
  if (!face_region) {  // an active edge or corner: along the closest points' line
    if (dot(d.normal, t.normal) <= Fixed{}) return;
    points.push_back({{(d.point_a + d.point_b) * half, -d.distance, mesh_feature(t.index, 0)}, d.normal});
    return;
  }
  // The face's contact: a capsule along it clipped to it, else its lowest point.
  Fixed lo, hi;
  if (segment) {
    const Fixed tilt = dot(normalize(core.to - core.from), t.normal);
    if (tilt * tilt <= capsule_parallel_sq_tolerance && clip_to_triangle(t, core.from, core.to, lo, hi) &&
        hi - lo > min_overlap_length) {
      face_point(t, mul_add(core.to - core.from, lo, core.from), r, 16, speculative_distance, points);
      face_point(t, mul_add(core.to - core.from, hi, core.from), r, 17, speculative_distance, points);
      return;
    }
  }
  face_point(t, segment_support(&core, -t.normal), r, 0, speculative_distance, points);
}

// --- the manifold -------------------------------------------------------------

// Points this close in depth to the deepest (m) are as deep as it.
constexpr Fixed same_depth = 0.001_fx;

// Four of the candidates by area (choose_four), starting from the point
// that is as deep as the deepest and farthest from their middle. A face
// lying on several triangles has, besides its corners, points where the
// triangles' edges clip it, all at one depth to within rounding; started
// from whichever of them rounded deepest (a point mid-way along the face's
// side), the four left out a corner, and the smaller face tipped the body
// as triangle edges passed under it (a box sliding down a slope of
// triangles went 2.6% too far). Started from a corner, the four are the
// face's corners, as on a plane.
int choose_four_spread(const std::vector<Candidate>& c, Vec3 normal, int* chosen) {
  const int count = static_cast<int>(c.size());
  Fixed deepest = c[0].depth;
  Vec3 middle;
  for (const Candidate& p : c) {
    deepest = max(deepest, p.depth);
    middle += p.p;
  }
  middle = middle / Fixed::from_int(count);
  // The rank choose_four takes its first point by: past the deepest for
  // the points as deep as it, by their distance from the middle (squared,
  // below the shape's extent squared).
  const auto rank = [&](int i) {
    const Candidate& p = c[static_cast<size_t>(i)];
    return p.depth >= deepest - same_depth ? deepest + length_sq(p.p - middle) : p.depth;
  };
  return choose_four(
      count, rank,
      [&](int from, int to) { return length_sq(c[static_cast<size_t>(to)].p - c[static_cast<size_t>(from)].p); },
      [&](int from, int to, int i) {
        const Vec3 base = c[static_cast<size_t>(from)].p;
        return dot(cross(c[static_cast<size_t>(to)].p - base, c[static_cast<size_t>(i)].p - base), normal);
      },
      chosen);
}

int assemble(std::vector<MeshPoint>& points, const WorldShape& mesh_shape, Vec3 centre, Manifold& out) {
  if (points.empty()) return 0;
  size_t deepest = 0;
  for (size_t i = 1; i < points.size(); ++i) {
    if (points[i].candidate.depth > points[deepest].candidate.depth) deepest = i;
  }
  const Vec3 normal = points[deepest].normal;
  std::vector<Candidate> kept;
  for (const MeshPoint& p : points) {
    if (dot(p.normal, normal) >= same_surface_cos && kept.size() < static_cast<size_t>(clip_capacity)) {
      kept.push_back(p.candidate);
    }
  }
  int chosen[max_manifold_points] = {0, 1, 2, 3};
  int count = static_cast<int>(kept.size());
  if (count > max_manifold_points) count = choose_four_spread(kept, normal, chosen);
  out.normal = normalize(rotate(mesh_shape.pose.orientation, normal));
  for (int k = 0; k < count; ++k) {
    const Candidate& c = kept[static_cast<size_t>(chosen[k])];
    add_point(out, mesh_shape.pose.apply(centre + c.p), c.depth, c.feature);
  }
  return count;
}

// The box in the mesh's frame around which the triangles are looked for.
Aabb search_box(const Relative& rel, Fixed reach) {
  const Vec3 r{reach, reach, reach};
  return {rel.centre - r, rel.centre + r};
}

int collide_mesh_polyhedron(const WorldShape& mesh_shape, const WorldShape& other, const Polyhedron& shape,
                            Fixed extent, Fixed speculative_distance, Manifold& out) {
  const TriangleMesh& mesh = *mesh_shape.shape->mesh;
  const Relative rel = relative_to(mesh_shape, other);
  Framed framed;
  place(shape, rel.rotation, Vec3{}, framed);
  std::vector<MeshPoint> points;
  for_each_triangle_near(mesh, search_box(rel, extent + speculative_distance), [&](uint32_t index) {
    polyhedron_triangle(framed, triangle_about(mesh, index, rel.centre), speculative_distance, points);
  });
  return assemble(points, mesh_shape, rel.centre, out);
}

int collide_mesh_rounded(const WorldShape& mesh_shape, const WorldShape& other, Vec3 half_segment, Fixed r,
                         Fixed speculative_distance, Manifold& out) {
  const TriangleMesh& mesh = *mesh_shape.shape->mesh;
  const Relative rel = relative_to(mesh_shape, other);
  const Vec3 axis = rel.rotation * half_segment;
  const CoreSegment core{-axis, axis};
  std::vector<MeshPoint> points;
  for_each_triangle_near(mesh, search_box(rel, length(half_segment) + r + speculative_distance), [&](uint32_t index) {
    rounded_triangle(core, r, triangle_about(mesh, index, rel.centre), speculative_distance, points);
  });
  return assemble(points, mesh_shape, rel.centre, out);
}

}  // namespace mesh_pairs

int collide_mesh_box(const WorldShape& mesh, const WorldShape& box, Fixed speculative_distance, Manifold& out) {
  const BoxPolyhedron shape(box.shape->half_extents);
  return mesh_pairs::collide_mesh_polyhedron(mesh, box, shape.view(), length(box.shape->half_extents),
                                             speculative_distance, out);
}

int collide_mesh_hull(const WorldShape& mesh, const WorldShape& hull, Fixed speculative_distance, Manifold& out) {
  return mesh_pairs::collide_mesh_polyhedron(mesh, hull, polyhedron_of(*hull.shape->hull), hull.shape->hull->extent,
                                             speculative_distance, out);
}

int collide_mesh_sphere(const WorldShape& mesh, const WorldShape& sphere, Fixed speculative_distance, Manifold& out) {
  return mesh_pairs::collide_mesh_rounded(mesh, sphere, Vec3{}, sphere.shape->radius, speculative_distance, out);
}

int collide_mesh_capsule(const WorldShape& mesh, const WorldShape& capsule, Fixed speculative_distance, Manifold& out) {
  const Vec3 half_segment{Fixed{}, capsule.shape->half_height, Fixed{}};
  return mesh_pairs::collide_mesh_rounded(mesh, capsule, half_segment, capsule.shape->radius, speculative_distance,
                                          out);
}

}  // namespace bitstep::collide_detail
