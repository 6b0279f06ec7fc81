#include "core/gjk.h"

#include "core/shape_types.h"

namespace bitstep {

namespace {

// A vertex of the Minkowski difference and the support points it came from
// (relative to A's centre).
struct Vertex {
  Vec3 w, a, b;  // w = a - b
};

// Up to four vertices, and the closest point of their hull to the origin
// as barycentric weights (summing to 1).
struct Simplex {
  Vertex v[4];
  Fixed weight[4];
  int count = 0;
};

constexpr int max_iterations = 32;

Vec3 support(const ConvexCore& s, Vec3 direction, Vec3 origin) { return s.support(s.object, direction) - origin; }

Vec3 shape_support(const void* object, Vec3 direction) {
  const WorldShape& s = *static_cast<const WorldShape*>(object);
  return with_shape_type(s.shape->type, [&](auto type) { return decltype(type)::core_support(s, direction); });
}

// The simplex kept to the vertices `keep` (indices), weighted `w`.
void reduce(Simplex& s, std::initializer_list<int> keep, std::initializer_list<Fixed> w) {
  Vertex kept[4];
  Fixed weights[4];
  int n = 0;
  auto wi = w.begin();
  for (const int i : keep) {
    kept[n] = s.v[i];
    weights[n] = *wi++;
    ++n;
  }
  for (int i = 0; i < n; ++i) {
    s.v[i] = kept[i];
    s.weight[i] = weights[i];
  }
  s.count = n;
}

// x / sum clamped to 0..1, dividing only where the quotient is inside
// (rounded products can leave a region's test a hair off its weights).
Fixed ratio(Fixed x, Fixed sum) {
  if (x <= Fixed{} || sum <= Fixed{}) return Fixed{};
  if (x >= sum) return Fixed::one();
  return x / sum;
}

// The closest point of segment (p, q) = vertices i, j to the origin.
void closest_on_segment(Simplex& s, int i, int j) {
  const Vec3 p = s.v[i].w, q = s.v[j].w;
  const Vec3 pq = q - p;
  const Fixed along = -dot(p, pq);  // t |pq|^2
  if (along <= Fixed{}) return reduce(s, {i}, {Fixed::one()});
  const Fixed len_sq = dot(pq, pq);
  if (along >= len_sq) return reduce(s, {j}, {Fixed::one()});
  const Fixed t = ratio(along, len_sq);
  reduce(s, {i, j}, {Fixed::one() - t, t});
}

// The closest point of triangle (i, j, k) to the origin: Ericson's
// ClosestPtPointTriangle (Real-Time Collision Detection, 5.1.5) with the
// origin as the point.
void closest_on_triangle(Simplex& s, int i, int j, int k) {
  const Vec3 a = s.v[i].w, b = s.v[j].w, c = s.v[k].w;
  const Vec3 ab = b - a, ac = c - a, ap = -a;
  const Fixed d1 = dot(ab, ap), d2 = dot(ac, ap);
  if (d1 <= Fixed{} && d2 <= Fixed{}) return reduce(s, {i}, {Fixed::one()});
  const Vec3 bp = -b;
  const Fixed d3 = dot(ab, bp), d4 = dot(ac, bp);
  if (d3 >= Fixed{} && d4 <= d3) return reduce(s, {j}, {Fixed::one()});
  const Fixed vc = d1 * d4 - d3 * d2;
  if (vc <= Fixed{} && d1 >= Fixed{} && d3 <= Fixed{}) {
    const Fixed t = ratio(d1, d1 - d3);
    return reduce(s, {i, j}, {Fixed::one() - t, t});
  }
  const Vec3 cp = -c;
  const Fixed d5 = dot(ab, cp), d6 = dot(ac, cp);
  if (d6 >= Fixed{} && d5 <= d6) return reduce(s, {k}, {Fixed::one()});
  const Fixed vb = d5 * d2 - d1 * d6;
  if (vb <= Fixed{} && d2 >= Fixed{} && d6 <= Fixed{}) {
    const Fixed t = ratio(d2, d2 - d6);
    return reduce(s, {i, k}, {Fixed::one() - t, t});
  }
  const Fixed va = d3 * d6 - d5 * d4;
  if (va <= Fixed{} && d4 - d3 >= Fixed{} && d5 - d6 >= Fixed{}) {
    const Fixed t = ratio(d4 - d3, (d4 - d3) + (d5 - d6));
    return reduce(s, {j, k}, {Fixed::one() - t, t});
  }
  const Fixed sum = va + vb + vc;
  if (sum <= Fixed{}) return closest_on_segment(s, i, j);  // degenerate (flat): an edge
  const Fixed v = ratio(vb, sum), w = ratio(vc, sum);
  reduce(s, {i, j, k}, {Fixed::one() - v - w, v, w});
}

// Whether face (a, b, c) faces the origin away from vertex d: the origin
// strictly on the other side of its plane. A flat tetrahedron (d in the
// plane) has no inside: every face counts.
bool origin_outside(Vec3 a, Vec3 b, Vec3 c, Vec3 d) {
  const Vec3 n = cross(b - a, c - a);
  const Fixed origin_side = -dot(a, n);  // dot(0 - a, n)
  const Fixed d_side = dot(d - a, n);
  if (d_side == Fixed{}) return true;
  return origin_side != Fixed{} && (origin_side > Fixed{}) != (d_side > Fixed{});
}

Vec3 point_of(const Simplex& s) {
  Vec3 p;
  for (int i = 0; i < s.count; ++i) p += s.v[i].w * s.weight[i];
  return p;
}

// The closest point of the tetrahedron to the origin: the nearest of its
// faces that the origin lies outside; none: the origin is inside.
bool closest_on_tetrahedron(Simplex& s) {
  static constexpr int faces[4][4] = {{0, 1, 2, 3}, {0, 2, 3, 1}, {0, 3, 1, 2}, {1, 3, 2, 0}};
  Simplex best;
  Fixed best_sq = Fixed::max();
  bool outside_any = false;
  for (const auto& f : faces) {
    if (!origin_outside(s.v[f[0]].w, s.v[f[1]].w, s.v[f[2]].w, s.v[f[3]].w)) continue;
    outside_any = true;
    Simplex face = s;
    closest_on_triangle(face, f[0], f[1], f[2]);
    const Fixed sq = length_sq(point_of(face));
    if (sq < best_sq) {
      best_sq = sq;
      best = face;
    }
  }
  if (!outside_any) return false;
  s = best;
  return true;
}

}  // namespace

// The corner farthest along d; the first of equals.
Vec3 corner_support(const void* object, Vec3 direction) {
  const auto& corners = *static_cast<const std::array<Vec3, 3>*>(object);
  size_t best = 0;
  for (size_t i = 1; i < 3; ++i) {
    if (dot(corners[i], direction) > dot(corners[best], direction)) best = i;
  }
  return corners[best];
}

ConvexCore triangle_core(const std::array<Vec3, 3>& corners) {
  return {&corners, corner_support, (corners[0] + corners[1] + corners[2]) / 3.0_fx, Fixed{}};
}

ConvexCore convex_core(const WorldShape& s) {
  const Fixed radius = with_shape_type(s.shape->type, [&](auto type) { return decltype(type)::core_radius(*s.shape); });
  return {&s, shape_support, s.pose.position, radius};
}

ConvexDistance convex_distance(const ConvexCore& a, const ConvexCore& b) {
  ConvexDistance result;
  const Vec3 origin = a.centre;
  Simplex s;
  Vec3 direction = b.centre - a.centre;  // a first guess: from A toward B
  if (direction == Vec3{}) direction = {Fixed::one(), Fixed{}, Fixed{}};
  // v: the closest point of the simplex so far (of A - B); search along -v.
  const Vec3 first_a = support(a, -direction, origin), first_b = support(b, direction, origin);
  s.v[0] = {first_a - first_b, first_a, first_b};
  s.weight[0] = Fixed::one();
  s.count = 1;
  Vec3 v = s.v[0].w;
  for (int iteration = 1; iteration <= max_iterations; ++iteration) {
    result.iterations = iteration;
    const Fixed v_sq = length_sq(v);
    if (v_sq == Fixed{}) {
      result.overlap = true;
      break;
    }
    const Vec3 pa = support(a, -v, origin), pb = support(b, v, origin);
    const Vec3 w = pa - pb;
    // No progress along -v (within the rounding of a few products): v is
    // the closest point.
    if (v_sq - dot(v, w) <= Fixed::from_raw(64)) break;
    bool repeated = false;
    for (int i = 0; i < s.count; ++i) repeated = repeated || s.v[i].w == w;
    if (repeated) break;
    s.v[s.count++] = {w, pa, pb};
    switch (s.count) {
      case 2: closest_on_segment(s, 0, 1); break;
      case 3: closest_on_triangle(s, 0, 1, 2); break;
      default:
        if (!closest_on_tetrahedron(s)) result.overlap = true;
        break;
    }
    if (result.overlap) break;
    const Vec3 next = point_of(s);
    if (length_sq(next) >= v_sq) break;  // no closer: rounding has the last word
    v = next;
  }
  const Fixed ra = a.radius, rb = b.radius;
  if (result.overlap) {
    result.distance = -(ra + rb);
    return result;
  }
  Vec3 ca, cb;
  for (int i = 0; i < s.count; ++i) {
    ca += s.v[i].a * s.weight[i];
    cb += s.v[i].b * s.weight[i];
  }
  const Vec3 between = cb - ca;
  const Fixed core_distance = length(between);
  result.normal = normalize_or(between, Vec3{Fixed::one(), Fixed{}, Fixed{}});
  result.distance = core_distance - ra - rb;
  result.point_a = origin + ca + result.normal * ra;
  result.point_b = origin + cb - result.normal * rb;
  return result;
}

}  // namespace bitstep
