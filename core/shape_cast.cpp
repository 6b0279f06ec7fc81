#include "core/shape_cast.h"

#include <array>
#include <utility>

#include "core/collide.h"
#include "core/collide_internal.h"
#include "core/gjk.h"
#include "core/shape_types.h"
#include "core/triangle_mesh.h"
#include "fixed/mat33.h"

namespace bitstep {

namespace {

using collide_detail::clamped_ratio;
using collide_detail::closest_segment_params;
using collide_detail::get;
using collide_detail::parallel_cross_sq_tolerance;
using collide_detail::path_ratio;
using collide_detail::plane_normal;
using collide_detail::unit_axis;

// Conservative advancement stops this close (m): Newton's steps converge
// quadratically, so a hit usually ends nanometres short of touching.
constexpr Fixed advance_tolerance = 0.000001_fx;
// A path that only grazes a shape converges linearly (the gap falls by 4x
// per step): 64 steps are below any tolerance.
constexpr int max_advance_steps = 64;
// Half the width of the narrowphase's window when it finds the touching
// point of two boxes that meet.
constexpr Fixed touch_window = 0.0001_fx;

ShapeEntry entry_at_start(const WorldShape& moving, const Ray& path) {
  return {Fixed{}, moving.pose.position, -path.direction};
}

// A shape's inner core, relative to an origin near the pair: a segment
// (capsule), a point (sphere) or a box, and the radius that rounds it.
struct Core {
  ShapeType type;
  Vec3 centre;
  Mat33 axes;  // box: the local axes as columns
  Vec3 half;   // box: half extents
  Vec3 start;  // capsule: the segment start + ...
  Vec3 along;  // ... along (start to end)
  Fixed radius;
};

Core core_of(const WorldShape& s, Vec3 origin) {
  const Shape& shape = *s.shape;
  Core c{shape.type, s.pose.position - origin, rotation(s.pose.orientation), shape.half_extents, {}, {}, Fixed{}};
  if (shape.type == ShapeType::capsule) {
    const Vec3 axis = c.axes.column(1) * shape.half_height;
    c.start = c.centre - axis;
    c.along = axis + axis;
    c.radius = shape.radius;
  } else if (shape.type == ShapeType::sphere) {
    c.radius = shape.radius;
  }
  return c;
}

// The point of the box (centre, axes, half) closest to p.
Vec3 closest_in_box(const Core& box, Vec3 p) {
  const Vec3 local = transpose(box.axes) * (p - box.centre);
  const Vec3 clamped{clamp(local.x, -box.half.x, box.half.x), clamp(local.y, -box.half.y, box.half.y),
                     clamp(local.z, -box.half.z, box.half.z)};
  return box.centre + box.axes * clamped;
}

// The parameter s in [0, 1] of the point of segment o + s d (box local)
// closest to a box of half extents h. The squared distance
//   f(s) = sum_i out_i(o_i + s d_i)^2,   out(x) = x - h (x > h), x + h (x < -h), else 0,
// is convex and a quadratic between the (at most six) parameters where
// the segment crosses a face's plane: on each piece its minimum is at
//   s* = -sum(e_i d_i) / sum(d_i^2)   (e_i = o_i -+ h_i over the axes outside),
// clamped to the piece. The least of the pieces' minima is exact.
Fixed closest_segment_param_to_box(Vec3 o, Vec3 d, Vec3 h) {
  std::array<Fixed, 8> cuts{};
  int count = 0;
  cuts[static_cast<size_t>(count++)] = Fixed{};
  for (int i = 0; i < 3; ++i) {
    const Fixed oi = get(o, i), di = get(d, i), hi = get(h, i);
    if (di == Fixed{}) continue;
    for (const Fixed plane : {-hi, hi}) {
      const Fixed gap = plane - oi;  // s = gap / di, kept when strictly inside (0, 1)
      if ((gap > Fixed{}) == (di > Fixed{}) && gap != Fixed{} && abs(gap) < abs(di)) {
        cuts[static_cast<size_t>(count++)] = gap / di;
      }
    }
  }
  cuts[static_cast<size_t>(count++)] = Fixed::one();
  for (int k = 1; k < count; ++k) {  // insertion sort: at most 8 cuts
    for (int j = k; j > 0 && cuts[static_cast<size_t>(j)] < cuts[static_cast<size_t>(j - 1)]; --j) {
      std::swap(cuts[static_cast<size_t>(j)], cuts[static_cast<size_t>(j - 1)]);
    }
  }
  const auto squared_distance = [&](Fixed s) {
    Fixed sum;
    for (int i = 0; i < 3; ++i) {
      const Fixed x = mul_add(get(d, i), s, get(o, i)), hi = get(h, i);
      const Fixed out = x > hi ? x - hi : (x < -hi ? x + hi : Fixed{});
      sum += out * out;
    }
    return sum;
  };
  Fixed best_s, best = squared_distance(Fixed{});
  for (int k = 0; k + 1 < count; ++k) {
    const Fixed lo = cuts[static_cast<size_t>(k)], hi_s = cuts[static_cast<size_t>(k + 1)];
    if (lo == hi_s) continue;
    const Fixed mid = lo + (hi_s - lo) / Fixed::from_int(2);
    Fixed numerator, denominator;  // s* = numerator / denominator
    for (int i = 0; i < 3; ++i) {
      const Fixed di = get(d, i), hi = get(h, i), x = mul_add(di, mid, get(o, i));
      if (x > hi || x < -hi) {
        const Fixed e = get(o, i) - (x > hi ? hi : -hi);
        numerator -= e * di;
        denominator += di * di;
      }
    }
    Fixed s = lo;
    if (denominator > Fixed{}) {
      if (numerator >= hi_s * denominator) {
        s = hi_s;
      } else if (numerator > lo * denominator) {
        s = numerator / denominator;
      }
    }
    const Fixed f = squared_distance(s);
    if (f < best) {
      best = f;
      best_s = s;
    }
  }
  return best_s;
}

// The point of a box or capsule core lowest along n (a capsule's end:
// its radius still to come).
Vec3 lowest_along(const Core& c, Vec3 n) {
  if (c.type == ShapeType::capsule) return dot(c.along, n) < Fixed{} ? c.start + c.along : c.start;
  Vec3 lowest = c.centre;
  if (c.type == ShapeType::box) {
    for (int i = 0; i < 3; ++i) {
      const Vec3 axis = c.axes.column(i);
      lowest -= axis * (dot(axis, n) < Fixed{} ? -get(c.half, i) : get(c.half, i));
    }
  }
  return lowest;
}

// The closest points of two cores (capsule-capsule, capsule-box), the
// moving one displaced by `shift`.
struct ClosestPoints {
  Vec3 on_moving, on_target;
};

Vec3 segment_point(const Core& c, Vec3 shift, Fixed s) { return mul_add(c.along, s, c.start + shift); }

Fixed segment_param_to_box(const Core& segment, Vec3 shift, const Core& box) {
  const Mat33 to_local = transpose(box.axes);
  return closest_segment_param_to_box(to_local * (segment.start + shift - box.centre), to_local * segment.along,
                                      box.half);
}

ClosestPoints closest_points(const Core& moving, Vec3 shift, const Core& target) {
  if (moving.type == ShapeType::capsule && target.type == ShapeType::capsule) {
    const auto [s, t] = closest_segment_params(moving.start + shift, moving.along, target.start, target.along);
    return {segment_point(moving, shift, s), segment_point(target, Vec3{}, t)};
  }
  if (moving.type == ShapeType::capsule) {  // against a box
    const Vec3 p = segment_point(moving, shift, segment_param_to_box(moving, shift, target));
    return {p, closest_in_box(target, p)};
  }
  // A box against a capsule: the capsule moves by -shift relative to the box.
  const Vec3 p = segment_point(target, Vec3{}, segment_param_to_box(target, -shift, moving));
  return {closest_in_box(moving, p - shift) + shift, p};
}

// Conservative advancement (the header's last case), relative to `origin`.
bool advance(const WorldShape& moving, const Ray& path, const WorldShape& target, ShapeEntry& entry) {
  const Vec3 origin = target.pose.position;
  const Core a = core_of(moving, origin), b = core_of(target, origin);
  const Fixed radii = a.radius + b.radius;
  Fixed travelled;
  for (int step = 0;; ++step) {
    const Vec3 shift = path.direction * travelled;
    const ClosestPoints closest = closest_points(a, shift, b);
    const Vec3 offset = closest.on_moving - closest.on_target;  // from the target to the moving shape
    const Fixed gap = length(offset) - radii;
    const Vec3 normal = normalize_or(offset, -path.direction);
    if (step == 0 && gap <= advance_tolerance) {
      entry = entry_at_start(moving, path);
      return true;
    }
    if (gap <= advance_tolerance || step == max_advance_steps) {
      entry = {travelled, closest.on_target + normal * b.radius + origin, normal};
      return true;
    }
    // The gap falls at `closing` m per metre travelled; when it does not
    // fall it never will (it is convex along the path).
    const Fixed closing = -dot(path.direction, normal);
    if (closing <= Fixed{}) return false;
    travelled += path_ratio(gap, closing);
    if (travelled > path.length) return false;
  }
}

// Conservative advancement over GJK (core/gjk.h), for any two convex
// shapes: the generic path a hull takes.
bool advance_convex(const WorldShape& moving, const Ray& path, const ConvexCore& target, ShapeEntry& entry) {
  Fixed travelled;
  for (int step = 0;; ++step) {
    const WorldShape placed{moving.shape,
                            {mul_add(path.direction, travelled, moving.pose.position), moving.pose.orientation}};
    const ConvexDistance d =
        convex_distance(convex_core(placed), target);  // its normal: from the moving shape to the target
    if (step == 0 && (d.overlap || d.distance <= advance_tolerance)) {
      entry = entry_at_start(moving, path);
      return true;
    }
    if (d.overlap || d.distance <= advance_tolerance || step == max_advance_steps) {
      entry = {travelled, d.point_b, -d.normal};
      return true;
    }
    const Fixed closing = dot(path.direction, d.normal);
    if (closing <= Fixed{}) return false;
    travelled += path_ratio(d.distance, closing);
    if (travelled > path.length) return false;
  }
}

// A convex shape along a path onto a mesh: conservative advancement onto
// each triangle whose front it moves toward, near the path's sweep (the
// mesh's tree, in its frame); the first entry.
bool onto_mesh(const WorldShape& moving, const Ray& path, const WorldShape& target, ShapeEntry& entry) {
  const TriangleMesh& mesh = *target.shape->mesh;
  const WorldShape at_end{moving.shape,
                          {mul_add(path.direction, path.length, moving.pose.position), moving.pose.orientation}};
  const Aabb swept = shape_aabb(moving).merged(shape_aabb(at_end));
  // The sweep's box in the mesh's frame: its eight corners taken there.
  Aabb local{target.pose.apply_inverse(swept.min), target.pose.apply_inverse(swept.min)};
  for (int k = 1; k < 8; ++k) {
    const Vec3 corner{(k & 1) != 0 ? swept.max.x : swept.min.x, (k & 2) != 0 ? swept.max.y : swept.min.y,
                      (k & 4) != 0 ? swept.max.z : swept.min.z};
    const Vec3 p = target.pose.apply_inverse(corner);
    local = local.merged({p, p});
  }
  bool found = false;
  for_each_triangle_near(mesh, local, [&](uint32_t index) {
    const TriangleMesh::Triangle& t = mesh.triangles[index];
    if (dot(rotate(target.pose.orientation, t.normal), path.direction) >= Fixed{}) return;  // behind or along it
    std::array<Vec3, 3> world;
    for (size_t k = 0; k < 3; ++k) world[k] = target.pose.apply(mesh.vertices[t.corners[k]]);
    const ConvexCore core = triangle_core(world);
    ShapeEntry e;
    if (advance_convex(moving, path, core, e) && (!found || e.distance < entry.distance)) {
      entry = e;
      found = true;
    }
  });
  return found;
}

// Box against box: the separating axis test along the path.
bool sweep_boxes(const WorldShape& moving, const Ray& path, const WorldShape& target, ShapeEntry& entry) {
  const Vec3 origin = target.pose.position;
  const Core a = core_of(moving, origin), b = core_of(target, origin);
  Fixed enter = Fixed::lowest(), leave = path.length;
  Vec3 entry_axis;
  bool entered_positive = false;
  // Along axis L the projections overlap while |s0 + v t| <= R: the centres'
  // separation s0 = (ca - cb).L moves at v = direction.L, R is the sum of
  // the two radii sum_i h_i |axis_i . L|. L need not be unit: the times are
  // ratios.
  const auto sweep_axis = [&](Vec3 axis) {
    Fixed reach;
    for (int i = 0; i < 3; ++i) {
      reach += get(a.half, i) * abs(dot(a.axes.column(i), axis)) + get(b.half, i) * abs(dot(b.axes.column(i), axis));
    }
    const Fixed s0 = dot(a.centre, axis), v = dot(path.direction, axis);
    if (v == Fixed{}) return abs(s0) <= reach;
    const Fixed t_low = path_ratio(-reach - s0, v), t_high = path_ratio(reach - s0, v);
    const Fixed t_in = v > Fixed{} ? t_low : t_high, t_out = v > Fixed{} ? t_high : t_low;
    if (t_in > enter) {
      enter = t_in;
      entry_axis = axis;
      entered_positive = v < Fixed{};  // moving down the axis, it meets the target's positive side
    }
    leave = min(leave, t_out);
    return enter <= leave;
  };
  for (int j = 0; j < 3; ++j) {
    if (!sweep_axis(b.axes.column(j))) return false;
  }
  for (int i = 0; i < 3; ++i) {
    if (!sweep_axis(a.axes.column(i))) return false;
  }
  for (int i = 0; i < 3; ++i) {
    for (int j = 0; j < 3; ++j) {
      const Vec3 axis = cross(a.axes.column(i), b.axes.column(j));
      if (length_sq(axis) < parallel_cross_sq_tolerance) continue;  // parallel edges: the face axes decide
      if (!sweep_axis(axis)) return false;
    }
  }
  if (leave < Fixed{}) return false;  // behind the path
  if (enter <= Fixed{}) {
    entry = entry_at_start(moving, path);
    return true;
  }
  const Vec3 normal = normalize(entered_positive ? entry_axis : -entry_axis);
  // Where they touch: the narrowphase's points of the boxes placed there.
  const WorldShape placed{moving.shape, {moving.pose.position + path.direction * enter, moving.pose.orientation}};
  Manifold m;
  const int count = collide(placed, target, touch_window, m);
  Vec3 sum;
  for (int k = 0; k < count; ++k) sum += m.points[static_cast<size_t>(k)].position;
  const Vec3 point =
      count > 0 ? sum / Fixed::from_int(count) : lowest_along(a, normal) + path.direction * enter + origin;
  entry = {enter, point, normal};
  return true;
}

// The moving shape's lowest point along the plane's normal, as a ray.
bool onto_plane(const WorldShape& moving, const Ray& path, const WorldShape& plane, ShapeEntry& entry) {
  const Vec3 n = plane_normal(plane);
  const Core a = core_of(moving, Vec3{});
  const Vec3 lowest = a.type == ShapeType::hull ? HullShape::core_support(moving, -n) : lowest_along(a, n);
  RayEntry e;
  if (!ray_enters(plane, {lowest, path.direction, path.length}, a.radius, e)) return false;
  if (e.distance == Fixed{}) {
    entry = entry_at_start(moving, path);
    return true;
  }
  entry = {e.distance, mul_add(path.direction, e.distance, lowest) - e.normal * a.radius, e.normal};
  return true;
}

}  // namespace

bool shape_enters(const WorldShape& moving, const Ray& path, const WorldShape& target, ShapeEntry& entry) {
  const ShapeType kind = moving.shape->type, target_kind = target.shape->type;
  RayEntry e;
  if (kind == ShapeType::plane) return false;  // planes are static
  if (kind == ShapeType::sphere) {
    const Fixed r = moving.shape->radius;
    if (!ray_enters(target, {moving.pose.position, path.direction, path.length}, r, e)) return false;
    entry = e.distance == Fixed{}
                ? entry_at_start(moving, path)
                : ShapeEntry{e.distance, mul_add(path.direction, e.distance, moving.pose.position) - e.normal * r,
                             e.normal};
    return true;
  }
  if (target_kind == ShapeType::plane) return onto_plane(moving, path, target, entry);
  if (target_kind == ShapeType::sphere) {
    // The target's centre moves backwards against the moving shape grown by its radius.
    const Fixed r = target.shape->radius;
    if (!ray_enters(moving, {target.pose.position, -path.direction, path.length}, r, e)) return false;
    entry = e.distance == Fixed{} ? entry_at_start(moving, path)
                                  : ShapeEntry{e.distance, target.pose.position - e.normal * r, -e.normal};
    return true;
  }
  if (kind == ShapeType::box && target_kind == ShapeType::box) return sweep_boxes(moving, path, target, entry);
  if (has_triangles(target_kind)) return onto_mesh(moving, path, target, entry);
  if (has_triangles(kind)) return false;  // meshes and heightfields are static
  if (kind == ShapeType::hull || target_kind == ShapeType::hull) {
    return advance_convex(moving, path, convex_core(target), entry);
  }
  return advance(moving, path, target, entry);
}

}  // namespace bitstep
