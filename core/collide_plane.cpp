// Box-plane: the box's vertices below the plane (plus the speculative
// distance), the deepest four.
#include "core/collide_internal.h"

namespace bitstep::collide_detail {

int collide_box_plane(const WorldShape& box, const WorldShape& plane, Fixed speculative_distance, Manifold& out) {
  const Vec3 n = plane_normal(plane);
  const Mat33 rot = axes_of(box);
  const Vec3 e = box.shape->half_extents;
  // Height of vertex v above the plane: centre height + sum_k +-(n.b_k) e_k.
  const Fixed center_height = dot(n, box.pose.position - plane.pose.position);
  const Vec3 n_box = transpose(rot) * n;
  const Vec3 reach{n_box.x * e.x, n_box.y * e.y, n_box.z * e.z};
  if (center_height - dot(abs(n_box), e) >= speculative_distance) return 0;

  // Vertex index bits: bit k set = + half extent along axis k.
  Fixed depth[8];
  for (int v = 0; v < 8; ++v) {
    Fixed height = center_height;
    for (int k = 0; k < 3; ++k) height += ((v >> k) & 1) != 0 ? get(reach, k) : -get(reach, k);
    depth[v] = -height;
  }
  // The deepest four with depth > -speculative_distance, ties to the lower
  // index; reported deepest first.
  bool taken[8] = {};
  out.normal = -n;  // from the box into the plane
  int count = 0;
  while (count < max_manifold_points) {
    int best = -1;
    for (int v = 0; v < 8; ++v) {
      if (!taken[v] && depth[v] > -speculative_distance && (best < 0 || depth[v] > depth[best])) best = v;
    }
    if (best < 0) break;
    taken[best] = true;
    Vec3 corner;
    for (int k = 0; k < 3; ++k) set(corner, k, ((best >> k) & 1) != 0 ? get(e, k) : -get(e, k));
    // Midway: up from the vertex by half the depth.
    const Vec3 position = box.pose.position + rot * corner + n * (depth[best] * half);
    add_point(out, position, depth[best], static_cast<FeatureId>(best));
    ++count;
  }
  return count;
}

}  // namespace bitstep::collide_detail
