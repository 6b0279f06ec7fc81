// A convex hull: its points, faces and mass come built (core/convex_hull.h);
// its facts here (shape_types.h).
#include "core/collide_internal.h"
#include "core/convex_hull.h"
#include "core/ray_primitives.h"
#include "core/shape_types.h"

namespace bitstep {

namespace {

const ConvexHull& hull_of(const Shape& shape) { return *shape.hull; }

// A ray in the hull's own frame.
struct LocalRay {
  Vec3 origin, direction;
};

LocalRay to_local(const WorldShape& placed, const Ray& ray) {
  const Mat33 to_hull = transpose(rotation(placed.pose.orientation));
  return {to_hull * (ray.origin - placed.pose.position), to_hull * ray.direction};
}

// Whether x (hull frame) lies on the inner side of each edge of the face's
// loop: (b - a) x (x - a) along the outward normal, for the loop runs
// counter-clockwise seen from outside.
bool within_face(const ConvexHull& hull, const ConvexHull::Face& face, Vec3 x) {
  for (uint16_t i = 0; i < face.count; ++i) {
    const Vec3 a = hull.vertices[hull.face_vertices[face.first + i]];
    const Vec3 b = hull.vertices[hull.face_vertices[face.first + (i + 1u) % face.count]];
    if (dot(cross(b - a, x - a), face.normal) < Fixed{}) return false;
  }
  return true;
}

// The ray against the solid hull: the part of it below every face's plane
// (n . x <= offset), entered through the last plane it crossed inward.
bool cast_solid(const WorldShape& placed, const Ray& ray, RayEntry& entry) {
  const ConvexHull& hull = hull_of(*placed.shape);
  const LocalRay local = to_local(placed, ray);
  Fixed near = Fixed::lowest(), far = ray.length;
  Vec3 near_normal;
  for (const ConvexHull::Face& face : hull.faces) {
    const Fixed inside = face.offset - dot(face.normal, local.origin);  // > 0 below the plane
    const Fixed rate = dot(face.normal, local.direction);               // > 0 toward the outside
    if (rate == Fixed{}) {
      if (inside < Fixed{}) return false;  // parallel, above it
      continue;
    }
    const Fixed t = collide_detail::path_ratio(inside, rate);
    if (rate < Fixed{}) {
      if (t > near) {
        near = t;
        near_normal = face.normal;
      }
    } else if (t < far) {
      far = t;
    }
    if (near > far) return false;
  }
  if (far < Fixed{}) return false;  // behind the ray
  if (near <= Fixed{}) {
    entry = {Fixed{}, -ray.direction};
    return true;
  }
  entry = {near, rotate(placed.pose.orientation, near_normal)};
  return true;
}

// The ray against each face's plane pushed out by r, where it meets the
// face's polygon: the slab of the grown hull above that face.
void cast_face_slabs(const WorldShape& placed, const Ray& ray, Fixed r, ray_primitives::Nearest& nearest) {
  const ConvexHull& hull = hull_of(*placed.shape);
  const LocalRay local = to_local(placed, ray);
  for (const ConvexHull::Face& face : hull.faces) {
    const Fixed height = dot(face.normal, local.origin) - face.offset - r;  // above the grown plane
    if (height <= Fixed{}) {
      if (height >= -r && within_face(hull, face, local.origin)) nearest.offer(true, {Fixed{}, -ray.direction});
      continue;
    }
    const Fixed closing = -dot(face.normal, local.direction);
    if (closing <= Fixed{}) continue;
    const Fixed t = collide_detail::path_ratio(height, closing);
    if (t > ray.length) continue;
    if (within_face(hull, face, mul_add(local.direction, t, local.origin))) {
      nearest.offer(true, {t, rotate(placed.pose.orientation, face.normal)});
    }
  }
}

}  // namespace

Fixed HullShape::volume(const Shape& shape) { return hull_of(shape).volume; }

ShapeMass HullShape::mass(const Shape& shape, Fixed density) {
  const ConvexHull& hull = hull_of(shape);
  const Fixed mass = density * hull.volume;
  return {mass, hull.unit_inertia * mass, hull.centroid};
}

// The builder checked its points, size and thickness.
Result<void> HullShape::check(const Shape& shape) {
  if (!shape.hull) return Error{"points", "a hull needs its points"};
  return {};
}

Fixed HullShape::extent(const Shape& shape) { return hull_of(shape).extent; }

// Along each world axis k, the vertices' extremes of row_k(R) . v.
Aabb HullShape::bounds(const WorldShape& placed) {
  const Mat33 r = rotation(placed.pose.orientation);
  Vec3 low = Vec3{Fixed::max(), Fixed::max(), Fixed::max()}, high = -low;
  for (const Vec3& v : hull_of(*placed.shape).vertices) {
    const Vec3 w = r * v;
    low = min(low, w);
    high = max(high, w);
  }
  return {placed.pose.position + low, placed.pose.position + high};
}

// A ray: the faces' half-spaces. A sphere cast: the hull grown by its
// radius is the union of the hull, a slab over each face and a capsule
// about each edge (the corners' balls lie in the capsules).
bool HullShape::ray(const WorldShape& placed, const Ray& ray, Fixed radius, RayEntry& entry) {
  if (radius == Fixed{}) return cast_solid(placed, ray, entry);
  ray_primitives::Nearest nearest;
  RayEntry solid;
  nearest.offer(cast_solid(placed, ray, solid), solid);
  cast_face_slabs(placed, ray, radius, nearest);
  const ConvexHull& hull = hull_of(*placed.shape);
  const Mat33 r = rotation(placed.pose.orientation);
  for (const ConvexHull::Edge& edge : hull.edges) {
    const Vec3 a = hull.vertices[edge.tail], b = hull.vertices[edge.head];
    const Vec3 centre = placed.pose.position + r * ((a + b) / 2.0_fx);
    const Fixed half_length = length(b - a) / 2.0_fx;
    ray_primitives::cast_capsule(centre, r * normalize(b - a), half_length, radius, ray, nearest);
  }
  if (nearest.found) entry = nearest.entry;
  return nearest.found;
}

Fixed HullShape::core_radius(const Shape&) { return Fixed{}; }

// The vertex farthest along d (in the hull's frame: R^T d); the first of equals.
Vec3 HullShape::core_support(const WorldShape& placed, Vec3 direction) {
  const ConvexHull& hull = hull_of(*placed.shape);
  const Mat33 r = rotation(placed.pose.orientation);
  const Vec3 local = transpose(r) * direction;
  size_t best = 0;
  Fixed best_reach = dot(hull.vertices[0], local);
  for (size_t i = 1; i < hull.vertices.size(); ++i) {
    const Fixed reach = dot(hull.vertices[i], local);
    if (reach > best_reach) {
      best = i;
      best_reach = reach;
    }
  }
  return placed.pose.position + r * hull.vertices[best];
}

}  // namespace bitstep
