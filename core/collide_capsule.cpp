// Capsule-capsule, capsule-box, capsule-sphere, capsule-plane: the capsule's
// inner segment against the other shape, the capsule's radius added.
#include "core/collide_internal.h"

namespace bitstep::collide_detail {

namespace {

// The capsule's axis (local +y) in the world.
Vec3 capsule_axis(const WorldShape& capsule) { return rotate(capsule.pose.orientation, unit_axis(1)); }

// A unit vector perpendicular to the unit u: u x (the world axis least aligned with u).
Vec3 perpendicular(Vec3 u) {
  const Vec3 a = abs(u);
  const int k = a.x <= a.y && a.x <= a.z ? 0 : (a.y <= a.z ? 1 : 2);
  return normalize_or(cross(u, unit_axis(k)), unit_axis(1));
}

// Narrows [t0, t1] to the t with start + t dir <= limit; false if empty.
// Divides only when the bound falls inside the range (no overflow).
bool clip_param(Fixed start, Fixed dir, Fixed limit, Fixed& t0, Fixed& t1) {
  if (dir == Fixed{}) return start <= limit;
  if (dir > Fixed{}) {  // t <= (limit - start) / dir
    const Fixed numerator = limit - start;
    if (numerator < t0 * dir) return false;
    if (numerator < t1 * dir) t1 = numerator / dir;
  } else {  // t >= (start - limit) / -dir
    const Fixed numerator = start - limit, magnitude = -dir;
    if (numerator > t1 * magnitude) return false;
    if (numerator > t0 * magnitude) t0 = numerator / magnitude;
  }
  return t0 <= t1;
}

// The t in [0, 1] whose segment point start + t dir is closest to the box
// [-e, e], and that squared distance. The squared distance is convex and
// piecewise quadratic in t, with breaks where a coordinate crosses a face
// plane: on each piece the outside coordinates are fixed, so the minimum of
// A t^2 + 2 B t + C is -B / A clamped to the piece. Ties go to the lower t.
Fixed closest_param_to_box(Vec3 start, Vec3 dir, Vec3 e, Fixed& best_distance_sq) {
  Fixed breaks[8];
  int n = 0;
  breaks[n++] = Fixed{};
  breaks[n++] = Fixed::one();
  for (int k = 0; k < 3; ++k) {
    const Fixed dk = get(dir, k), sk = get(start, k);
    for (const Fixed bound : {-get(e, k), get(e, k)}) {
      const Fixed numerator = bound - sk;  // t = numerator / dk, kept when in (0, 1)
      if (dk != Fixed{} && (numerator > Fixed{}) == (dk > Fixed{}) && numerator != Fixed{} &&
          abs(numerator) < abs(dk)) {
        breaks[n++] = numerator / dk;
      }
    }
  }
  for (int i = 1; i < n; ++i) {
    for (int j = i; j > 0 && breaks[j - 1] > breaks[j]; --j) {
      const Fixed swap = breaks[j];
      breaks[j] = breaks[j - 1];
      breaks[j - 1] = swap;
    }
  }
  Fixed best_t{};
  best_distance_sq = Fixed::max();
  for (int i = 0; i + 1 < n; ++i) {
    const Fixed ta = breaks[i], tb = breaks[i + 1];
    if (tb <= ta) continue;
    const Vec3 middle = mul_add(dir, (ta + tb) * half, start);
    Fixed a{}, b{};
    for (int k = 0; k < 3; ++k) {
      const Fixed mk = get(middle, k), ek = get(e, k);
      if (mk <= ek && mk >= -ek) continue;
      const Fixed dk = get(dir, k);
      a = mul_add(dk, dk, a);
      b = mul_add(dk, get(start, k) - (mk > ek ? ek : -ek), b);
    }
    Fixed t = ta;
    if (a > Fixed{}) {
      if (-b >= a * tb)
        t = tb;
      else if (-b > a * ta)
        t = -b / a;
    }
    const Vec3 p = mul_add(dir, t, start);
    const Fixed d_sq = length_sq(p - max(-e, min(p, e)));
    if (d_sq < best_distance_sq) {
      best_distance_sq = d_sq;
      best_t = t;
    }
  }
  return best_t;
}

// A capsule against a box, in the box's frame.
struct CapsuleBox {
  const WorldShape& box;
  Mat33 rot;        // the box's rotation
  Vec3 e;           // the box's half extents
  Vec3 start, dir;  // the capsule's segment start + t dir, t in [0, 1], box frame
  Fixed radius, half_height;
  Fixed speculative_distance;
  Manifold& out;

  Vec3 world(Vec3 local) const { return box.pose.position + rot * local; }

  // One point: p on the segment, q on (or in) the box, n the unit direction
  // from the box to the capsule (box frame).
  int one_point(Vec3 p, Vec3 q, Vec3 n, FeatureId feature) const {
    const Fixed depth = radius - dot(n, p - q);
    if (depth <= -speculative_distance) return 0;
    out.normal = -normalize(rot * n);
    add_point(out, world((p + q - n * radius) * half), depth, feature);
    return 1;
  }

  // The segment clipped to face k's side planes: its two ends (one when the
  // segment is a point or crosses the face steeply and the far end is beyond
  // the speculative distance).
  int face_contact(int k, bool negative) const {
    Fixed t0{}, t1 = Fixed::one();
    for (const int j : {(k + 1) % 3, (k + 2) % 3}) {
      if (!clip_param(get(start, j), get(dir, j), get(e, j), t0, t1) ||
          !clip_param(-get(start, j), -get(dir, j), get(e, j), t0, t1)) {
        return 0;
      }
    }
    const Vec3 face_normal = negative ? -unit_axis(k) : unit_axis(k);
    const uint32_t face = static_cast<uint32_t>(2 * k) + (negative ? 1u : 0u);
    const bool two = (t1 - t0) * (half_height + half_height) > min_overlap_length;
    int count = 0;
    for (int end = 0; end < (two ? 2 : 1); ++end) {
      const Vec3 p = mul_add(dir, end == 0 ? t0 : t1, start);
      const Fixed height = (negative ? -get(p, k) : get(p, k)) - get(e, k);  // of the segment above the face
      const Fixed depth = radius - height;
      if (depth <= -speculative_distance) continue;
      // Midway between the face (height 0) and the capsule's surface (height - r).
      add_point(out, world(p - face_normal * ((height + radius) * half)), depth,
                16 + 2 * face + static_cast<uint32_t>(end));
      ++count;
    }
    if (count > 0) out.normal = -normalize(negative ? -rot.column(k) : rot.column(k));
    return count;
  }

  // After the one point near an edge or a vertex of the box, with n (from
  // the box to the capsule, unit) within ~1.15 degrees of face k's normal
  // (face_aligned_edge_sq_tolerance, as box-box): the segment's ends that
  // lie over face k within the speculative distance, their depths along n.
  // A capsule lying across a box's edge, tilted by a hair outward, touches
  // at the edge alone, and tilted by a hair inward the face clips it to its
  // inner end and the edge: one point, then two. A forearm resting across
  // a stair's edge (tilted by a hair either way) would lose its inner
  // point and the impulse it held every few steps, drop and swing, jolting
  // a resting ragdoll heap. So the inner end is a point either way, under
  // the same feature id; the edge point keeps its exact depth.
  int with_face_ends(int count, Vec3 n) const {
    if (count == 0) return 0;
    const Vec3 a = abs(n);
    const int k = a.x >= a.y && a.x >= a.z ? 0 : (a.y >= a.z ? 1 : 2);
    const Fixed off_axis = length_sq(n) - get(n, k) * get(n, k);  // sin^2 of the angle to e_k
    if (off_axis > face_aligned_edge_sq_tolerance) return count;
    const bool negative = get(n, k) < Fixed{};
    const uint32_t face = static_cast<uint32_t>(2 * k) + (negative ? 1u : 0u);
    const int j1 = (k + 1) % 3, j2 = (k + 2) % 3;
    for (int end = 0; end < (half_height > Fixed{} ? 2 : 1); ++end) {
      const Vec3 p = end == 0 ? start : start + dir;
      if (abs(get(p, j1)) > get(e, j1) || abs(get(p, j2)) > get(e, j2)) continue;  // not over the face
      Vec3 q = p;
      set(q, k, negative ? -get(e, k) : get(e, k));
      const Fixed depth = radius - dot(n, p - q);
      if (depth <= -speculative_distance || dot(n, p - q) < Fixed{}) continue;  // too far, or on the inner side
      add_point(out, world((p + q - n * radius) * half), depth, 16 + 2 * face + static_cast<uint32_t>(end));
      ++count;
    }
    return count;
  }

  int collide() const {
    Fixed distance_sq;
    const Fixed t = closest_param_to_box(start, dir, e, distance_sq);
    const Vec3 p = mul_add(dir, t, start);
    if (distance_sq > Fixed{}) {
      // The segment is outside the box: q is the closest box point.
      const Vec3 q = max(-e, min(p, e));
      const Vec3 n = normalize_or(p - q, unit_axis(1));
      if (radius - dot(n, p - q) <= -speculative_distance) return 0;
      // Over a face (only one coordinate clamped: the closest point is in the
      // face's region, n is its normal): clip the segment to that face, so a
      // capsule lying on it gets two points. Near an edge or a vertex: one,
      // and the ends over a face n is nearly normal to (with_face_ends).
      int clamped = 0, k = 0;
      for (int m = 0; m < 3; ++m) {
        if (get(p, m) != get(q, m)) {
          ++clamped;
          k = m;
        }
      }
      if (clamped == 1) {
        const int count = face_contact(k, get(p, k) < Fixed{});
        return count > 0 ? count : one_point(p, q, n, 0);
      }
      return with_face_ends(one_point(p, q, n, 0), n);
    }
    // The segment touches the box: separating axes of a segment and a box are
    // the box's face normals and segment x box edge (Minkowski sum faces).
    const Vec3 center = mul_add(dir, half, start), half_axis = dir * half;
    Axis face{Fixed::lowest()};
    for (int k = 0; k < 3; ++k) {
      const Fixed s = abs(get(center, k)) - get(e, k) - abs(get(half_axis, k));
      if (s > face.separation) face = {s, k};
    }
    Axis edge{face.separation + margin(face.separation)};
    for (int k = 0; k < 3; ++k) {
      const Vec3 l = cross(half_axis, unit_axis(k));
      if (length_sq(l) <= parallel_cross_sq_tolerance * length_sq(half_axis)) continue;  // also h = 0
      const Fixed scaled = abs(dot(center, l)) - dot(e, abs(l));
      const Fixed s = scaled / length(l);
      if (s > edge.separation) edge = {s, k};
    }
    if (edge.index < 0) {
      const int k = face.index;
      const bool negative = get(center, k) < Fixed{};
      const int count = face_contact(k, negative);
      if (count > 0) return count;
      Vec3 q = p;  // fallback: the closest segment point pushed out through face k
      set(q, k, negative ? -get(e, k) : get(e, k));
      return one_point(p, q, negative ? -unit_axis(k) : unit_axis(k), 0);
    }
    // Edge axis: the box edge along axis k nearest the capsule.
    const int k = edge.index;
    const Vec3 l = cross(half_axis, unit_axis(k));
    const Vec3 n = normalize(dot(center, l) < Fixed{} ? -l : l);
    Vec3 corner;
    for (int m = 0; m < 3; ++m) set(corner, m, get(n, m) < Fixed{} ? -get(e, m) : get(e, m));
    set(corner, k, -get(e, k));
    const Vec3 edge_dir = unit_axis(k) * (get(e, k) + get(e, k));
    const SegmentParams params = closest_segment_params(start, dir, corner, edge_dir);
    return one_point(mul_add(dir, params.s, start), mul_add(edge_dir, params.t, corner), n, 1);
  }
};

}  // namespace

int collide_capsule_plane(const WorldShape& capsule, const WorldShape& plane, Fixed speculative_distance,
                          Manifold& out) {
  const Vec3 n = plane_normal(plane);
  const Vec3 u = capsule_axis(capsule);
  const Fixed h = capsule.shape->half_height, r = capsule.shape->radius;
  const Fixed center_height = dot(n, capsule.pose.position - plane.pose.position);
  const Fixed reach = dot(n, u) * h;  // height of the +h end above the centre
  out.normal = -n;
  int count = 0;
  for (int end = 0; end < (h > Fixed{} ? 2 : 1); ++end) {  // a zero-length segment has one end
    const Fixed height = end == 0 ? center_height - reach : center_height + reach;
    const Fixed depth = r - height;
    if (depth <= -speculative_distance) continue;
    const Vec3 tip = capsule.pose.position + u * (end == 0 ? -h : h);
    add_point(out, tip - n * ((height + r) * half), depth, static_cast<FeatureId>(end));
    ++count;
  }
  return count;
}

int collide_capsule_sphere(const WorldShape& capsule, const WorldShape& sphere, Fixed speculative_distance,
                           Manifold& out) {
  const Fixed h = capsule.shape->half_height, ra = capsule.shape->radius, rb = sphere.shape->radius;
  const Vec3 d = sphere.pose.position - capsule.pose.position;
  const Fixed reach = h + ra + rb + speculative_distance;
  if (abs(d.x) >= reach || abs(d.y) >= reach || abs(d.z) >= reach) return 0;
  const Vec3 u = capsule_axis(capsule);
  const Vec3 closest = u * clamp(dot(d, u), -h, h);  // on the segment, relative to the capsule's centre
  // Sphere centre on the segment: push out perpendicular to the axis.
  return collide_points_with_radii(capsule.pose.position, closest, ra, d, rb, perpendicular(u), speculative_distance,
                                   out);
}

int collide_capsule_capsule(const WorldShape& a, const WorldShape& b, Fixed speculative_distance, Manifold& out) {
  const Fixed ha = a.shape->half_height, hb = b.shape->half_height;
  const Fixed ra = a.shape->radius, rb = b.shape->radius;
  const Vec3 d = b.pose.position - a.pose.position;
  const Fixed reach = ha + hb + ra + rb + speculative_distance;
  if (abs(d.x) >= reach || abs(d.y) >= reach || abs(d.z) >= reach) return 0;
  const Vec3 ua = capsule_axis(a), ub = capsule_axis(b);
  const Vec3 start_a = ua * -ha, dir_a = ua * (ha + ha);  // relative to A's centre
  const Vec3 start_b = d - ub * hb, dir_b = ub * (hb + hb);
  const Vec3 axes_cross = cross(ua, ub);

  if (ha > Fixed{} && hb > Fixed{} && length_sq(axes_cross) < capsule_parallel_sq_tolerance) {
    // Nearly parallel: the two ends of the overlap of B's projection on A's
    // axis, each paired with its closest point on B, with one normal: the
    // part of the centre offset perpendicular to A's axis.
    const Fixed b0 = dot(start_b, ua), b1 = dot(start_b + dir_b, ua);
    const Fixed lo = max(-ha, min(b0, b1)), hi = min(ha, max(b0, b1));
    if (hi - lo > min_overlap_length) {
      const Vec3 n = normalize_or(d - ua * dot(d, ua), perpendicular(ua));
      out.normal = n;
      int count = 0;
      for (int end = 0; end < 2; ++end) {
        const Vec3 pa = ua * (end == 0 ? lo : hi);
        const Vec3 pb = mul_add(dir_b, closest_param_to_point(start_b, dir_b, pa), start_b);
        const Fixed depth = ra + rb - dot(pb - pa, n);
        if (depth <= -speculative_distance) continue;
        add_point(out, a.pose.position + (pa + pb + n * (ra - rb)) * half, depth, static_cast<FeatureId>(1 + end));
        ++count;
      }
      return count;
    }
  }
  const SegmentParams params = closest_segment_params(start_a, dir_a, start_b, dir_b);
  const Vec3 pa = mul_add(dir_a, params.s, start_a), pb = mul_add(dir_b, params.t, start_b);
  // Crossing axes: push apart along their common normal, towards B.
  const Vec3 common = normalize_or(axes_cross, perpendicular(ua));
  const Vec3 fallback = dot(common, d) < Fixed{} ? -common : common;
  return collide_points_with_radii(a.pose.position, pa, ra, pb, rb, fallback, speculative_distance, out);
}

int collide_capsule_box(const WorldShape& capsule, const WorldShape& box, Fixed speculative_distance, Manifold& out) {
  const Fixed h = capsule.shape->half_height, r = capsule.shape->radius;
  const Vec3 e = box.shape->half_extents;
  const Mat33 rot = axes_of(box);
  const Vec3 center = transpose(rot) * (capsule.pose.position - box.pose.position);
  for (int k = 0; k < 3; ++k) {
    if (abs(get(center, k)) >= get(e, k) + h + r + speculative_distance) return 0;
  }
  const Vec3 axis = transpose(rot) * capsule_axis(capsule);
  const CapsuleBox pair{box, rot, e, center - axis * h, axis * (h + h), r, h, speculative_distance, out};
  return pair.collide();
}

}  // namespace bitstep::collide_detail
