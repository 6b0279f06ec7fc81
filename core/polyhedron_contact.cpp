// The separating-axis pieces (core/polyhedron_contact.h).
#include "core/polyhedron_contact.h"

namespace bitstep::collide_detail::polyhedra {

void place(const Polyhedron& shape, const Mat33& r, Vec3 t, Framed& out) {
  out.shape = shape;
  out.vertex_count = shape.vertices.size();
  out.face_count = shape.faces.size();
  for (size_t i = 0; i < out.vertex_count; ++i) out.vertices[i] = r * shape.vertices[i] + t;
  for (size_t f = 0; f < out.face_count; ++f) {
    const ConvexHull::Face& face = shape.faces[f];
    out.normals[f] = r * face.normal;
    out.offsets[f] = face.offset + dot(out.normals[f], t);  // n' . (R x + t) = n . x + n' . t
  }
  for (size_t e = 0; e < shape.edges.size(); ++e) out.directions[e] = r * shape.edge_directions[e];
  out.inside = r * shape.inside + t;
}

FaceQuery query_faces(const Framed& p, const Framed& q) {
  FaceQuery best;
  for (size_t f = 0; f < p.face_count; ++f) {
    Fixed lowest = Fixed::max();
    for (size_t j = 0; j < q.vertex_count; ++j) lowest = min(lowest, dot(p.normals[f], q.vertices[j]));
    const Fixed separation = lowest - p.offsets[f];
    if (separation > best.separation) best = {separation, f};
  }
  return best;
}

int sign(Fixed x) { return x < Fixed{} ? -1 : (x > Fixed{} ? 1 : 0); }

EdgeQuery query_edges(const Framed& a, const Framed& b) {
  EdgeQuery best;
  std::array<int, max_faces> b_side;  // sign(n_B . direction_A), by B's face
  for (size_t i = 0; i < a.shape.edges.size(); ++i) {
    const ConvexHull::Edge& ea = a.shape.edges[i];
    const Vec3 tail_a = a.vertices[ea.tail];
    const Vec3 direction_a = a.directions[i];
    for (size_t g = 0; g < b.face_count; ++g) b_side[g] = sign(dot(b.normals[g], direction_a));
    for (size_t j = 0; j < b.shape.edges.size(); ++j) {
      const ConvexHull::Edge& eb = b.shape.edges[j];
      // c . b_x_a = -b_side[face], d . b_x_a = -b_side[twin] (c, d negated).
      const int cba = -b_side[eb.face], dba = -b_side[eb.twin_face];
      if (cba * dba >= 0) continue;
      const Vec3 direction_b = b.directions[j];
      const int adc = sign(dot(a.normals[ea.face], direction_b)), bdc = sign(dot(a.normals[ea.twin_face], direction_b));
      if (adc * bdc >= 0 || cba * bdc <= 0) continue;
      const Vec3 axis = cross(direction_a, direction_b);
      if (length_sq(axis) < parallel_cross_sq_tolerance) continue;  // parallel edges: a face axis decides
      Vec3 normal = normalize(axis);
      if (dot(normal, tail_a - a.inside) < Fixed{}) normal = -normal;
      const Fixed separation = dot(normal, b.vertices[eb.tail] - tail_a);
      if (separation > best.separation) best = {separation, true, i, j, normal};
    }
  }
  return best;
}

int clip(const ClipVertex* in, int count, Vec3 s, Vec3 a, uint32_t plane_tag, ClipVertex* out) {
  int kept = 0;
  for (int i = 0; i < count && kept < clip_capacity - 1; ++i) {
    const ClipVertex& from = in[i];
    const ClipVertex& to = in[i + 1 < count ? i + 1 : 0];
    const Fixed d_from = dot(s, from.p - a), d_to = dot(s, to.p - a);
    const bool from_inside = d_from <= Fixed{}, to_inside = d_to <= Fixed{};
    if (from_inside) out[kept++] = from;
    if (from_inside != to_inside) {
      // x = from + (to - from) d_from / (d_from - d_to): the signs differ, so
      // the divisor is not zero and the ratio lies in [0, 1].
      const Fixed denominator = d_from - d_to;
      const Vec3 delta = to.p - from.p;
      const Vec3 x{from.p.x + mul_div(delta.x, d_from, denominator), from.p.y + mul_div(delta.y, d_from, denominator),
                   from.p.z + mul_div(delta.z, d_from, denominator)};
      out[kept++] = {x, from_inside ? plane_tag : from.out_edge};
    }
  }
  return kept;
}

int reduce_to_four(const Candidate* c, int count, Vec3 normal, int* chosen) {
  return choose_four(
      count, [&](int i) { return c[i].depth; }, [&](int from, int to) { return length_sq(c[to].p - c[from].p); },
      [&](int from, int to, int i) { return dot(cross(c[to].p - c[from].p, c[i].p - c[from].p), normal); }, chosen);
}

int emit(const Candidate* c, int count, Vec3 normal_in_a, const Pose& pose_a, const Mat33& rot_a, Manifold& out) {
  int chosen[max_manifold_points] = {0, 1, 2, 3};
  if (count > max_manifold_points) count = reduce_to_four(c, count, normal_in_a, chosen);
  for (int k = 0; k < count; ++k) {
    const Candidate& p = c[chosen[k]];
    add_point(out, pose_a.position + rot_a * p.p, p.depth, p.feature);
  }
  return count;
}

int face_contact(const Framed& p, size_t f, const Framed& q, uint32_t kind, Fixed speculative_distance,
                 Candidate* candidates) {
  const Vec3 n = p.normals[f];
  size_t incident = 0;
  Fixed most_against = Fixed::max();
  for (size_t g = 0; g < q.face_count; ++g) {
    const Fixed along = dot(q.normals[g], n);
    if (along < most_against) {
      most_against = along;
      incident = g;
    }
  }
  std::array<ClipVertex, clip_capacity> buffer_1, buffer_2;
  const ConvexHull::Face& in_face = q.shape.faces[incident];
  int count = in_face.count;
  for (uint16_t i = 0; i < in_face.count; ++i) {
    buffer_1[i] = {q.vertices[q.shape.face_vertices[in_face.first + i]], i};
  }
  ClipVertex* in = buffer_1.data();
  ClipVertex* out = buffer_2.data();
  const ConvexHull::Face& ref_face = p.shape.faces[f];
  for (uint16_t i = 0; i < ref_face.count && count > 0; ++i) {
    const Vec3 a = p.vertices[p.shape.face_vertices[ref_face.first + i]];
    const Vec3 b = p.vertices[p.shape.face_vertices[ref_face.first + (i + 1u) % ref_face.count]];
    count = clip(in, count, cross(b - a, n), a, side_plane_tag + i, out);
    std::swap(in, out);
  }
  int kept = 0;
  for (int i = 0; i < count; ++i) {
    const Fixed depth = p.offsets[f] - dot(n, in[i].p);
    if (depth <= -speculative_distance) continue;
    const uint32_t previous = in[i > 0 ? i - 1 : count - 1].out_edge;
    const FeatureId feature = kind << 24 | static_cast<uint32_t>(f) << 18 | static_cast<uint32_t>(incident) << 12 |
                              previous << 6 | in[i].out_edge;
    candidates[kept++] = {mul_add(n, depth * half, in[i].p), depth, feature};
  }
  return kept;
}

}  // namespace bitstep::collide_detail::polyhedra
