// collide(): dispatch over the pair of shape types, and the helpers the pair
// functions share (core/collide_internal.h).
#include "core/collide.h"

#include "core/collide_internal.h"

namespace bitstep {

namespace collide_detail {

Fixed clamped_ratio(Fixed numerator, Fixed denominator) {
  if (numerator <= Fixed{}) return Fixed{};
  if (numerator >= denominator) return Fixed::one();
  return numerator / denominator;
}

SegmentParams closest_segment_params(Vec3 p1, Vec3 d1, Vec3 p2, Vec3 d2) {
  // Minimise |p1 + s d1 - p2 - t d2|^2. With r = p1 - p2:
  //   a = d1.d1, b = d1.d2, e = d2.d2, c = d1.r, f = d2.r,
  //   s = (b f - c e) / (a e - b^2), then t = (b s + f) / e, each clamped to
  //   [0, 1] and the other recomputed (Ericson 5.1.9).
  const Vec3 r = p1 - p2;
  const Fixed a = dot(d1, d1), e = dot(d2, d2), f = dot(d2, r);
  const Fixed zero{}, one = Fixed::one();
  if (a <= degenerate_length_sq && e <= degenerate_length_sq) return {zero, zero};
  if (a <= degenerate_length_sq) return {zero, clamped_ratio(f, e)};
  const Fixed c = dot(d1, r);
  if (e <= degenerate_length_sq) return {clamped_ratio(-c, a), zero};
  const Fixed b = dot(d1, d2);
  const Fixed denominator = det2(a, e, b, b);  // |d1 x d2|^2 >= 0
  Fixed s = zero;
  if (denominator > zero) s = clamped_ratio(det2(b, f, c, e), denominator);
  const Fixed t_numerator = mul_add(b, s, f);  // t = (b s + f) / e
  if (t_numerator <= zero) return {clamped_ratio(-c, a), zero};
  if (t_numerator >= e) return {clamped_ratio(b - c, a), one};
  return {s, t_numerator / e};
}

Fixed closest_param_to_point(Vec3 p, Vec3 d, Vec3 q) {
  const Fixed length_squared = dot(d, d);
  if (length_squared <= degenerate_length_sq) return Fixed{};
  return clamped_ratio(dot(q - p, d), length_squared);
}

Vec3 plane_normal(const WorldShape& plane) {
  return normalize_or(rotate(plane.pose.orientation, unit_axis(1)), unit_axis(1));
}

namespace {

// Pair order: each pair function takes the higher-ranked shape first.
int rank(ShapeType type) {
  switch (type) {
    case ShapeType::plane: return 0;
    case ShapeType::box: return 1;
    case ShapeType::sphere: return 2;
    case ShapeType::capsule: return 3;
    case ShapeType::hull: return 4;
    case ShapeType::mesh:
    case ShapeType::heightfield: return 5;  // a heightfield is a mesh
  }
  return 0;
}

// The routine of each pair, by rank: pairs[rank a][rank b] for rank a >=
// rank b (the routine takes the higher-ranked shape first). A new shape
// adds its row and a column to the rows after it.
using PairRoutine = int (*)(const WorldShape& a, const WorldShape& b, Fixed speculative_distance, Manifold& out);

int no_contact(const WorldShape&, const WorldShape&, Fixed, Manifold&) {
  return 0;
}  // plane-plane, mesh-plane, mesh-mesh: static shapes

constexpr int shape_count = 6;
constexpr PairRoutine pairs[shape_count][shape_count] = {
    // clang-format off
    /* plane   */ {no_contact},
    /* box     */ {collide_box_plane, collide_box_box},
    /* sphere  */ {collide_sphere_plane, collide_sphere_box, collide_sphere_sphere},
    /* capsule */ {collide_capsule_plane, collide_capsule_box, collide_capsule_sphere, collide_capsule_capsule},
    /* hull    */ {collide_hull_plane, collide_hull_box, collide_hull_sphere, collide_hull_capsule, collide_hull_hull},
    /* mesh    */ {no_contact, collide_mesh_box, collide_mesh_sphere, collide_mesh_capsule, collide_mesh_hull,
                   no_contact},
    // clang-format on
};

// a has rank >= b's.
int dispatch(const WorldShape& a, const WorldShape& b, Fixed speculative_distance, Manifold& out) {
  return pairs[rank(a.shape->type)][rank(b.shape->type)](a, b, speculative_distance, out);
}

}  // namespace

}  // namespace collide_detail

int collide(const WorldShape& a, const WorldShape& b, Fixed speculative_distance, Manifold& out) {
  using namespace collide_detail;
  out = Manifold{};
  const bool swapped = rank(a.shape->type) < rank(b.shape->type);
  const int count = swapped ? dispatch(b, a, speculative_distance, out) : dispatch(a, b, speculative_distance, out);
  out.point_count = count;
  if (count == 0) {
    out = Manifold{};
    return 0;
  }
  if (swapped) out.normal = -out.normal;  // the pair function's normal points from b to a
  return count;
}

}  // namespace bitstep
