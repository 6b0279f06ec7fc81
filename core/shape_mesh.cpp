// A static triangle mesh: its triangles and tree come built
// (core/triangle_mesh.h); its facts here (shape_types.h). A mesh is a
// surface of one-sided triangles: rays and sphere casts enter it through
// the triangles' fronts only.
#include "core/collide_internal.h"
#include "core/ray_primitives.h"
#include "core/shape_types.h"
#include "core/triangle_mesh.h"

namespace bitstep {

namespace {

const TriangleMesh& mesh_of(const Shape& shape) { return *shape.mesh; }

// Whether x (on or near triangle t's plane) lies within its three edges.
bool within_triangle(const TriangleMesh& mesh, const TriangleMesh::Triangle& t, Vec3 x) {
  for (size_t k = 0; k < 3; ++k) {
    const Vec3 a = mesh.vertices[t.corners[k]], b = mesh.vertices[t.corners[(k + 1) % 3]];
    if (dot(cross(b - a, x - a), t.normal) < Fixed{}) return false;
  }
  return true;
}

// A ray (in the mesh's frame) against triangle t grown by r: the slab over
// its front (its plane pushed out by r, within its edges) and, for r > 0,
// a capsule about each edge; only a ray heading toward its front meets it.
void cast_triangle(const TriangleMesh& mesh, uint32_t index, const Ray& local, Fixed r, const Quat& to_world,
                   ray_primitives::Nearest& nearest) {
  const TriangleMesh::Triangle& t = mesh.triangles[index];
  const Fixed height = dot(t.normal, local.origin) - t.offset - r;  // above the grown front
  const Fixed closing = -dot(t.normal, local.direction);
  if (closing <= Fixed{}) return;  // one-sided: only toward its front
  if (height <= Fixed{}) {
    if (r > Fixed{} && height >= -r && within_triangle(mesh, t, local.origin)) {
      nearest.offer(true, {Fixed{}, -local.direction});  // starts within the slab
    }
  } else {
    const Fixed distance = collide_detail::path_ratio(height, closing);
    if (distance <= local.length && within_triangle(mesh, t, mul_add(local.direction, distance, local.origin))) {
      nearest.offer(true, {distance, rotate(to_world, t.normal)});
    }
  }
  if (r == Fixed{}) return;
  for (size_t k = 0; k < 3; ++k) {
    const Vec3 a = mesh.vertices[t.corners[k]], b = mesh.vertices[t.corners[(k + 1) % 3]];
    ray_primitives::Nearest edge;
    ray_primitives::cast_capsule((a + b) / 2.0_fx, normalize(b - a), length(b - a) / 2.0_fx, r, local, edge);
    if (edge.found) nearest.offer(true, {edge.entry.distance, rotate(to_world, edge.entry.normal)});
  }
}

}  // namespace

// A surface: no volume and no mass (a mesh belongs to a static body).
Fixed MeshShape::volume(const Shape&) { return Fixed{}; }

ShapeMass MeshShape::mass(const Shape&, Fixed) { return {}; }

Result<void> MeshShape::check(const Shape& shape) {
  if (!shape.mesh) return Error{"triangles", "a mesh needs its triangles"};
  return {};
}

Fixed MeshShape::extent(const Shape& shape) { return mesh_of(shape).extent; }

// The mesh's own box turned into the world: |R| half widths about its turned centre.
Aabb MeshShape::bounds(const WorldShape& placed) {
  const Aabb& local = mesh_of(*placed.shape).bounds;
  const Mat33 r = rotation(placed.pose.orientation);
  const Vec3 centre = (local.min + local.max) / 2.0_fx, half = (local.max - local.min) / 2.0_fx;
  const Vec3 extent{dot(abs(r.rows[0]), half), dot(abs(r.rows[1]), half), dot(abs(r.rows[2]), half)};
  const Vec3 world_centre = placed.pose.position + r * centre;
  return {world_centre - extent, world_centre + extent};
}

// The ray in the mesh's frame down its tree: the nodes whose boxes, grown
// by the radius, the ray enters, then their triangles; the nearest entry.
bool MeshShape::ray(const WorldShape& placed, const Ray& ray, Fixed radius, RayEntry& entry) {
  const TriangleMesh& mesh = mesh_of(*placed.shape);
  const Ray local{placed.pose.apply_inverse(ray.origin), rotate_inverse(placed.pose.orientation, ray.direction),
                  ray.length};
  ray_primitives::Nearest nearest;
  uint32_t stack[64];
  int depth = 0;
  stack[depth++] = 0;
  while (depth > 0) {
    const TriangleMesh::Node& node = mesh.nodes[stack[--depth]];
    Fixed distance;
    if (!ray_enters(node.bounds.expanded(radius), local, distance)) continue;
    if (nearest.found && distance > nearest.entry.distance) continue;
    if (node.count == 0) {
      stack[depth++] = node.first + 1;
      stack[depth++] = node.first;
      continue;
    }
    for (uint32_t k = node.first; k < node.first + node.count; ++k) {
      cast_triangle(mesh, mesh.order[k], local, radius, placed.pose.orientation, nearest);
    }
  }
  if (nearest.found) entry = nearest.entry;
  return nearest.found;
}

Fixed MeshShape::core_radius(const Shape&) { return Fixed{}; }

// Not convex: no support point (its origin); the generic path takes a
// mesh's triangles one at a time (collide_mesh.cpp), never the mesh.
Vec3 MeshShape::core_support(const WorldShape& placed, Vec3) { return placed.pose.position; }

}  // namespace bitstep
