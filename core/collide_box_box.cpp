// Box-box: the separating axis test over 15 axes (Gottschalk's OBB test, as in
// qu3e's q3BoxtoBox and Box2D's polygon collider), then either the incident
// face clipped against the reference face's side planes (up to 4 points) or
// one point between two crossing edges (an edge axis along a face normal is
// that face's contact: collide_internal.h).
#include "core/collide_internal.h"

namespace bitstep::collide_detail {

namespace {

// A vertex of the polygon being clipped, in the reference box's frame, with
// the tag of the polygon edge that leaves it (0..3: incident face edges,
// 4..7: reference side planes). Its feature is (previous vertex's tag, tag).
struct ClipVertex {
  Vec3 p;
  uint32_t out_edge = 0;
};

inline constexpr int clip_capacity = 16;  // a quad clipped by 4 planes has at most 8

// Sutherland-Hodgman: keeps the part of the convex polygon `in` with
// side * x[axis] <= limit (side = +-1). A vertex on the plane is inside.
int clip(const ClipVertex* in, int count, int axis, bool negative_side, Fixed limit, uint32_t plane_tag,
         ClipVertex* out) {
  auto distance = [&](Vec3 p) { return (negative_side ? -get(p, axis) : get(p, axis)) - limit; };
  int kept = 0;
  for (int i = 0; i < count && kept < clip_capacity - 1; ++i) {
    const ClipVertex& from = in[i];
    const ClipVertex& to = in[i + 1 < count ? i + 1 : 0];
    const Fixed d_from = distance(from.p), d_to = distance(to.p);
    const bool from_inside = d_from <= Fixed{}, to_inside = d_to <= Fixed{};
    if (from_inside) out[kept++] = from;  // its outgoing edge continues on the same line
    if (from_inside != to_inside) {
      // x = from + (to - from) d_from / (d_from - d_to); the divisor is non-zero
      // because the signs differ, and the ratio is in [0, 1].
      const Fixed denominator = d_from - d_to;
      const Vec3 delta = to.p - from.p;
      Vec3 x{from.p.x + mul_div(delta.x, d_from, denominator), from.p.y + mul_div(delta.y, d_from, denominator),
             from.p.z + mul_div(delta.z, d_from, denominator)};
      set(x, axis, negative_side ? -limit : limit);  // exactly on the plane
      // Leaving the kept region the new edge runs along the plane; entering
      // it, along the original edge.
      out[kept++] = {x, from_inside ? plane_tag : from.out_edge};
    }
  }
  return kept;
}

struct Candidate {
  Vec3 p;       // reference frame, on the incident face
  Fixed depth;  // m, below the reference face
  FeatureId feature;
};

// Four of `count` > 4 candidates (choose_four), measured in the reference
// face's plane (its two tangent axes).
int reduce_to_four(const Candidate* c, int count, int tangent_1, int tangent_2, int* chosen) {
  auto plane_delta = [&](int from, int to) {
    return std::array<Fixed, 2>{get(c[to].p, tangent_1) - get(c[from].p, tangent_1),
                                get(c[to].p, tangent_2) - get(c[from].p, tangent_2)};
  };
  return choose_four(
      count, [&](int i) { return c[i].depth; },
      [&](int from, int to) {
        const auto e = plane_delta(from, to);
        return det2(e[0], e[0], -e[1], e[1]);
      },
      [&](int from, int to, int i) {
        const auto base = plane_delta(from, to), e = plane_delta(from, i);
        return det2(base[0], e[1], base[1], e[0]);  // twice the signed triangle area
      },
      chosen);
}

// Edge index for feature ids: 4 * axis + (bit 0: + on axis+1, bit 1: + on axis+2).
uint32_t edge_index(int axis, Vec3 corner) {
  const uint32_t bit0 = get(corner, (axis + 1) % 3) > Fixed{} ? 1u : 0u;
  const uint32_t bit1 = get(corner, (axis + 2) % 3) > Fixed{} ? 2u : 0u;
  return static_cast<uint32_t>(4 * axis) + bit0 + bit1;
}

// One point between A's edge along axis i and B's edge along axis j, the
// edges being the ones most in the direction of the normal (A's) and against
// it (B's). d: B's centre minus A's.
int edge_contact(const Mat33& rot_a, const Mat33& rot_b, Vec3 ea, Vec3 eb, Vec3 d, Vec3 origin, int i, int j,
                 Fixed speculative_distance, Manifold& out) {
  const Vec3 axis_a = rot_a.column(i), axis_b = rot_b.column(j);
  Vec3 n = normalize(cross(axis_a, axis_b));  // |a x b|^2 >= parallel_cross_sq_tolerance here
  if (dot(n, d) < Fixed{}) n = -n;
  const Vec3 n_a = transpose(rot_a) * n, n_b = transpose(rot_b) * n;
  Vec3 corner_a, corner_b;
  for (int m = 0; m < 3; ++m) {
    set(corner_a, m, get(n_a, m) < Fixed{} ? -get(ea, m) : get(ea, m));
    set(corner_b, m, get(n_b, m) > Fixed{} ? -get(eb, m) : get(eb, m));
  }
  set(corner_a, i, -get(ea, i));  // the edges run from -e to +e along their axis
  set(corner_b, j, -get(eb, j));
  const Vec3 start_a = rot_a * corner_a, start_b = d + rot_b * corner_b;  // relative to A's centre
  const Vec3 dir_a = axis_a * (get(ea, i) + get(ea, i)), dir_b = axis_b * (get(eb, j) + get(eb, j));
  const SegmentParams params = closest_segment_params(start_a, dir_a, start_b, dir_b);
  const Vec3 point_a = mul_add(dir_a, params.s, start_a), point_b = mul_add(dir_b, params.t, start_b);
  const Fixed depth = -dot(point_b - point_a, n);
  if (depth <= -speculative_distance) return 0;
  out.normal = n;
  add_point(out, origin + (point_a + point_b) * half, depth,
            box_feature(3, edge_index(i, corner_a), edge_index(j, corner_b), 0, 0));
  return 1;
}

// The two boxes as the separating axis test and the clipping read them: A's
// frame is the working frame.
struct BoxPair {
  Mat33 rot_a, rot_b;
  Vec3 ea, eb;  // half extents
  Vec3 d;       // B's centre minus A's (world)
  Vec3 t_a;     // B's centre in A's frame
  Vec3 t_b;     // A's centre in B's frame
  Mat33 c;      // c_ij = a_i . b_j: column j is B's axis j in A's frame
  Mat33 ct;
  Mat33 abs_c;
};

BoxPair box_pair(const WorldShape& a, const WorldShape& b) {
  BoxPair p;
  p.rot_a = axes_of(a);
  p.rot_b = axes_of(b);
  p.ea = a.shape->half_extents;
  p.eb = b.shape->half_extents;
  p.d = b.pose.position - a.pose.position;
  p.t_a = transpose(p.rot_a) * p.d;
  p.t_b = transpose(p.rot_b) * -p.d;
  p.c = transpose(p.rot_a) * p.rot_b;
  p.ct = transpose(p.c);
  p.abs_c = Mat33{{abs(p.c.rows[0]), abs(p.c.rows[1]), abs(p.c.rows[2])}};
  return p;
}

// Face axes. Separation along a_i: |t_i| - (ea_i + sum_j |c_ij| eb_j), and
// along b_j the same from B's side. False when one proves the boxes apart.
bool face_axes(const BoxPair& p, Fixed speculative_distance, Axis& face_a, Axis& face_b) {
  face_a = Axis{Fixed::lowest()};
  face_b = Axis{Fixed::lowest()};
  for (int i = 0; i < 3; ++i) {
    const Fixed s = abs(get(p.t_a, i)) - get(p.ea, i) - dot(row(p.abs_c, i), p.eb);
    if (s > speculative_distance) return false;
    if (s > face_a.separation) face_a = {s, i};
  }
  for (int j = 0; j < 3; ++j) {
    const Fixed s = abs(get(p.t_b, j)) - get(p.eb, j) - dot(p.abs_c.column(j), p.ea);
    if (s > speculative_distance) return false;
    if (s > face_b.separation) face_b = {s, j};
  }
  return true;
}

// Edge axes l = a_i x b_j (in A's frame), not normalised: the separation
// times |l| is |t.l| - ea.|l| - eb.|c^T l|. Since |l| <= 1, a negative
// scaled separation only grows more negative when divided by |l|, so an
// axis is normalised only when it could beat the best one (or is positive,
// where it could prove the boxes apart).
// With p, q the axes after i, l = e_i x c_j is exactly (l_i, l_p, l_q) =
// (0, -c_qj, c_pj): cross rounds its products by 0 and 1 exactly. So each
// dot product with l is an exact sum of two products rounded once (det2;
// negating an entry of c, within [-3, 3], or a half extent is exact), as
// dot rounds its three: the same bits without the products by zero.
// `edge` starts at the separation to beat; false when an axis proves the
// boxes apart.
bool edge_axes(const BoxPair& pair, Fixed speculative_distance, Axis& edge) {
  const Mat33& c = pair.c;
  const Vec3 t_a = pair.t_a, ea = pair.ea, eb = pair.eb;
  for (int i = 0; i < 3; ++i) {
    const int p = (i + 1) % 3, q = (i + 2) % 3;
    const Vec3 c_p = row(c, p), c_q = row(c, q);
    for (int j = 0; j < 3; ++j) {
      const Fixed l_q = get(c_p, j), minus_l_p = get(c_q, j);
      if (det2(l_q, l_q, -minus_l_p, minus_l_p) < parallel_cross_sq_tolerance) continue;  // |l|^2
      const Fixed t_l = det2(get(t_a, q), l_q, get(t_a, p), minus_l_p);
      const Fixed ea_abs_l = det2(get(ea, p), abs(minus_l_p), -get(ea, q), abs(l_q));
      // B's part, eb . |c^T l| below, is >= 0 (a sum of products of
      // non-negative numbers, rounded): without it the scaled separation is
      // already an upper bound, and an axis that cannot win on it is
      // skipped with the same answer.
      const Fixed beat = min(edge.separation, Fixed{});
      if (abs(t_l) - ea_abs_l <= beat) continue;
      // l in B's frame: (c^T l)_k = c_pk l_p + c_qk l_q.
      const Vec3 l_b{det2(c_q.x, l_q, c_p.x, minus_l_p), det2(c_q.y, l_q, c_p.y, minus_l_p),
                     det2(c_q.z, l_q, c_p.z, minus_l_p)};
      const Fixed scaled = abs(t_l) - ea_abs_l - dot(eb, abs(l_b));
      if (scaled <= beat) continue;
      const Fixed s = scaled / length(cross(unit_axis(i), c.column(j)));
      if (s > speculative_distance) return false;
      if (s > edge.separation) edge = {s, 3 * i + j};
    }
  }
  return true;
}

// The face an edge axis lies along (collide_internal.h,
// face_aligned_edge_sq_tolerance): A's faces first, then B's; -1 if none.
int face_along_edge_axis(const BoxPair& p, int edge_index, bool& face_of_b) {
  const Vec3 l = cross(unit_axis(edge_index / 3), p.c.column(edge_index % 3));
  const Vec3 n_a = l / length(l), n_b = p.ct * n_a;  // n in A's frame and in B's
  const Fixed aligned = Fixed::one() - face_aligned_edge_sq_tolerance;
  face_of_b = false;
  for (int m = 0; m < 3; ++m) {
    if (get(n_a, m) * get(n_a, m) >= aligned) return m;
  }
  for (int m = 0; m < 3; ++m) {
    if (get(n_b, m) * get(n_b, m) >= aligned) {
      face_of_b = true;
      return m;
    }
  }
  return -1;
}

// The reference face (axis k of the reference box, on the side facing the
// other box) and the incident box's face most anti-parallel to it, as
// polygons in the reference box's frame.
struct FaceClip {
  bool reference_b;
  int k;              // the reference face's axis
  bool ref_negative;  // the reference face is on the negative side of axis k
  int j;              // the incident face's axis
  bool inc_negative;
  Vec3 er;  // the reference box's half extents
};

// The incident face's corners in the reference frame, (+,+), (-,+), (-,-),
// (+,-) in its two other axes: a loop around the face.
void incident_face(const BoxPair& p, FaceClip& f, ClipVertex* polygon) {
  const Vec3 ei = f.reference_b ? p.ea : p.eb;
  const Vec3 t = f.reference_b ? p.t_b : p.t_a;      // incident centre
  const Mat33& axes_i = f.reference_b ? p.ct : p.c;  // incident axes as columns
  f.ref_negative = get(t, f.k) < Fixed{};            // the reference face faces the incident box
  const Vec3 row_k = row(axes_i, f.k);               // the incident axes' components along the reference normal axis
  f.j = 0;
  for (int m = 1; m < 3; ++m) {
    if (abs(get(row_k, m)) > abs(get(row_k, f.j))) f.j = m;
  }
  f.inc_negative = (get(row_k, f.j) < Fixed{}) == f.ref_negative;
  const int j = f.j, u = (j + 1) % 3, v = (j + 2) % 3;
  for (int m = 0; m < 4; ++m) {
    Vec3 corner;
    set(corner, j, f.inc_negative ? -get(ei, j) : get(ei, j));
    set(corner, u, (m == 1 || m == 2) ? -get(ei, u) : get(ei, u));
    set(corner, v, m >= 2 ? -get(ei, v) : get(ei, v));
    polygon[m] = {axes_i * corner + t, static_cast<uint32_t>(m)};
  }
}

// The clipped points at most `speculative_distance` above the reference
// face, with their depths and feature ids.
int face_candidates(const FaceClip& f, const ClipVertex* clipped, int count, Fixed speculative_distance,
                    Candidate* candidates) {
  const uint32_t kind = f.reference_b ? 2u : 1u;
  const uint32_t ref_face = static_cast<uint32_t>(2 * f.k) + (f.ref_negative ? 1u : 0u);
  const uint32_t inc_face = static_cast<uint32_t>(2 * f.j) + (f.inc_negative ? 1u : 0u);
  int kept = 0;
  for (int q = 0; q < count; ++q) {
    const Fixed height = get(clipped[q].p, f.k);
    const Fixed depth = get(f.er, f.k) - (f.ref_negative ? -height : height);
    if (depth <= -speculative_distance) continue;
    const uint32_t in_edge = clipped[q > 0 ? q - 1 : count - 1].out_edge;
    candidates[kept++] = {clipped[q].p, depth, box_feature(kind, ref_face, inc_face, in_edge, clipped[q].out_edge)};
  }
  return kept;
}

// Face contact: the incident face clipped by the reference face's four side
// planes, at most four points kept, each halfway up to the reference face.
int face_contact(const BoxPair& p, const WorldShape& a, const WorldShape& b, bool reference_b, int k,
                 Fixed speculative_distance, Manifold& out) {
  FaceClip f{reference_b, k, false, 0, false, reference_b ? p.eb : p.ea};
  ClipVertex polygon[2][clip_capacity];
  incident_face(p, f, polygon[0]);
  const Mat33& rot_r = reference_b ? p.rot_b : p.rot_a;
  const Vec3 center_r = reference_b ? b.pose.position : a.pose.position;
  const Vec3 ref_normal = normalize(f.ref_negative ? -rot_r.column(k) : rot_r.column(k));
  out.normal = reference_b ? -ref_normal : ref_normal;

  int count = 4;
  const int tangent_1 = (k + 1) % 3, tangent_2 = (k + 2) % 3;
  const int plane_axis[4] = {tangent_1, tangent_2, tangent_1, tangent_2};
  for (int q = 0; q < 4 && count > 0; ++q) {
    count = clip(polygon[q % 2], count, plane_axis[q], q >= 2, get(f.er, plane_axis[q]), static_cast<uint32_t>(4 + q),
                 polygon[(q + 1) % 2]);
  }
  Candidate candidates[clip_capacity];
  const int kept = face_candidates(f, polygon[0], count, speculative_distance, candidates);  // after 4 planes
  int chosen[max_manifold_points] = {0, 1, 2, 3};
  const int n = kept > max_manifold_points ? reduce_to_four(candidates, kept, tangent_1, tangent_2, chosen) : kept;
  for (int q = 0; q < n; ++q) {
    const Candidate& c_q = candidates[chosen[q]];
    Vec3 mid = c_q.p;  // halfway up to the reference face
    const Fixed half_depth = c_q.depth * half;
    set(mid, k, get(mid, k) + (f.ref_negative ? -half_depth : half_depth));
    add_point(out, center_r + rot_r * mid, c_q.depth, c_q.feature);
  }
  return n;
}

}  // namespace

int collide_box_box(const WorldShape& a, const WorldShape& b, Fixed speculative_distance, Manifold& out) {
  const BoxPair p = box_pair(a, b);
  Axis face_a, face_b;
  if (!face_axes(p, speculative_distance, face_a, face_b)) return 0;
  bool reference_b = face_b.separation > face_a.separation + margin(face_a.separation);
  const Fixed face_separation = reference_b ? face_b.separation : face_a.separation;
  Axis edge{face_separation + margin(face_separation)};
  if (!edge_axes(p, speculative_distance, edge)) return 0;
  int k = reference_b ? face_b.index : face_a.index;
  if (edge.index >= 0) {
    bool face_of_b = false;
    const int face = face_along_edge_axis(p, edge.index, face_of_b);
    if (face < 0) {
      return edge_contact(p.rot_a, p.rot_b, p.ea, p.eb, p.d, a.pose.position, edge.index / 3, edge.index % 3,
                          speculative_distance, out);
    }
    k = face;
    reference_b = face_of_b;
  }
  return face_contact(p, a, b, reference_b, k, speculative_distance, out);
}

}  // namespace bitstep::collide_detail
