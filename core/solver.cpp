#include "core/solver.h"

#include <algorithm>

namespace bitstep {

namespace {

// The hot state of one body during the solve (STYLE rule 5): velocities,
// pseudo-velocities and the inverse mass properties, contiguous by slot.
struct SolverBody {
  Vec3 v, w;    // m/s, rad/s
  Vec3 pv, pw;  // split-impulse pseudo-velocities
  Fixed inverse_mass;
  Mat33 inverse_inertia;  // world frame
};

// One contact point as a constraint. Normal n points from a to b; the
// relative velocity at the point is dv = (v_b + w_b x r_b) - (v_a + w_a x r_a)
// and the normal row asks dv . n >= velocity_target with impulse >= 0.
struct PointRow {
  uint32_t a, b;
  Vec3 ra, rb;  // m, from each centre of mass to the point
  Vec3 normal, tangent[2];
  Fixed normal_mass;      // 1 / (J M^-1 J^T) of the normal row, kg
  Fixed tangent_mass[2];  // likewise for the two friction rows
  Fixed velocity_target;  // m/s: restitution bounce, speculative approach or Baumgarte bias
  Fixed push_target;      // m/s: split-impulse separation speed
  Fixed static_friction, dynamic_friction;
  ContactPoint* point;    // where the accumulated impulses live
};

// An orthonormal pair perpendicular to the unit vector n (fixed choice, so
// warm-started friction impulses keep their meaning between steps).
void tangent_basis(Vec3 n, Vec3& t1, Vec3& t2) {
  const Vec3 axis = abs(n.x) < 0.57735_fx ? Vec3{Fixed::one(), {}, {}} : Vec3{{}, Fixed::one(), {}};
  t1 = normalize(cross(n, axis));
  t2 = cross(n, t1);
}

Vec3 velocity_at(const SolverBody& body, Vec3 r) { return body.v + cross(body.w, r); }
Vec3 push_at(const SolverBody& body, Vec3 r) { return body.pv + cross(body.pw, r); }

// 1 / (m_a^-1 + m_b^-1 + (r_a x d) . I_a^-1 (r_a x d) + (r_b x d) . I_b^-1 (r_b x d)).
Fixed effective_mass(const SolverBody& a, const SolverBody& b, Vec3 ra, Vec3 rb, Vec3 d) {
  const Vec3 rda = cross(ra, d), rdb = cross(rb, d);
  const Fixed k = a.inverse_mass + b.inverse_mass + dot(rda, a.inverse_inertia * rda) + dot(rdb, b.inverse_inertia * rdb);
  return k > Fixed{} ? Fixed::one() / k : Fixed{};
}

void apply_impulse(SolverBody& a, SolverBody& b, Vec3 ra, Vec3 rb, Vec3 impulse) {
  a.v -= impulse * a.inverse_mass;
  a.w -= a.inverse_inertia * cross(ra, impulse);
  b.v += impulse * b.inverse_mass;
  b.w += b.inverse_inertia * cross(rb, impulse);
}

void apply_push(SolverBody& a, SolverBody& b, Vec3 ra, Vec3 rb, Vec3 impulse) {
  a.pv -= impulse * a.inverse_mass;
  a.pw -= a.inverse_inertia * cross(ra, impulse);
  b.pv += impulse * b.inverse_mass;
  b.pw += b.inverse_inertia * cross(rb, impulse);
}

std::vector<SolverBody> gather_bodies(const std::vector<Body>& bodies) {
  std::vector<SolverBody> out(bodies.size());
  for (size_t i = 0; i < bodies.size(); ++i) {
    const Body& body = bodies[i];
    if (!body.alive) continue;
    out[i] = {body.linear_velocity, body.angular_velocity, {}, {}, body.inverse_mass, body.inverse_inertia_world};
  }
  return out;
}

std::vector<PointRow> prepare_rows(const Settings& settings, const std::vector<Body>& bodies,
                                   const std::vector<SolverBody>& solver_bodies, std::vector<Contact>& contacts) {
  std::vector<PointRow> rows;
  const Fixed inverse_dt = Fixed::one() / settings.dt;
  for (Contact& contact : contacts) {
    const uint32_t ia = contact.key.body_a, ib = contact.key.body_b;
    const Body& body_a = bodies[ia];
    const Body& body_b = bodies[ib];
    const SolverBody& a = solver_bodies[ia];
    const SolverBody& b = solver_bodies[ib];
    Manifold& m = contact.manifold;
    Vec3 t1, t2;
    tangent_basis(m.normal, t1, t2);
    // Pair mixing: geometric mean of frictions, the larger restitution.
    const Fixed mu_s = sqrt(body_a.material.static_friction * body_b.material.static_friction);
    const Fixed mu_d = sqrt(body_a.material.dynamic_friction * body_b.material.dynamic_friction);
    const Fixed restitution = max(body_a.material.restitution, body_b.material.restitution);
    for (int i = 0; i < m.point_count; ++i) {
      ContactPoint& p = m.points[static_cast<size_t>(i)];
      PointRow row{ia, ib, p.position - body_a.pose.position, p.position - body_b.pose.position, m.normal, {t1, t2},
                   {}, {}, {}, {}, mu_s, mu_d, &p};
      row.normal_mass = effective_mass(a, b, row.ra, row.rb, m.normal);
      row.tangent_mass[0] = effective_mass(a, b, row.ra, row.rb, t1);
      row.tangent_mass[1] = effective_mass(a, b, row.ra, row.rb, t2);
      const Fixed approach = dot(velocity_at(b, row.rb) - velocity_at(a, row.ra), m.normal);
      // A gap (depth < 0) may close by depth / dt this step: speculative contact.
      row.velocity_target = p.depth < Fixed{} ? p.depth * inverse_dt : Fixed{};
      if (approach < -settings.restitution_threshold) {
        row.velocity_target = max(row.velocity_target, -restitution * approach);
      }
      const Fixed excess = p.depth - settings.penetration_slop;
      if (excess > Fixed{}) {
        const Fixed factor = settings.baumgarte ? settings.baumgarte_factor : settings.split_impulse_factor;
        const Fixed recovery = min(factor * excess * inverse_dt, settings.max_push_out_speed);
        if (settings.baumgarte) {
          row.velocity_target = max(row.velocity_target, recovery);
        } else {
          row.push_target = recovery;
        }
      }
      p.split_impulse = Fixed{};
      rows.push_back(row);
    }
  }
  return rows;
}

void warm_start(std::vector<SolverBody>& bodies, const std::vector<PointRow>& rows) {
  for (const PointRow& row : rows) {
    const ContactPoint& p = *row.point;
    const Vec3 impulse =
        row.normal * p.normal_impulse + row.tangent[0] * p.tangent_impulse[0] + row.tangent[1] * p.tangent_impulse[1];
    apply_impulse(bodies[row.a], bodies[row.b], row.ra, row.rb, impulse);
  }
}

// Friction: the impulse that stops sliding, kept while within the static
// cone |j_t| <= mu_s j_n, else scaled onto the dynamic cone mu_d j_n.
void solve_friction(SolverBody& a, SolverBody& b, const PointRow& row) {
  ContactPoint& p = *row.point;
  const Vec3 dv = velocity_at(b, row.rb) - velocity_at(a, row.ra);
  const Fixed old0 = p.tangent_impulse[0], old1 = p.tangent_impulse[1];
  Fixed new0 = old0 - row.tangent_mass[0] * dot(dv, row.tangent[0]);
  Fixed new1 = old1 - row.tangent_mass[1] * dot(dv, row.tangent[1]);
  const Fixed magnitude = length(Vec3{new0, new1, Fixed{}});
  if (magnitude > row.static_friction * p.normal_impulse) {
    const Fixed slide = row.dynamic_friction * p.normal_impulse;
    new0 = mul_div(new0, slide, magnitude);
    new1 = mul_div(new1, slide, magnitude);
  }
  p.tangent_impulse[0] = new0;
  p.tangent_impulse[1] = new1;
  apply_impulse(a, b, row.ra, row.rb, row.tangent[0] * (new0 - old0) + row.tangent[1] * (new1 - old1));
}

void solve_normal(SolverBody& a, SolverBody& b, const PointRow& row) {
  ContactPoint& p = *row.point;
  const Fixed vn = dot(velocity_at(b, row.rb) - velocity_at(a, row.ra), row.normal);
  const Fixed total = max(p.normal_impulse + row.normal_mass * (row.velocity_target - vn), Fixed{});
  const Fixed delta = total - p.normal_impulse;
  p.normal_impulse = total;
  apply_impulse(a, b, row.ra, row.rb, row.normal * delta);
}

void solve_push(SolverBody& a, SolverBody& b, const PointRow& row) {
  ContactPoint& p = *row.point;
  const Fixed vn = dot(push_at(b, row.rb) - push_at(a, row.ra), row.normal);
  const Fixed total = max(p.split_impulse + row.normal_mass * (row.push_target - vn), Fixed{});
  const Fixed delta = total - p.split_impulse;
  p.split_impulse = total;
  apply_push(a, b, row.ra, row.rb, row.normal * delta);
}

// Sweeps alternate direction every pass, so no point of a symmetric stack
// is always solved last (a seed remedy against drift).
template <class Solve>
void sweep(std::vector<SolverBody>& bodies, const std::vector<PointRow>& rows, int pass, Solve solve) {
  if (pass % 2 == 0) {
    for (const PointRow& row : rows) solve(bodies[row.a], bodies[row.b], row);
  } else {
    for (auto it = rows.rbegin(); it != rows.rend(); ++it) solve(bodies[it->a], bodies[it->b], *it);
  }
}

}  // namespace

void solve_contacts(const Settings& settings, std::vector<Body>& bodies, std::vector<Contact>& contacts,
                    PushVelocities& push) {
  std::vector<SolverBody> solver_bodies = gather_bodies(bodies);
  const std::vector<PointRow> rows = prepare_rows(settings, bodies, solver_bodies, contacts);
  if (settings.warm_starting) {
    warm_start(solver_bodies, rows);
  } else {
    for (const PointRow& row : rows) {
      row.point->normal_impulse = Fixed{};
      row.point->tangent_impulse[0] = row.point->tangent_impulse[1] = Fixed{};
    }
  }
  for (int pass = 0; pass < settings.velocity_iterations; ++pass) {
    sweep(solver_bodies, rows, pass, [](SolverBody& a, SolverBody& b, const PointRow& row) {
      solve_friction(a, b, row);
      solve_normal(a, b, row);
    });
  }
  if (!settings.baumgarte) {
    for (int pass = 0; pass < settings.position_iterations; ++pass) sweep(solver_bodies, rows, pass, solve_push);
  }
  push.linear.assign(bodies.size(), Vec3{});
  push.angular.assign(bodies.size(), Vec3{});
  for (size_t i = 0; i < bodies.size(); ++i) {
    Body& body = bodies[i];
    if (!body.alive || body.type != BodyType::dynamic) continue;
    body.linear_velocity = solver_bodies[i].v;
    body.angular_velocity = solver_bodies[i].w;
    push.linear[i] = solver_bodies[i].pv;
    push.angular[i] = solver_bodies[i].pw;
  }
}

}  // namespace bitstep
