#include "core/shock.h"

#include <algorithm>

#include "core/shock_levels.h"

namespace bitstep {

namespace {

// A rank whose touching points the iterations left approaching no faster
// than this is held already (see the end of propagate_shock), m/s.
constexpr Fixed quiet_approach = 0.001_fx;

// A copy of j with body a (or b) immovable: its turn is dropped and the
// effective mass is the other body's alone.
Jacobian frozen(Jacobian j, const SolverBody& a, const SolverBody& b, bool freeze_a) {
  const bool linear = j.direction != Vec3{};
  Fixed k;
  if (freeze_a) {
    j.turn_a = Vec3{};
    k = (linear ? b.inverse_mass : Fixed{}) + dot(j.arm_b, j.turn_b);
  } else {
    j.turn_b = Vec3{};
    k = (linear ? a.inverse_mass : Fixed{}) + dot(j.arm_a, j.turn_a);
  }
  j.mass = k > Fixed{} ? Fixed::one() / k : Fixed{};
  return j;
}

// The manifold's rows with body a (or b) immovable, made when first needed
// (the mover's inverse mass is still its own then: a body is frozen only
// after its level).
void make_one_sided(ManifoldRow& m, std::vector<PointRow>& rows, const SolverBody& a, const SolverBody& b,
                    bool freeze_a) {
  for (size_t k = 0; k < m.count; ++k) rows[m.first + k].normal = frozen(rows[m.first + k].normal, a, b, freeze_a);
  m.normal = frozen(m.normal, a, b, freeze_a);
  m.tangent[0] = frozen(m.tangent[0], a, b, freeze_a);
  m.tangent[1] = frozen(m.tangent[1], a, b, freeze_a);
  m.twist = frozen(m.twist, a, b, freeze_a);
  for (Jacobian& row : m.rolling) row = frozen(row, a, b, freeze_a);
  for (ManifoldRow::Rocking& r : m.rocking) r.row = frozen(r.row, a, b, freeze_a);
  m.one_sided = true;
}

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
          std::vector<PointRow>& rows) {
  if (m.count < 3 || !m.rocking[0].active || !m.rocking[1].active) return false;
  // Only a resting contact: no bounce or bias asks the surfaces apart (a
  // speculative gap's allowed approach is met by moving together).
  for (size_t i = 0; i < m.count; ++i) {
    if (rows[m.first + i].velocity_target > Fixed{}) return false;
  }
  const Vec3 r_mover = mover_is_b ? m.offset_b : m.offset_a;
  const Vec3 r_support = mover_is_b ? m.offset_a : m.offset_b;
  // Target rates: the support's rigid motion continued to the mover.
  const Vec3 w = support.velocity.angular;
  const Vec3 v = support.velocity.linear + cross(w, r_support) - cross(w, r_mover);
  const Vec3 dv = v - mover.velocity.linear, dw = w - mover.velocity.angular;
  // Impulse P through the centroid and angular impulse L about it:
  // m dv = P, I dw = r x P + L (I in world axes, applied through the body frame).
  const Vec3 impulse = dv * (Fixed::one() / mover.inverse_mass);
  const Quat q = body.pose.orientation;
  const Vec3 angular = rotate(q, body.inertia_local * rotate_inverse(q, dw)) - cross(r_mover, impulse);
  // In the rows' terms (an impulse lambda acts +d on b, -d on a).
  const Manifold& manifold = *m.manifold;
  const Vec3 n = manifold.normal;
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
  Vec3 centroid;
  for (size_t i = 0; i < m.count; ++i) centroid += rows[m.first + i].point->position;
  centroid = centroid / Fixed::from_int(static_cast<int32_t>(m.count));
  Fixed total = normal;
  Vec3 moment = l - n * dot(l, n);
  for (size_t i = 0; i < m.count; ++i) {
    const ContactPoint& point = *rows[m.first + i].point;
    total += point.normal_impulse;
    moment += cross(point.position - centroid, n) * point.normal_impulse;
  }
  const Vec3 u0 = m.rocking[0].row.arm_b, u1 = m.rocking[1].row.arm_b;
  const Fixed g00 = dot(u0, u0), g01 = dot(u0, u1), g11 = dot(u1, u1);
  const Fixed det = g00 * g11 - g01 * g01;
  if (det < 0.000001_fx) return false;
  const Fixed b0 = dot(u0, moment), b1 = dot(u1, moment);
  const Fixed inverse_det = Fixed::one() / det;
  const Fixed lambda0 = (b0 * g11 - b1 * g01) * inverse_det, lambda1 = (b1 * g00 - b0 * g01) * inverse_det;
  const Fixed share = total / Fixed::from_int(static_cast<int32_t>(m.count));
  Fixed point_impulse[max_manifold_points];
  for (size_t i = 0; i < m.count; ++i) {
    point_impulse[i] = share + lambda0 * m.rocking[0].alpha[i] + lambda1 * m.rocking[1].alpha[i];
    if (point_impulse[i] < Fixed{}) return false;
  }
  if (length(Vec3{friction0, friction1, Fixed{}}) > m.static_friction * total) return false;
  if (abs(twist) > m.static_friction * total * m.twist_radius) return false;
  for (size_t i = 0; i < m.count; ++i) rows[m.first + i].point->normal_impulse = point_impulse[i];
  m.manifold->friction_impulse[0] = friction0;
  m.manifold->friction_impulse[1] = friction1;
  m.manifold->twist_impulse = twist;
  mover.velocity = {v, w};
  return true;
}


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
bool glue_all(SolverBody& mover, const Body& body, const std::vector<SolverBody>& solver_bodies,
              const std::vector<Body>& bodies, const uint32_t* entries, size_t entry_count,
              const std::vector<uint32_t>& level, std::vector<ManifoldRow>& manifolds, std::vector<PointRow>& rows) {
  constexpr Fixed same_motion = 0.000001_fx;  // m/s and rad/s
  constexpr Fixed same_normal = 0.99999_fx;   // cosine
  const Vec3 position = body.pose.position;
  Vec3 n, v, w, centroid;
  Fixed mu = Fixed::max();
  int32_t point_count = 0;
  for (size_t e = 0; e < entry_count; ++e) {
    const ManifoldRow& m = manifolds[entries[e]];
    const bool mover_is_b = level[m.a] < level[m.b];
    const uint32_t support = mover_is_b ? m.a : m.b;
    const Vec3 up = mover_is_b ? m.manifold->normal : -m.manifold->normal;
    for (size_t i = 0; i < m.count; ++i) {
      if (rows[m.first + i].velocity_target > Fixed{}) return false;  // only resting contacts
      centroid += rows[m.first + i].point->position;
    }
    point_count += static_cast<int32_t>(m.count);
    // The support's rigid motion continued to the mover's centre of mass.
    const SolverBody& s = solver_bodies[support];
    const Vec3 w_s = s.velocity.angular;
    const Vec3 v_s = s.velocity.linear + cross(w_s, position - bodies[support].pose.position);
    if (e == 0) {
      n = up;
      v = v_s;
      w = w_s;
    } else {
      if (dot(up, n) < same_normal) return false;
      const Vec3 dv = v_s - v, dw = w_s - w;
      if (max(max(abs(dv.x), abs(dv.y)), abs(dv.z)) > same_motion) return false;
      if (max(max(abs(dw.x), abs(dw.y)), abs(dw.z)) > same_motion) return false;
    }
    mu = min(mu, m.static_friction);
  }
  if (point_count < 3) return false;
  centroid = centroid / Fixed::from_int(point_count);
  // The glue's impulse on the mover: P through the centroid and an angular
  // impulse L about it (m dv = P, I dw = r x P + L), as in glue().
  const Vec3 r_mover = centroid - position;
  const Vec3 impulse = (v - mover.velocity.linear) * (Fixed::one() / mover.inverse_mass);
  const Quat q = body.pose.orientation;
  const Vec3 angular =
      rotate(q, body.inertia_local * rotate_inverse(q, w - mover.velocity.angular)) - cross(r_mover, impulse);
  // The whole impulse on the mover: normal, tangential, twist about n at the
  // centroid and the normal impulses' in-plane moment about it.
  Fixed total = dot(impulse, n);
  Vec3 tangential = impulse - n * total;
  Fixed twist = dot(angular, n);
  Vec3 moment = angular - n * twist;
  Fixed radius;
  for (size_t e = 0; e < entry_count; ++e) {
    const ManifoldRow& m = manifolds[entries[e]];
    const Manifold& manifold = *m.manifold;
    Vec3 middle;
    for (size_t i = 0; i < m.count; ++i) {
      const ContactPoint& point = *rows[m.first + i].point;
      total += point.normal_impulse;
      moment += cross(point.position - centroid, n) * point.normal_impulse;
      radius += length(point.position - centroid);
      middle += point.position;
    }
    middle = middle / Fixed::from_int(static_cast<int32_t>(m.count));
    // An impulse lambda along a row acts +d on b, -d on a; the twist row's
    // impulse is the same about the mover's up either way.
    Vec3 friction = m.tangent[0].direction * manifold.friction_impulse[0] +
                    m.tangent[1].direction * manifold.friction_impulse[1];
    if (!(level[m.a] < level[m.b])) friction = -friction;
    tangential += friction;
    twist += manifold.twist_impulse + dot(cross(middle - centroid, friction), n);
  }
  radius = radius / Fixed::from_int(point_count);
  if (total <= Fixed{}) return false;
  if (length(tangential) > mu * total) return false;
  if (abs(twist) > mu * total * radius) return false;
  // The fresh distribution pi_i = total / k + beta . a_i, a_i = (p_i - c) x n
  // in the face's plane (e0, e1), with G beta = moment: the least-squares
  // spread of the points' impulses that gives the moment (sum a_i = 0). The
  // arms are measured in units of the points' mean distance from c, so G
  // stays near the point count whatever the size of the face.
  if (radius < 0.0001_fx) return false;
  const Fixed inverse_radius = Fixed::one() / radius;
  const Vec3 axis = abs(n.x) < 0.57735_fx ? Vec3{Fixed::one(), {}, {}} : Vec3{{}, Fixed::one(), {}};
  const Vec3 e0 = normalize(cross(n, axis));
  const Vec3 e1 = cross(n, e0);
  const auto arm = [&](const ContactPoint& point) { return cross((point.position - centroid) * inverse_radius, n); };
  Fixed g00, g01, g11;
  for (size_t e = 0; e < entry_count; ++e) {
    const ManifoldRow& m = manifolds[entries[e]];
    for (size_t i = 0; i < m.count; ++i) {
      const Vec3 a = arm(*rows[m.first + i].point);
      const Fixed a0 = dot(a, e0), a1 = dot(a, e1);
      g00 += a0 * a0;
      g01 += a0 * a1;
      g11 += a1 * a1;
    }
  }
  const Fixed det = g00 * g11 - g01 * g01;
  if (det < 0.0001_fx) return false;  // the points lie on a line
  const Fixed b0 = dot(moment, e0) * inverse_radius, b1 = dot(moment, e1) * inverse_radius;
  const Fixed inverse_det = Fixed::one() / det;
  const Fixed beta0 = (b0 * g11 - b1 * g01) * inverse_det, beta1 = (b1 * g00 - b0 * g01) * inverse_det;
  const Fixed share = total / Fixed::from_int(point_count);
  const auto point_share = [&](const ContactPoint& point) {
    const Vec3 a = arm(point);
    return share + beta0 * dot(a, e0) + beta1 * dot(a, e1);
  };
  for (size_t e = 0; e < entry_count; ++e) {
    const ManifoldRow& m = manifolds[entries[e]];
    for (size_t i = 0; i < m.count; ++i) {
      if (point_share(*rows[m.first + i].point) < Fixed{}) return false;
    }
  }
  // Held: the points take their shares; each contact the friction in
  // proportion to its normal impulse, and the twist that keeps the total.
  for (size_t e = 0; e < entry_count; ++e) {
    const ManifoldRow& m = manifolds[entries[e]];
    Manifold& manifold = *m.manifold;
    Fixed normal;
    Vec3 middle;
    for (size_t i = 0; i < m.count; ++i) {
      ContactPoint& point = *rows[m.first + i].point;
      point.normal_impulse = point_share(point);
      normal += point.normal_impulse;
      middle += point.position;
    }
    middle = middle / Fixed::from_int(static_cast<int32_t>(m.count));
    const Fixed part = normal / total;
    const Vec3 friction = tangential * part;
    const Vec3 along = level[m.a] < level[m.b] ? friction : -friction;
    manifold.friction_impulse[0] = dot(along, m.tangent[0].direction);
    manifold.friction_impulse[1] = dot(along, m.tangent[1].direction);
    manifold.twist_impulse = twist * part - dot(cross(middle - centroid, friction), n);
  }
  mover.velocity = {v, w};
  return true;
}

// Twice the kinetic energy per unit mass, J/kg: |v|^2 + w . (I / m) w.
// I / m is taken in the body frame, where it is at most about size^2, so
// with the envelope's speeds and sizes neither term nears the range.
Fixed energy_per_mass(const Body& body, const BodyRates& rates, Fixed inverse_mass) {
  const Vec3 w = rotate_inverse(body.pose.orientation, rates.angular);
  return dot(rates.linear, rates.linear) + dot(w, (body.inertia_local * inverse_mass) * w);
}

// Whether the iterations left some touching point of the rank approaching
// faster than `speed` (m/s), against the velocities of the ranks below as
// the shock step left them.
bool approaching(const std::vector<SolverBody>& solver_bodies, const std::vector<ManifoldRow>& manifolds,
                 const std::vector<PointRow>& rows, size_t begin, size_t end, Fixed speed) {
  for (size_t i = begin; i < end; ++i) {
    const ManifoldRow& m = manifolds[i];
    for (size_t k = 0; k < m.count; ++k) {
      const PointRow& row = rows[m.first + k];
      if (row.point->depth < -touch_tolerance) continue;
      if (relative_velocity(solver_bodies[m.a], solver_bodies[m.b], row.normal) < -speed) return true;
    }
  }
  return false;
}

}  // namespace

void propagate_shock(const Settings& settings, const std::vector<Body>& bodies, const std::vector<Contact>& contacts,
                     SolverScratch& scratch) {
  std::vector<SolverBody>& solver_bodies = scratch.bodies;
  const std::vector<PointRow>& rows = scratch.rows;
  const std::vector<ManifoldRow>& manifold_rows = scratch.manifolds;
  if (manifold_rows.empty()) return;  // nothing awake touches anything
  ShockLevels& levels = scratch.levels;
  shock_levels(bodies, contacts, settings.gravity, levels);
  const std::vector<uint32_t>& level = levels.rank;
  const std::vector<uint32_t>& height = levels.height;
  // Whether the lower-ranked body of a manifold between ranks holds the
  // other up (the normal points from a to b).
  const auto holds_up = [&](const ManifoldRow& m) {
    return is_support(level[m.a] < level[m.b] ? m.manifold->normal : -m.manifold->normal, settings.gravity);
  };
  // Manifolds between ranked bodies, by (rank of the higher body, order):
  // those within a rank (both bodies movable); between ranks, those
  // against an immovable body, those along a sideways chain within a
  // height, and those through which a lower height holds a higher one up.
  // Any other contact between heights (a tumbling body touching another
  // from below or the side) is left to the iterations: freezing the wrong
  // side would squeeze the body between two immovable ones.
  std::vector<ShockEntry>& order = scratch.order;
  order.clear();
  for (uint32_t i = 0; i < manifold_rows.size(); ++i) {
    const ManifoldRow& m = manifold_rows[i];
    if (level[m.a] == not_supported || level[m.b] == not_supported) continue;
    const bool between_heights = level[m.a] != 0 && level[m.b] != 0 && height[m.a] != height[m.b] &&
                                 height[m.a] != not_supported && height[m.b] != not_supported;
    const bool support = level[m.a] != level[m.b] && holds_up(m);
    const bool sideways = level[m.a] != level[m.b] && !between_heights && !support;
    if (between_heights && !support) continue;
    // The higher-ranked body holds the lower-ranked one up (a body leaning
    // on one ranked after it through another chain): freezing the lower
    // would press the other down from above. Left to the iterations.
    const Vec3 from_higher = level[m.a] < level[m.b] ? -m.manifold->normal : m.manifold->normal;
    const bool lower_rests_on_higher =
        level[m.a] != level[m.b] && !support && is_support(from_higher, settings.gravity);
    if (lower_rests_on_higher) continue;
    // Apart: a speculative contact, for the iterations (gluing it would
    // stop a falling body in the air), unless sideways, where it is solved
    // one-sided up to touching and no more.
    if (!sideways && !touches(*m.manifold)) continue;
    order.push_back({std::max(level[m.a], level[m.b]), i, support});
  }
  std::sort(order.begin(), order.end(),
            [](ShockEntry x, ShockEntry y) { return x.level != y.level ? x.level < y.level : x.index < y.index; });

  // Bodies held up through more than one contact (by several bodies, or by
  // several shapes of one: a table's four legs on the table below): glued
  // to all their supports at once (glue_all), else to one at a time. One neither glue can hold (its
  // supports move differently, or its load's centre lies outside each
  // contact alone) is left as the iterations left it: solved against each
  // support in turn, one-sided, it is driven toward whichever rises fastest
  // and, through the rotation that gives it, the bodies above it faster
  // still (that launched the top bricks of wall128 at 90 m/s). Sideways
  // contacts are not supports: a body pressed against a wall or a frozen
  // neighbour is solved against it one-sided.
  std::vector<uint32_t>& first_support = scratch.first_support;
  std::vector<uint8_t>& several_supports = scratch.several_supports;
  first_support.assign(bodies.size(), not_supported);
  several_supports.assign(bodies.size(), 0);
  for (const ShockEntry& e : order) {
    if (!e.holds_up) continue;
    const ManifoldRow& m = manifold_rows[e.index];
    const bool mover_is_b = level[m.a] < level[m.b];
    const uint32_t mover = mover_is_b ? m.b : m.a, support = mover_is_b ? m.a : m.b;
    if (first_support[mover] == not_supported) {
      first_support[mover] = support;
    } else {
      several_supports[mover] = 1;
    }
  }

  // Each body with several supports: its support manifolds (positions in
  // `order`), grouped by body (a counting sort: deterministic), in order.
  std::vector<uint32_t>& support_begin = scratch.support_begin;
  std::vector<uint32_t>& support_entries = scratch.support_entries;
  support_begin.assign(bodies.size() + 1, 0);
  const auto mover_of = [&](const ManifoldRow& m) { return level[m.a] < level[m.b] ? m.b : m.a; };
  for (const ShockEntry& e : order) {
    const uint32_t mover = mover_of(manifold_rows[e.index]);
    if (e.holds_up && several_supports[mover]) ++support_begin[mover + 1];
  }
  for (size_t i = 1; i < support_begin.size(); ++i) support_begin[i] += support_begin[i - 1];
  support_entries.resize(support_begin.back());
  std::vector<uint32_t>& fill = scratch.support_fill;
  fill.assign(support_begin.begin(), support_begin.end() - 1);
  for (uint32_t i = 0; i < order.size(); ++i) {
    const uint32_t mover = mover_of(manifold_rows[order[i].index]);
    if (order[i].holds_up && several_supports[mover]) support_entries[fill[mover]++] = i;
  }
  // Per body, whether it is glued to all its supports at once in this pass.
  std::vector<uint8_t>& glued_to_all = scratch.glued_to_all;
  std::vector<BodyRates>& glued_velocity = scratch.glued_velocity;  // read only where glued_to_all
  glued_to_all.assign(bodies.size(), 0);
  glued_velocity.resize(bodies.size());

  // Copies of the rows with the lower body's side frozen, accumulating into
  // copies of the manifolds: the shock step corrects this step's velocities
  // only, and next step warm-starts from what the iterations found (the
  // shock's one-sided impulses would push the supports down when applied to
  // both bodies).
  std::vector<PointRow>& shock_rows = scratch.shock_rows;
  std::vector<ManifoldRow>& shock_manifolds = scratch.shock_manifolds;
  std::vector<Manifold>& accumulated = scratch.accumulated;
  shock_rows.clear();
  shock_manifolds.clear();
  accumulated.resize(order.size());
  for (size_t i = 0; i < order.size(); ++i) {
    ManifoldRow m = manifold_rows[order[i].index];
    accumulated[i] = *m.manifold;
    m.manifold = &accumulated[i];
    const size_t first = shock_rows.size();
    for (size_t k = 0; k < m.count; ++k) {
      shock_rows.push_back(rows[m.first + k]);
      shock_rows.back().point = &accumulated[i].points[k];
    }
    m.first = first;
    shock_manifolds.push_back(m);
  }

  // Rank by rank; once a rank is done its bodies become immovable
  // (inverse mass 0; the frozen rows already carry no turn for them).
  std::vector<Fixed>& saved_inverse_mass = scratch.saved_inverse_mass;
  std::vector<uint32_t>& frozen_bodies = scratch.frozen_bodies;
  saved_inverse_mass.clear();
  frozen_bodies.clear();
  size_t begin = 0;
  while (begin < order.size()) {
    size_t end = begin;
    while (end < order.size() && order[end].level == order[begin].level) ++end;
    // The iterations' velocities of the rank's bodies (with duplicates), and
    // whether the rank has a sideways contact (a body pressed against one
    // ranked below it, not held up by it).
    std::vector<RankBody>& before_shock = scratch.rank_bodies;
    before_shock.clear();
    bool sideways = false;
    for (size_t i = begin; i < end; ++i) {
      const ManifoldRow& m = shock_manifolds[i];
      for (uint32_t body : {m.a, m.b}) {
        if (level[body] == order[begin].level) before_shock.push_back({body, solver_bodies[body].velocity});
      }
      sideways = sideways || (level[m.a] != level[m.b] && !order[i].holds_up);
    }
    const bool stirring_only =
        !sideways && !approaching(solver_bodies, shock_manifolds, shock_rows, begin, end, quiet_approach);
    // Passes over the rank until one changes no velocity (exactly: the
    // arithmetic is fixed point), at most shock_iterations.
    bool converged = false;
    for (int pass = 0; pass < settings.shock_iterations && !converged; ++pass) {
      bool changed = false;
      for (size_t i = begin; i < end; ++i) {
        ManifoldRow& m = shock_manifolds[i];
        const BodyRates before_a = solver_bodies[m.a].velocity, before_b = solver_bodies[m.b].velocity;
        if (level[m.a] != level[m.b]) {
          const bool mover_is_b = level[m.a] < level[m.b];
          const uint32_t mover = mover_is_b ? m.b : m.a;
          if (order[i].holds_up) {
            const BodyRates before = mover_is_b ? before_b : before_a;
            if (several_supports[mover]) {
              // Glued to all its supports at once at its first support manifold.
              const uint32_t* list = &support_entries[support_begin[mover]];
              const size_t count = support_begin[mover + 1] - support_begin[mover];
              // Glued in the last pass and not moved since: its supports are
              // frozen, so the glue would find the same again.
              if (list[0] == i && !(glued_to_all[mover] && solver_bodies[mover].velocity == glued_velocity[mover])) {
                glued_to_all[mover] = glue_all(solver_bodies[mover], bodies[mover], solver_bodies, bodies, list,
                                               count, level, shock_manifolds, shock_rows);
                glued_velocity[mover] = solver_bodies[mover].velocity;
              }
              if (glued_to_all[mover]) {
                changed = changed || !(solver_bodies[mover].velocity == before);
                continue;
              }
            }
            const bool glued = glue(solver_bodies[mover], solver_bodies[mover_is_b ? m.a : m.b], bodies[mover],
                                    mover_is_b, m, shock_rows);
            if (glued) {
              changed = changed || !(solver_bodies[mover].velocity == before);
              continue;
            }
            if (several_supports[mover]) continue;
          }
          if (!m.one_sided) make_one_sided(m, shock_rows, solver_bodies[m.a], solver_bodies[m.b], mover_is_b);
        }
        solve_manifold(solver_bodies, shock_rows, m, pass);
        changed = changed || !(solver_bodies[m.a].velocity == before_a) || !(solver_bodies[m.b].velocity == before_b);
      }
      converged = !changed;
    }
    // Passes that did not converge end at an arbitrary point of an
    // oscillation (a box on one corner leaning on a glued box of its own
    // rank loses ~1% of its rotation per pass; a row whose point is a hair
    // apart hands back the iterations' impulse and the next glue undoes
    // it), and settled heaps crept by ~1 mm/s on what the last pass left.
    // Then a rank the iterations already hold (no sideways push, no touching
    // point approaching faster than quiet_approach) keeps the iterations'
    // velocities; any other keeps, body by body, whichever of the two
    // velocities has the lower kinetic energy: the shock step may stop
    // motion it did not finish solving, never add to it.
    if (!converged) {
      for (const RankBody& b : before_shock) {
        SolverBody& body = solver_bodies[b.body];
        if (stirring_only || energy_per_mass(bodies[b.body], b.velocity, body.inverse_mass) <
                                 energy_per_mass(bodies[b.body], body.velocity, body.inverse_mass)) {
          body.velocity = b.velocity;
        }
      }
    }
    for (size_t i = begin; i < end; ++i) {
      for (uint32_t body : {shock_manifolds[i].a, shock_manifolds[i].b}) {
        if (level[body] != order[begin].level || solver_bodies[body].inverse_mass == Fixed{}) continue;
        frozen_bodies.push_back(body);
        saved_inverse_mass.push_back(solver_bodies[body].inverse_mass);
        solver_bodies[body].inverse_mass = Fixed{};
      }
    }
    begin = end;
  }
  for (size_t i = 0; i < frozen_bodies.size(); ++i) solver_bodies[frozen_bodies[i]].inverse_mass = saved_inverse_mass[i];

}

}  // namespace bitstep
