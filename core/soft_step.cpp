#include "core/soft_step.h"

#include <algorithm>

namespace bitstep {

namespace {

constexpr Fixed two_pi = "raw:6487ed511"_fx;  // 2 pi rounded to Q32.32

// How a pass treats an overlap: the solve pushes it out softly, the relax
// takes the push's velocity away again.
enum class Bias : uint8_t { soft, none };

struct PassCoefficients {
  Softness soft;
  Fixed inverse_h;
  Fixed max_push;  // m/s
  Fixed slop;      // m
  Bias bias;
};

// One contact point's normal row, soft (Box2D v3's b2SolveContact). s is
// the separation now: the row's at the step's start (-depth) plus the
// bodies' displacement along the row since, J . delta.
void solve_soft_point(SolverBody& a, SolverBody& b, const BodyRates& moved_a, const BodyRates& moved_b,
                      const PointRow& row, const PassCoefficients& k, uint8_t& pressed) {
  const Fixed s = relative_rate(moved_a, moved_b, row.normal, a.still, b.still) - row.point->depth + k.slop;
  Fixed bias, mass_scale = Fixed::one(), impulse_scale;
  if (s > Fixed{}) {
    bias = s * k.inverse_h;  // a gap may close within the substep, no further
  } else if (k.bias == Bias::soft) {
    bias = max(k.soft.bias_rate * s, -k.max_push);
    mass_scale = k.soft.mass_scale;
    impulse_scale = k.soft.impulse_scale;
  }
  Fixed& accumulated = row.point->normal_impulse;
  const Fixed vn = relative_velocity(a, b, row.normal);
  const Fixed increment = -(row.normal.mass * mass_scale) * (vn + bias) - impulse_scale * accumulated;
  const Fixed total = max(accumulated + increment, Fixed{});
  const Fixed delta = total - accumulated;
  accumulated = total;
  if (total > Fixed{}) pressed = 1;
  apply_impulse(a, b, row.normal, delta);
}

void warm_start(std::vector<SolverBody>& bodies, const SoftStepRows& rows) {
  warm_start_joints(bodies, rows.joints);
  for (const PointRow& row : rows.rows) warm_start_point(bodies[row.a], bodies[row.b], row);
  for (const ManifoldRow& m : rows.manifolds) warm_start_manifold(bodies[m.a], bodies[m.b], m);
}

// One pass over every row: the joints, then per manifold its points'
// normal rows and its friction, then the wheels.
void solve_pass(std::vector<SolverBody>& bodies, const SoftStepRows& rows, SoftStepScratch& scratch,
                const PassCoefficients& k) {
  solve_joints(bodies, rows.joints, rows.tree);
  for (const ManifoldRow& m : rows.manifolds) {
    SolverBody& a = bodies[m.a];
    SolverBody& b = bodies[m.b];
    for (size_t i = m.first; i < m.first + m.count; ++i) {
      solve_soft_point(a, b, scratch.moved[m.a], scratch.moved[m.b], rows.rows[i], k, scratch.pressed[i]);
    }
    solve_friction(a, b, m);
  }
  solve_tyres(bodies, rows.tyres);
}

// The bodies some row acts on. The others take no part in the substeps:
// they end the step with the velocities they came in with, no push.
void mark_bodies_in_rows(size_t count, const SoftStepRows& rows, std::vector<uint8_t>& in_rows) {
  in_rows.assign(count, 0);
  for (const ManifoldRow& m : rows.manifolds) in_rows[m.a] = in_rows[m.b] = 1;
  for (const JointRow& j : rows.joints) in_rows[j.a] = in_rows[j.b] = 1;
  for (const TyreRow& t : rows.tyres) in_rows[t.a] = in_rows[t.b] = 1;
}

// Each movable body's share of the step's forces, taken off the velocities
// it came in with (the substeps give it back share by share).
void split_forces(const std::vector<Body>& world_bodies, std::vector<SolverBody>& bodies,
                  const std::vector<BodyRates>& start, int n, SoftStepScratch& scratch) {
  const size_t count = bodies.size();
  scratch.force_share.assign(count, BodyRates{});
  scratch.moved.assign(count, BodyRates{});
  scratch.solved_sum.assign(count, BodyRates{});
  const Fixed parts = Fixed::from_int(n);
  for (size_t i = 0; i < count; ++i) {
    if (!is_awake_dynamic(world_bodies[i]) || i >= start.size() || scratch.in_rows[i] == 0) continue;
    BodyRates& v = bodies[i].velocity;
    BodyRates& share = scratch.force_share[i];
    share.linear = (v.linear - start[i].linear) / parts;
    share.angular = (v.angular - start[i].angular) / parts;
    v.linear -= share.linear * parts;
    v.angular -= share.angular * parts;
  }
}

// Box2D's restitution: a point that approached faster than the threshold
// when the step began and was pressed in some substep leaves at e times
// that speed.
void restitution(const Settings& settings, const std::vector<Body>& world_bodies, std::vector<SolverBody>& bodies,
                 const SoftStepRows& rows, const SoftStepScratch& scratch) {
  for (const ManifoldRow& m : rows.manifolds) {
    const Fixed e = max(world_bodies[m.a].material.restitution, world_bodies[m.b].material.restitution);
    if (e == Fixed{}) continue;
    for (size_t i = m.first; i < m.first + m.count; ++i) {
      const PointRow& row = rows.rows[i];
      const Fixed approach = scratch.approach[i];
      if (approach > -settings.restitution_threshold || scratch.pressed[i] == 0) continue;
      SolverBody& a = bodies[m.a];
      SolverBody& b = bodies[m.b];
      Fixed& accumulated = row.point->normal_impulse;
      const Fixed vn = relative_velocity(a, b, row.normal);
      const Fixed total = max(accumulated - row.normal.mass * (vn + e * approach), Fixed{});
      const Fixed delta = total - accumulated;
      accumulated = total;
      apply_impulse(a, b, row.normal, delta);
    }
  }
}

}  // namespace

Softness make_softness(Fixed hertz, Fixed damping_ratio, Fixed h) {
  if (hertz == Fixed{}) return {Fixed{}, Fixed{}, Fixed::one()};
  const Fixed omega = two_pi * hertz;
  const Fixed a1 = 2.0_fx * damping_ratio + h * omega;
  const Fixed a2 = h * omega * a1;
  const Fixed a3 = Fixed::one() / (Fixed::one() + a2);
  return {omega / a1, a2 * a3, a3};
}

void run_soft_step(const Settings& settings, const std::vector<Body>& world_bodies, std::vector<SolverBody>& bodies,
                   const SoftStepRows& rows, const std::vector<BodyRates>& start_velocities, SoftStepScratch& scratch) {
  const int n = settings.soft_substeps;
  const Fixed h = settings.dt / Fixed::from_int(n);
  // Box2D caps the contact's frequency at a quarter of the substep rate:
  // stiffer, the implicit spring overshoots within a substep.
  const Fixed hertz = min(settings.contact_hertz, Fixed::one() / (4.0_fx * h));
  PassCoefficients k{make_softness(hertz, settings.contact_damping_ratio, h), Fixed::one() / h,
                     settings.max_push_out_speed, settings.penetration_slop, Bias::soft};
  scratch.approach.resize(rows.rows.size());
  scratch.pressed.assign(rows.rows.size(), 0);
  for (size_t i = 0; i < rows.rows.size(); ++i) {
    const PointRow& row = rows.rows[i];
    scratch.approach[i] = relative_rate(start_velocities[row.a], start_velocities[row.b], row.normal);
  }
  mark_bodies_in_rows(bodies.size(), rows, scratch.in_rows);
  split_forces(world_bodies, bodies, start_velocities, n, scratch);
  for (int substep = 0; substep < n; ++substep) {
    for (size_t i = 0; i < bodies.size(); ++i) {
      bodies[i].velocity.linear += scratch.force_share[i].linear;
      bodies[i].velocity.angular += scratch.force_share[i].angular;
    }
    warm_start(bodies, rows);
    k.bias = Bias::soft;
    solve_pass(bodies, rows, scratch, k);
    for (size_t i = 0; i < bodies.size(); ++i) {
      if (bodies[i].still || scratch.in_rows[i] == 0) continue;
      const BodyRates& v = bodies[i].velocity;
      scratch.moved[i].linear += v.linear * h;
      scratch.moved[i].angular += v.angular * h;
      scratch.solved_sum[i].linear += v.linear;
      scratch.solved_sum[i].angular += v.angular;
    }
    k.bias = Bias::none;
    solve_pass(bodies, rows, scratch, k);
  }
  restitution(settings, world_bodies, bodies, rows, scratch);
  const Fixed parts = Fixed::from_int(n);
  for (size_t i = 0; i < bodies.size(); ++i) {
    SolverBody& body = bodies[i];
    if (scratch.in_rows[i] == 0) continue;
    body.push.linear = scratch.solved_sum[i].linear / parts - body.velocity.linear;
    body.push.angular = scratch.solved_sum[i].angular / parts - body.velocity.angular;
  }
}

}  // namespace bitstep
