#include "core/ray_cast.h"

#include "core/collide_internal.h"
#include "core/ray_primitives.h"
#include "core/shape_types.h"
#include "fixed/mat33.h"

namespace bitstep {

namespace collide_detail {

Fixed path_ratio(Fixed gap, Fixed rate) {
  if (abs(gap) >= abs(rate) * far_distance) return (gap < Fixed{}) != (rate < Fixed{}) ? -far_distance : far_distance;
  return gap / rate;
}

}  // namespace collide_detail

namespace ray_primitives {

using collide_detail::get;
using collide_detail::path_ratio;
using collide_detail::set;

namespace {

bool inside_ball(Vec3 offset, Fixed r) { return within_axes(offset, r) && length_sq(offset) <= r * r; }

// The part of the ray between `near` and `far` that lies within slabs
// lo <= x . axis <= hi, and the slab it entered through last.
struct SlabClip {
  Fixed near = Fixed::lowest();
  Fixed far;
  int axis = -1;
  bool through_low = false;  // entered through the low plane: outward normal -axis
};

// Clips to one slab, where the ray's coordinate is o + t u; false when
// nothing is left.
bool clip(SlabClip& c, int axis, Fixed o, Fixed u, Fixed lo, Fixed hi) {
  if (u == Fixed{}) return lo <= o && o <= hi;
  const bool low_first = u > Fixed{};
  const Fixed t_lo = path_ratio(lo - o, u), t_hi = path_ratio(hi - o, u);
  const Fixed t_in = low_first ? t_lo : t_hi, t_out = low_first ? t_hi : t_lo;
  if (t_in > c.near) c = {t_in, c.far, axis, low_first};
  if (t_out < c.far) c.far = t_out;
  return c.near <= c.far;
}

// A ray starting inside a solid shape.
RayEntry entry_at_start(const Ray& ray) { return {Fixed{}, -ray.direction}; }

}  // namespace

// A box centred at `centre` with `rotation`, half extents `h`.
bool cast_box(Vec3 centre, const Mat33& rotation, Vec3 h, const Ray& ray, RayEntry& entry) {
  const Mat33 to_local = transpose(rotation);
  const Vec3 o = to_local * (ray.origin - centre), u = to_local * ray.direction;
  SlabClip c;
  c.far = ray.length;
  for (int i = 0; i < 3; ++i) {
    if (!clip(c, i, get(o, i), get(u, i), -get(h, i), get(h, i))) return false;
  }
  if (c.far < Fixed{}) return false;  // behind the ray
  if (c.near <= Fixed{}) {
    entry = entry_at_start(ray);
    return true;
  }
  Vec3 normal;
  set(normal, c.axis, c.through_low ? -Fixed::one() : Fixed::one());
  entry = {c.near, rotation * normal};
  return true;
}

// A ball of radius r about `centre`. Measured from the closest approach
// (t0 along the ray, at q from the centre), the entry is t0 - sqrt(r^2 -
// |q|^2): no square of the distance to a far origin is formed.
bool cast_ball(Vec3 centre, Fixed r, const Ray& ray, RayEntry& entry) {
  const Vec3 p = ray.origin - centre;
  if (inside_ball(p, r)) {
    entry = entry_at_start(ray);
    return true;
  }
  const Fixed t0 = -dot(p, ray.direction);
  if (t0 < Fixed{}) return false;  // outside and moving away
  const Vec3 q = p + ray.direction * t0;
  if (!inside_ball(q, r)) return false;
  const Fixed t = max(t0 - sqrt(r * r - length_sq(q)), Fixed{});
  if (t > ray.length) return false;
  entry = {t, normalize_or(p + ray.direction * t, -ray.direction)};
  return true;
}

namespace {

// The side of a cylinder of radius r about the segment centre +- h axis
// (unit axis): the same closest-approach form in the plane across the axis,
// where the ray moves at |u_perp| per metre along it.
bool cast_cylinder_side(Vec3 centre, Vec3 axis, Fixed h, Fixed r, const Ray& ray, RayEntry& entry) {
  const Vec3 w = ray.origin - centre;
  const Fixed along = dot(w, axis), rate_along = dot(ray.direction, axis);
  const Vec3 w_perp = w - axis * along, u_perp = ray.direction - axis * rate_along;
  if (inside_ball(w_perp, r)) {
    if (abs(along) > h) return false;  // beyond an end: the side is never entered
    entry = entry_at_start(ray);
    return true;
  }
  const Fixed rate_sq = length_sq(u_perp);
  if (rate_sq < Fixed::from_raw(16)) return false;  // along the axis: only the ends are met
  const Fixed t0 = path_ratio(-dot(w_perp, u_perp), rate_sq);
  if (t0 < Fixed{}) return false;  // outside and moving away from the axis
  const Vec3 q = w_perp + u_perp * t0;
  if (!inside_ball(q, r)) return false;
  const Fixed t = max(t0 - sqrt(path_ratio(r * r - length_sq(q), rate_sq)), Fixed{});
  if (t > ray.length) return false;
  if (abs(along + rate_along * t) > h) return false;  // enters the infinite cylinder beyond the ends
  entry = {t, normalize_or(w_perp + u_perp * t, -ray.direction)};
  return true;
}

}  // namespace

// A capsule (a segment swept by r) is the union of its side and two balls:
// the ray enters it where it enters the first of them.
void cast_capsule(Vec3 centre, Vec3 axis, Fixed h, Fixed r, const Ray& ray, Nearest& nearest) {
  RayEntry e;
  nearest.offer(cast_cylinder_side(centre, axis, h, r, ray, e), e);
  nearest.offer(cast_ball(centre + axis * h, r, ray, e), e);
  nearest.offer(cast_ball(centre - axis * h, r, ray, e), e);
}

// A box grown by r (a sphere cast against it): the union of the box grown
// along each axis alone and the twelve edges swept by r (their ends are the
// rounded corners).
void cast_rounded_box(Vec3 centre, const Mat33& rotation, Vec3 h, Fixed r, const Ray& ray, Nearest& nearest) {
  RayEntry e;
  for (int i = 0; i < 3; ++i) {
    Vec3 grown = h;
    set(grown, i, get(h, i) + r);
    nearest.offer(cast_box(centre, rotation, grown, ray, e), e);
  }
  for (int i = 0; i < 3; ++i) {
    const int j = (i + 1) % 3, k = (i + 2) % 3;
    for (int corner = 0; corner < 4; ++corner) {
      Vec3 offset;
      set(offset, j, (corner & 1) != 0 ? get(h, j) : -get(h, j));
      set(offset, k, (corner & 2) != 0 ? get(h, k) : -get(h, k));
      cast_capsule(centre + rotation * offset, rotation.column(i), get(h, i), r, ray, nearest);
    }
  }
}

// The half-space below a plane through `point` with unit `normal`, grown by r.
bool cast_half_space(Vec3 point, Vec3 normal, Fixed r, const Ray& ray, RayEntry& entry) {
  const Fixed height = dot(ray.origin - point, normal) - r;
  if (height <= Fixed{}) {
    entry = entry_at_start(ray);
    return true;
  }
  const Fixed closing = -dot(ray.direction, normal);
  if (closing <= Fixed{}) return false;  // parallel or moving away
  const Fixed t = path_ratio(height, closing);
  if (t > ray.length) return false;
  entry = {t, normal};
  return true;
}

}  // namespace ray_primitives

namespace {

using collide_detail::get;
using collide_detail::path_ratio;
using ray_primitives::clip;
using ray_primitives::SlabClip;

bool acceptable(const Ray& ray) {
  return within_axes(ray.origin, max_ray_coordinate) && ray.length >= Fixed{} && ray.length <= max_ray_length;
}

}  // namespace

// Each shape's own cast (shape_types.h).
bool ray_enters(const WorldShape& placed, const Ray& ray, Fixed radius, RayEntry& entry) {
  if (!acceptable(ray) || radius < Fixed{}) return false;
  return with_shape_type(placed.shape->type,
                         [&](auto type) { return decltype(type)::ray(placed, ray, radius, entry); });
}

bool ray_enters(const Aabb& box, const Ray& ray, Fixed& distance) {
  if (!acceptable(ray)) return false;
  SlabClip c;
  c.far = ray.length;
  for (int i = 0; i < 3; ++i) {
    if (!clip(c, i, get(ray.origin, i), get(ray.direction, i), get(box.min, i), get(box.max, i))) return false;
  }
  if (c.far < Fixed{}) return false;
  distance = max(c.near, Fixed{});
  return true;
}

}  // namespace bitstep
