#include "core/shock_solve.h"

#include <bit>

namespace bitstep {

// A copy of a row with body a (or b) immovable: its linear part and turn
// are dropped and the effective mass is the other body's alone.
namespace {

Jacobian frozen(Jacobian j, const SolverBody& a, const SolverBody& b, bool freeze_a) {
  Fixed k;
  if (freeze_a) {
    j.linear_a = j.turn_a = Vec3{};
    k = b.inverse_mass + dot(j.arm_b, j.turn_b);
  } else {
    j.linear_b = j.turn_b = Vec3{};
    k = a.inverse_mass + dot(j.arm_a, j.turn_a);
  }
  j.mass = k > Fixed{} ? Fixed::one() / k : Fixed{};
  return j;
}

AngularPart frozen(AngularPart j, bool freeze_a) {
  Fixed k;
  if (freeze_a) {
    j.turn_a = Vec3{};
    k = dot(j.axis, j.turn_b);
  } else {
    j.turn_b = Vec3{};
    k = dot(j.axis, j.turn_a);
  }
  j.mass = k > Fixed{} ? Fixed::one() / k : Fixed{};
  return j;
}

}  // namespace

// The manifold's rows with body a (or b) immovable, made when first needed
// (the mover's inverse mass is still its own then: a body is frozen only
// after its level).
void make_one_sided(ManifoldRow& m, std::vector<PointRow>& rows, const SolverBody& a, const SolverBody& b,
                    bool freeze_a) {
  for (size_t k = 0; k < m.count; ++k) rows[m.first + k].normal = frozen(rows[m.first + k].normal, a, b, freeze_a);
  m.normal = frozen(m.normal, a, b, freeze_a);
  m.tangent[0] = frozen(m.tangent[0], a, b, freeze_a);
  m.tangent[1] = frozen(m.tangent[1], a, b, freeze_a);
  m.twist = frozen(m.twist, freeze_a);
  for (AngularPart& row : m.rolling) row = frozen(row, freeze_a);
  for (ManifoldRow::Rocking& r : m.rocking) r.row = frozen(r.row, freeze_a);
  m.one_sided = true;
}

namespace {

// glue's asks past the range (a 1e5 kg box glued to a 10 g die thrown at
// 500 m/s, or spinning on it) cannot be delivered by the face, and the rows
// take them one by one. Decided from bit lengths, cheaply (glue runs in
// every shock pass): `bits` of a value x is the least e with |x| < 2^e, so
// a product of values of e_a and e_b bits is below 2^(e_a + e_b).
int bits(uint64_t raw_magnitudes) { return static_cast<int>(std::bit_width(raw_magnitudes)) - raw::fraction_bits; }
uint64_t magnitude_of(Fixed x) { return magnitude(x.raw()); }
int bits(Fixed x) { return bits(magnitude_of(x)); }
int bits(Vec3 v) { return bits(magnitude_of(v.x) | magnitude_of(v.y) | magnitude_of(v.z)); }
int bits(Fixed a, Fixed b) { return bits(magnitude_of(a) | magnitude_of(b)); }
int bits(const Mat33& m) {
  uint64_t all = 0;
  for (const Vec3& row : m.rows) all |= magnitude_of(row.x) | magnitude_of(row.y) | magnitude_of(row.z);
  return bits(all);
}

// |v| > limit, without the square root where |x| + |y| + |z| <= limit:
// the correctly rounded length of v is at most that sum, which is exact
// (a wrap of it faults in the checked build; the envelope keeps impulses
// far below 2^31).
bool longer_than(Vec3 v, Fixed limit) {
  if (abs(v.x) + abs(v.y) + abs(v.z) <= limit) return false;
  return length(v) > limit;
}

// glue's face: a face contact (3 or more points, both rocking rows) with no
// row asking the surfaces apart (a bounce or a bias; a speculative gap's
// allowed approach is met by moving together), its centroid, its points'
// levers and the rocking axes' Gram matrix.
void measure_face(const ManifoldRow& m, const std::vector<PointRow>& rows, GlueFace& face, GlueFaces& faces) {
  face.state = GlueFace::State::never;
  // A face slot serves another contact in another step: what glue kept of
  // the last one (a target from other offsets) is not this one's.
  face.has_target = face.has_mass = false;
  if (m.count < 3 || !m.rocking[0].active || !m.rocking[1].active) return;
  for (size_t i = 0; i < m.count; ++i) {
    if (rows[m.first + i].velocity_target > Fixed{}) return;
  }
  const Vec3 n = m.manifold->normal;
  Vec3 centroid;
  for (size_t i = 0; i < m.count; ++i) centroid += rows[m.first + i].point->position;
  centroid = centroid / Fixed::from_int(static_cast<int32_t>(m.count));
  const Vec3 u0 = m.rocking[0].row.axis, u1 = m.rocking[1].row.axis;
  face.g00 = dot(u0, u0);
  face.g01 = dot(u0, u1);
  face.g11 = dot(u1, u1);
  const Fixed det = face.g00 * face.g11 - face.g01 * face.g01;
  if (det < 0.000001_fx) return;
  face.inverse_det = Fixed::one() / det;
  face.gram_bits = static_cast<int8_t>(bits(Vec3{face.g00, face.g01, face.g11}));
  face.inverse_det_bits = static_cast<int8_t>(bits(face.inverse_det));
  uint64_t alphas = 0;
  for (size_t i = 0; i < m.count; ++i) alphas |= magnitude_of(m.rocking[0].alpha[i]) | magnitude_of(m.rocking[1].alpha[i]);
  face.alpha_bits = static_cast<int8_t>(bits(alphas));
  face.n = n;
  face.centroid = centroid;
  face.first_point = faces.take_points(m.count);
  for (size_t i = 0; i < m.count; ++i) {
    faces.points[face.first_point + i] = {cross(rows[m.first + i].point->position - centroid, n), {}, {}};
  }
  face.state = GlueFace::State::usable;
}

}  // namespace

// In the shock step a face contact (3 or 4 points) of body `mover` against an
// immovable support is solved as one block: the impulse that glues the body
// to the support (relative velocity zero in all six directions: w = w_s and
// the centroids moving together) is taken whole when the contact can deliver
// it: every point still pushes, friction and twist stay inside the static
// cone, and no row asks the surfaces apart. Otherwise (false) the rows are
// left to the one-by-one pass. Solving the block removes the coupling
// between friction at the face and the body's rocking that row-by-row
// passes leave as a slow sideways creep.
bool glue(SolverBody& mover, const SolverBody& support, const Body& body, bool mover_is_b, const ManifoldRow& m,
          std::vector<PointRow>& rows, GlueFace& face, GlueFaces& faces) {
  if (!faces.measured(face)) measure_face(m, rows, face, faces);
  if (face.state == GlueFace::State::never) return false;
  const Vec3 r_mover = mover_is_b ? m.offset_b : m.offset_a;
  const Vec3 r_support = mover_is_b ? m.offset_a : m.offset_b;
  // Target rates: the support's rigid motion continued to the mover. A
  // face glues one mover to one support at the row's offsets, and the
  // support stays frozen through the passes: the target is taken again
  // while the support's velocity keeps its bits, and so is the mover's
  // mass while its inverse does (the same values, so the same bits).
  const Vec3 w = support.velocity.angular;
  if (!face.has_target || !(face.support_linear == support.velocity.linear) || !(face.support_angular == w)) {
    face.target_linear = support.velocity.linear + cross(w, r_support) - cross(w, r_mover);
    face.support_linear = support.velocity.linear;
    face.support_angular = w;
    face.has_target = true;
  }
  if (!face.has_mass || !(face.inverse_mass == mover.inverse_mass)) {
    face.mass = Fixed::one() / mover.inverse_mass;
    face.inverse_mass = mover.inverse_mass;
    face.has_mass = true;
  }
  const Vec3 v = face.target_linear;
  const Vec3 dv = v - mover.velocity.linear, dw = w - mover.velocity.angular;
  // Impulse P through the centroid and angular impulse L about it:
  // m dv = P, I dw = r x P + L (I in world axes, applied through the body frame).
  const Fixed mass = face.mass;
  // m dv below 2^29; I dw (three products below 2^27, rotated: under
  // 0.65 2^30) less r x P (two products below 2^29): under 2^31. A body at
  // the world's clamps has m R <= 5.4e5 kg m < 2^20 and I <= m R^2 <= 2.7e6
  // kg m^2 < 2^22 (speed_limits), so dv under 2^9 m/s and dw under 2^5
  // rad/s need no further look (r lies within R of the centre).
  const int dv_bits = bits(dv), dw_bits = bits(dw);
  const bool within_clamps =
      body.limits.linear == envelope::max_linear_speed && body.limits.angular == envelope::max_angular_speed;
  if (!(within_clamps && dv_bits <= 9 && dw_bits <= 5)) {
    if (dv_bits + bits(mass) > 29 || bits(body.inertia_local) + dw_bits > 27) return false;
    if (bits(r_mover) + bits(mass) + dv_bits > 29) return false;  // r x P with P = m dv
  }
  const Vec3 impulse = dv * mass;
  const Quat q = body.pose.orientation;
  const Vec3 angular = rotate(q, body.inertia_local * rotate_inverse(q, dw)) - cross(r_mover, impulse);
  // In the rows' terms (an impulse lambda acts +d on b, -d on a).
  const Manifold& manifold = *m.manifold;
  const Vec3 n = face.n;
  const Vec3 p = mover_is_b ? impulse : -impulse;
  const Vec3 l = mover_is_b ? angular : -angular;
  const Fixed normal = dot(p, n);
  const Fixed friction0 = manifold.friction_impulse[0] + dot(p, m.tangent[0].direction);
  const Fixed friction1 = manifold.friction_impulse[1] + dot(p, m.tangent[1].direction);
  const Fixed twist = manifold.twist_impulse + dot(l, n);
  // The contact's whole impulse this step (the iterations' plus the glue's)
  // as a fresh point distribution: the total normal impulse shared equally
  // plus the rocking distributions that give its in-plane moment about the
  // centroid, lambda0 u0 + lambda1 u1 (a 2 x 2 solve by Cramer's rule). It
  // must push at every point. Rebuilding it drops whatever the iterations
  // left in the modes that move nothing (a 4-point face is statically
  // indeterminate), which would otherwise decide whether the glue holds.
  Fixed total = normal;
  Vec3 moment = l - n * dot(l, n);
  for (size_t i = 0; i < m.count; ++i) {
    const Fixed jn = rows[m.first + i].point->normal_impulse;
    total += jn;
    moment += faces.points[face.first_point + i].lever * jn;
  }
  // A face too small for the moment it must carry asks point impulses past
  // the range (a 1e5 kg box spinning on a 1 cm die).
  const Vec3 u0 = m.rocking[0].row.axis, u1 = m.rocking[1].row.axis;
  const Fixed b0 = dot(u0, moment), b1 = dot(u1, moment);
  if (bits(b0, b1) + face.gram_bits > 29) return false;
  const Fixed n0 = b0 * face.g11 - b1 * face.g01, n1 = b1 * face.g00 - b0 * face.g01;
  if (bits(n0, n1) + face.inverse_det_bits > 29) return false;
  const Fixed lambda0 = n0 * face.inverse_det, lambda1 = n1 * face.inverse_det;
  if (bits(lambda0, lambda1) + face.alpha_bits > 29) return false;
  const Fixed share = total / Fixed::from_int(static_cast<int32_t>(m.count));
  Fixed point_impulse[max_manifold_points];
  for (size_t i = 0; i < m.count; ++i) {
    point_impulse[i] = share + lambda0 * m.rocking[0].alpha[i] + lambda1 * m.rocking[1].alpha[i];
    if (point_impulse[i] < Fixed{}) return false;
  }
  const Fixed cone = m.static_friction * total;  // the static cone's radius, for friction and twist
  if (longer_than(Vec3{friction0, friction1, Fixed{}}, cone)) return false;
  if (abs(twist) > cone * m.twist_radius) return false;
  for (size_t i = 0; i < m.count; ++i) rows[m.first + i].point->normal_impulse = point_impulse[i];
  m.manifold->friction_impulse[0] = friction0;
  m.manifold->friction_impulse[1] = friction1;
  m.manifold->twist_impulse = twist;
  mover.velocity = {v, w};
  return true;
}

namespace {

// A support contact's row (its index in the solve named) and which way its
// normal points, as GlueFaces::entry_rows keeps them.
uint64_t entry_row(uint32_t row, const ManifoldRow& m, const std::vector<uint32_t>& level) {
  return uint64_t{row} * 2 + (level[m.a] < level[m.b] ? 1 : 0);
}

// glue_all's face: every support contact resting (no row asking the
// surfaces apart), facing the same way (normals within a quarter of a
// degree), three points or more not on a line; their centroid, levers and
// mean distance from it, each contact's middle, the face's axes and the
// least-squares matrix of the points' arms.
void measure_faces(const uint32_t* entries, size_t entry_count, const std::vector<uint32_t>& level,
                   const std::vector<ManifoldRow*>& manifolds, const std::vector<PointRow>& rows, GlueFace& face,
                   GlueFaces& faces) {
  constexpr Fixed same_normal = 0.99999_fx;  // cosine
  face.state = GlueFace::State::never;
  Vec3 n, centroid;
  Fixed mu = Fixed::max();
  int32_t point_count = 0;
  for (size_t e = 0; e < entry_count; ++e) {
    const ManifoldRow& m = *manifolds[entries[e]];
    const Vec3 up = level[m.a] < level[m.b] ? m.manifold->normal : -m.manifold->normal;
    for (size_t i = 0; i < m.count; ++i) {
      if (rows[m.first + i].velocity_target > Fixed{}) return;  // only resting contacts
      centroid += rows[m.first + i].point->position;
    }
    point_count += static_cast<int32_t>(m.count);
    if (e == 0) {
      n = up;
    } else if (dot(up, n) < same_normal) {
      return;
    }
    mu = min(mu, m.static_friction);
  }
  if (point_count < 3) return;
  centroid = centroid / Fixed::from_int(point_count);
  face.first_point = faces.take_points(static_cast<size_t>(point_count));
  face.first_middle = faces.take_middles(entry_count);
  face.entry_count = static_cast<uint32_t>(entry_count);
  Fixed radius;
  size_t k = face.first_point;
  for (size_t e = 0; e < entry_count; ++e) {
    const ManifoldRow& m = *manifolds[entries[e]];
    Vec3 middle;
    for (size_t i = 0; i < m.count; ++i, ++k) {
      const Vec3 position = rows[m.first + i].point->position;
      faces.points[k] = {cross(position - centroid, n), {}, {}};
      radius += length(position - centroid);
      middle += position;
    }
    faces.middles[face.first_middle + e] = middle / Fixed::from_int(static_cast<int32_t>(m.count));
    faces.entry_rows[face.first_middle + e] = entry_row(m.index, m, level);
  }
  radius = radius / Fixed::from_int(point_count);
  // The arms are measured in units of the points' mean distance from c, so
  // G stays near the point count whatever the size of the face.
  if (radius < 0.0001_fx) return;
  const Fixed inverse_radius = Fixed::one() / radius;
  const Vec3 axis = abs(n.x) < 0.57735_fx ? Vec3{Fixed::one(), {}, {}} : Vec3{{}, Fixed::one(), {}};
  const Vec3 e0 = normalize(cross(n, axis));
  const Vec3 e1 = cross(n, e0);
  Fixed g00, g01, g11;
  k = face.first_point;
  for (size_t e = 0; e < entry_count; ++e) {
    const ManifoldRow& m = *manifolds[entries[e]];
    for (size_t i = 0; i < m.count; ++i, ++k) {
      const Vec3 a = cross((rows[m.first + i].point->position - centroid) * inverse_radius, n);
      faces.points[k].a0 = dot(a, e0);
      faces.points[k].a1 = dot(a, e1);
      g00 += faces.points[k].a0 * faces.points[k].a0;
      g01 += faces.points[k].a0 * faces.points[k].a1;
      g11 += faces.points[k].a1 * faces.points[k].a1;
    }
  }
  const Fixed det = g00 * g11 - g01 * g01;
  if (det < 0.0001_fx) return;  // the points lie on a line
  face.n = n;
  face.centroid = centroid;
  face.e0 = e0;
  face.e1 = e1;
  face.mu = mu;
  face.radius = radius;
  face.inverse_radius = inverse_radius;
  face.g00 = g00;
  face.g01 = g01;
  face.g11 = g11;
  face.inverse_det = Fixed::one() / det;
  face.point_count = point_count;
  face.state = GlueFace::State::usable;
}

// The body's face of the last shock step, taken again where it lies
// (GlueFaces::face_at keeps it) when measure_faces would find it again.
// Exact: measure_faces reads only the support contacts (their number and
// order), each one's up normal, point count, point positions in row order,
// static friction, and whether a row asks the surfaces apart. A contact
// whose ManifoldRow::reused_from is the row that last step's face was
// measured from (entry_rows) has, by the row cache (row_cache.h: key,
// normal, points in row order and touching count compared word for word,
// both bodies' friction too, so its static friction is that row's), the
// same normal, count, positions and friction; the same row and the same
// level order give the same up. GlueFaces::recall makes sure last step's
// rows are those this step's were reused from (the shock step runs in the
// solve that built its rows, so its faces read what the cache compared).
// A usable face was measured with no row asking apart, so only that is
// checked again here.
bool recall_faces(const uint32_t* entries, size_t entry_count, const std::vector<uint32_t>& level,
                  const std::vector<ManifoldRow*>& manifolds, const std::vector<PointRow>& rows, GlueFace& face,
                  GlueFaces& faces) {
  // Its points and middles lie past what this step has handed out: not
  // written over this step.
  if (face.first_point != faces.points_used || face.first_middle != faces.middles_used ||
      face.entry_count != entry_count) {
    return false;
  }
  for (size_t e = 0; e < entry_count; ++e) {
    const ManifoldRow& m = *manifolds[entries[e]];
    if (m.reused_from == ManifoldRow::none) return false;
    if (faces.entry_rows[face.first_middle + e] != entry_row(m.reused_from, m, level)) return false;
    for (size_t i = 0; i < m.count; ++i) {
      if (rows[m.first + i].velocity_target > Fixed{}) return false;
    }
  }
  // Taken again: the same places, this step's rows named for the next.
  faces.take_points(static_cast<size_t>(face.point_count));
  faces.take_middles(entry_count);
  for (size_t e = 0; e < entry_count; ++e) {
    const ManifoldRow& m = *manifolds[entries[e]];
    faces.entry_rows[face.first_middle + e] = entry_row(m.index, m, level);
  }
  face.state = GlueFace::State::usable;
  return true;
}

// What glue_all reads of the supports: the manifolds (entries into
// manifolds) and the ranks that say which side of each is the support.
struct SupportSet {
  const uint32_t* entries;
  size_t count;
  const std::vector<uint32_t>& level;
  const std::vector<ManifoldRow*>& manifolds;
  const ManifoldRow& operator[](size_t e) const { return *manifolds[entries[e]]; }
  bool a_supports(const ManifoldRow& m) const { return level[m.a] < level[m.b]; }
};

// The supports' rigid motion continued to the mover's centre of mass, if
// they share one (within same_motion).
bool common_motion(const SupportSet& supports, const std::vector<SolverBody>& solver_bodies,
                   const std::vector<Body>& bodies, Vec3 position, BodyRates& out) {
  constexpr Fixed same_motion = 0.000001_fx;  // m/s and rad/s
  Vec3 v, w;
  for (size_t e = 0; e < supports.count; ++e) {
    const ManifoldRow& m = supports[e];
    const uint32_t support = supports.a_supports(m) ? m.a : m.b;
    const SolverBody& s = solver_bodies[support];
    const Vec3 w_s = s.velocity.angular;
    const Vec3 v_s = s.velocity.linear + cross(w_s, position - bodies[support].pose.position);
    if (e == 0) {
      v = v_s;
      w = w_s;
    } else {
      const Vec3 dv = v_s - v, dw = w_s - w;
      if (max(max(abs(dv.x), abs(dv.y)), abs(dv.z)) > same_motion) return false;
      if (max(max(abs(dw.x), abs(dw.y)), abs(dw.z)) > same_motion) return false;
    }
  }
  out = {v, w};
  return true;
}

// The whole impulse on the mover (the iterations' plus the glue's):
// normal, tangential, twist about n at the centroid and the normal
// impulses' in-plane moment about it.
struct WholeImpulse {
  Fixed total;
  Vec3 tangential;
  Fixed twist;
  Vec3 moment;
};

WholeImpulse whole_impulse(const SupportSet& supports, const std::vector<PointRow>& rows, const GlueFace& face,
                           const GlueFaces& faces, Vec3 impulse, Vec3 angular) {
  const Vec3 n = face.n, centroid = face.centroid;
  WholeImpulse whole;
  whole.total = dot(impulse, n);
  whole.tangential = impulse - n * whole.total;
  whole.twist = dot(angular, n);
  whole.moment = angular - n * whole.twist;
  size_t k = face.first_point;
  for (size_t e = 0; e < supports.count; ++e) {
    const ManifoldRow& m = supports[e];
    const Manifold& manifold = *m.manifold;
    for (size_t i = 0; i < m.count; ++i, ++k) {
      const Fixed jn = rows[m.first + i].point->normal_impulse;
      whole.total += jn;
      whole.moment += faces.points[k].lever * jn;
    }
    // An impulse lambda along a row acts +d on b, -d on a; the twist row's
    // impulse is the same about the mover's up either way.
    Vec3 friction = m.tangent[0].direction * manifold.friction_impulse[0] +
                    m.tangent[1].direction * manifold.friction_impulse[1];
    if (!supports.a_supports(m)) friction = -friction;
    whole.tangential += friction;
    whole.twist += manifold.twist_impulse + dot(cross(faces.middles[face.first_middle + e] - centroid, friction), n);
  }
  return whole;
}

// Held: the points take their shares (point_share(k) for the face's k-th
// point); each contact the friction in proportion to its normal impulse,
// and the twist that keeps the total.
template <class PointShare>
void share_impulse(const SupportSet& supports, std::vector<PointRow>& rows, const GlueFace& face,
                   const GlueFaces& faces, const WholeImpulse& whole, PointShare point_share) {
  const Vec3 n = face.n, centroid = face.centroid;
  size_t k = face.first_point;
  for (size_t e = 0; e < supports.count; ++e) {
    const ManifoldRow& m = supports[e];
    Manifold& manifold = *m.manifold;
    Fixed normal;
    for (size_t i = 0; i < m.count; ++i, ++k) {
      ContactPoint& point = *rows[m.first + i].point;
      point.normal_impulse = point_share(k);
      normal += point.normal_impulse;
    }
    const Fixed part = normal / whole.total;
    const Vec3 friction = whole.tangential * part;
    const Vec3 along = supports.a_supports(m) ? friction : -friction;
    manifold.friction_impulse[0] = dot(along, m.tangent[0].direction);
    manifold.friction_impulse[1] = dot(along, m.tangent[1].direction);
    manifold.twist_impulse =
        whole.twist * part - dot(cross(faces.middles[face.first_middle + e] - centroid, friction), n);
  }
}

}  // namespace

// A body held up by several supports is glued to all of them at once when
// they share one rigid motion (within 1 um/s and 1 urad/s: a wall's bricks
// glued to the ground) and their contacts face the same way (normals within
// a quarter of a degree): the contacts are taken as one face, as if the
// supports were one body. Its whole impulse (the iterations' plus the
// glue's) is rebuilt as a fresh distribution over all the points, which
// must push at every one, with the friction cone over the sum of the
// contacts' normal impulses and the twist cone over the points' mean
// distance from their common centroid. Glued one contact at a time, a
// running-bond brick had to be held by each half of its base alone (its
// load's centre lies on the edge between them). The friction found is
// shared by the contacts in proportion to their normal impulses.
GlueAll glue_all(SolverBody& mover, const Body& body, const std::vector<SolverBody>& solver_bodies,
              const std::vector<Body>& bodies, const uint32_t* entries, size_t entry_count,
              const std::vector<uint32_t>& level, const std::vector<ManifoldRow*>& manifolds,
              std::vector<PointRow>& rows, GlueFace& face, GlueFaces& faces) {
  if (!faces.measured(face) &&
      !(face.recallable && recall_faces(entries, entry_count, level, manifolds, rows, face, faces))) {
    measure_faces(entries, entry_count, level, manifolds, rows, face, faces);
  }
  if (face.state == GlueFace::State::never) return GlueAll::refused;
  const SupportSet supports{entries, entry_count, level, manifolds};
  const Vec3 position = body.pose.position;
  BodyRates motion;
  if (!common_motion(supports, solver_bodies, bodies, position, motion)) return GlueAll::supports_part;
  const Vec3 v = motion.linear, w = motion.angular;
  // The glue's impulse on the mover: P through the centroid and an angular
  // impulse L about it (m dv = P, I dw = r x P + L), as in glue().
  const Vec3 r_mover = face.centroid - position;
  const Vec3 impulse = (v - mover.velocity.linear) * (Fixed::one() / mover.inverse_mass);
  const Quat q = body.pose.orientation;
  const Vec3 angular =
      rotate(q, body.inertia_local * rotate_inverse(q, w - mover.velocity.angular)) - cross(r_mover, impulse);
  const WholeImpulse whole = whole_impulse(supports, rows, face, faces, impulse, angular);
  if (whole.total <= Fixed{}) return GlueAll::refused;
  const Fixed cone = face.mu * whole.total;  // the static cone's radius, for friction and twist
  if (longer_than(whole.tangential, cone)) return GlueAll::refused;
  if (abs(whole.twist) > cone * face.radius) return GlueAll::refused;
  // The fresh distribution pi_i = total / k + beta . a_i, a_i = (p_i - c) x n
  // in the face's plane (e0, e1), with G beta = moment: the least-squares
  // spread of the points' impulses that gives the moment (sum a_i = 0).
  const Fixed b0 = dot(whole.moment, face.e0) * face.inverse_radius;
  const Fixed b1 = dot(whole.moment, face.e1) * face.inverse_radius;
  const Fixed beta0 = (b0 * face.g11 - b1 * face.g01) * face.inverse_det;
  const Fixed beta1 = (b1 * face.g00 - b0 * face.g01) * face.inverse_det;
  const Fixed share = whole.total / Fixed::from_int(face.point_count);
  const auto point_share = [&](size_t point) {
    return share + beta0 * faces.points[point].a0 + beta1 * faces.points[point].a1;
  };
  for (size_t p = face.first_point; p < face.first_point + static_cast<size_t>(face.point_count); ++p) {
    if (point_share(p) < Fixed{}) return GlueAll::refused;
  }
  share_impulse(supports, rows, face, faces, whole, point_share);
  mover.velocity = {v, w};
  return GlueAll::glued;
}

}  // namespace bitstep
