// Sphere-sphere, sphere-box, sphere-plane: one point each.
#include "core/collide_internal.h"

namespace bitstep::collide_detail {

int collide_points_with_radii(Vec3 origin, Vec3 point_a, Fixed radius_a, Vec3 point_b, Fixed radius_b, Vec3 fallback,
                              Fixed speculative_distance, Manifold& out) {
  const Vec3 d = point_b - point_a;
  const Vec3 n = normalize_or(d, fallback);
  const Fixed distance = dot(n, d);
  const Fixed depth = radius_a + radius_b - distance;
  if (depth <= -speculative_distance) return 0;
  out.normal = n;
  // Midway between A's surface point a + n ra and B's b - n rb.
  add_point(out, origin + (point_a + point_b + n * (radius_a - radius_b)) * half, depth, 0);
  return 1;
}

int collide_sphere_sphere(const WorldShape& a, const WorldShape& b, Fixed speculative_distance, Manifold& out) {
  const Fixed ra = a.shape->radius, rb = b.shape->radius;
  const Vec3 d = b.pose.position - a.pose.position;
  const Fixed reach = ra + rb + speculative_distance;
  if (abs(d.x) >= reach || abs(d.y) >= reach || abs(d.z) >= reach) return 0;  // also keeps |d|^2 in range
  // Concentric spheres: any direction will do, +y is a fixed one.
  return collide_points_with_radii(a.pose.position, Vec3::zero(), ra, d, rb, unit_axis(1), speculative_distance, out);
}

int collide_sphere_box(const WorldShape& sphere, const WorldShape& box, Fixed speculative_distance, Manifold& out) {
  const Fixed r = sphere.shape->radius;
  const Vec3 e = box.shape->half_extents;
  const Mat33 rot = axes_of(box);
  const Vec3 center = sphere.pose.position - box.pose.position;  // relative to the box centre, world axes
  const Vec3 p = transpose(rot) * center;                        // in the box frame
  for (int k = 0; k < 3; ++k) {
    if (abs(get(p, k)) >= get(e, k) + r + speculative_distance) return 0;
  }
  const Vec3 q = max(-e, min(p, e));  // the box point closest to the centre
  if (q == p) {
    // The centre is inside: push out through the nearest face (ties to the
    // lower axis, then to the + side).
    int k = 0;
    for (int m = 1; m < 3; ++m) {
      if (get(e, m) - abs(get(p, m)) < get(e, k) - abs(get(p, k))) k = m;
    }
    const bool negative = get(p, k) < Fixed{};
    const Vec3 face_normal = normalize(negative ? -rot.column(k) : rot.column(k));  // box to sphere
    Vec3 surface = p;
    set(surface, k, negative ? -get(e, k) : get(e, k));
    const Fixed depth = r + get(e, k) - abs(get(p, k));
    out.normal = -face_normal;
    // Midway between the face point and the sphere's surface point centre - n r.
    add_point(out, box.pose.position + (rot * surface + center - face_normal * r) * half, depth, 0);
    return 1;
  }
  const Vec3 surface = rot * q;
  const Vec3 d = center - surface;  // box surface to sphere centre
  const Vec3 n = normalize_or(d, normalize_or(rot * (p - q), unit_axis(1)));
  const Fixed depth = r - dot(n, d);
  if (depth <= -speculative_distance) return 0;
  out.normal = -n;
  add_point(out, box.pose.position + (surface + center - n * r) * half, depth, 0);
  return 1;
}

int collide_sphere_plane(const WorldShape& sphere, const WorldShape& plane, Fixed speculative_distance, Manifold& out) {
  const Vec3 n = plane_normal(plane);
  const Fixed r = sphere.shape->radius;
  const Fixed height = dot(n, sphere.pose.position - plane.pose.position);  // of the centre
  const Fixed depth = r - height;
  if (depth <= -speculative_distance) return 0;
  out.normal = -n;
  // Midway between the sphere's lowest point (height - r) and the plane (0).
  add_point(out, sphere.pose.position - n * ((height + r) * half), depth, 0);
  return 1;
}

}  // namespace bitstep::collide_detail
