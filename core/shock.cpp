#include "core/shock.h"

#include <algorithm>

#include "core/shock_levels.h"

namespace bitstep {

namespace {

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

}  // namespace

void propagate_shock(const Settings& settings, const std::vector<Body>& bodies, const std::vector<Contact>& contacts,
                     SolverScratch& scratch) {
  std::vector<SolverBody>& solver_bodies = scratch.bodies;
  const std::vector<PointRow>& rows = scratch.rows;
  const std::vector<ManifoldRow>& manifold_rows = scratch.manifolds;
  if (manifold_rows.empty()) return;  // nothing awake touches anything
  ShockLevels& levels = scratch.levels;
  shock_levels(bodies, contacts, settings.gravity, settings.penetration_slop, levels);
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
    // Apart by more than the slop: a speculative contact, for the
    // iterations (gluing it would stop a falling body in the air), unless
    // sideways, where it is solved one-sided up to touching and no more.
    if (!sideways && !touches(*m.manifold, settings.penetration_slop)) continue;
    order.push_back({std::max(level[m.a], level[m.b]), i, support});
  }
  std::sort(order.begin(), order.end(),
            [](ShockEntry x, ShockEntry y) { return x.level != y.level ? x.level < y.level : x.index < y.index; });

  // Bodies held up by more than one body. One the glue cannot hold (its
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
    } else if (first_support[mover] != support) {
      several_supports[mover] = 1;
    }
  }

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
    // Passes over the rank until one changes no velocity (exactly: the
    // arithmetic is fixed point), at most shock_iterations.
    for (int pass = 0; pass < settings.shock_iterations; ++pass) {
      bool changed = false;
      for (size_t i = begin; i < end; ++i) {
        ManifoldRow& m = shock_manifolds[i];
        const BodyRates before_a = solver_bodies[m.a].velocity, before_b = solver_bodies[m.b].velocity;
        if (level[m.a] != level[m.b]) {
          const bool mover_is_b = level[m.a] < level[m.b];
          const uint32_t mover = mover_is_b ? m.b : m.a;
          if (order[i].holds_up) {
            if (glue(solver_bodies[mover], solver_bodies[mover_is_b ? m.a : m.b], bodies[mover], mover_is_b, m,
                     shock_rows)) {
              changed = changed || !(solver_bodies[mover].velocity == (mover_is_b ? before_b : before_a));
              continue;
            }
            if (several_supports[mover]) continue;
          }
          if (!m.one_sided) make_one_sided(m, shock_rows, solver_bodies[m.a], solver_bodies[m.b], mover_is_b);
        }
        solve_manifold(solver_bodies, shock_rows, m, pass);
        changed = changed || !(solver_bodies[m.a].velocity == before_a) || !(solver_bodies[m.b].velocity == before_b);
      }
      if (!changed) break;
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
