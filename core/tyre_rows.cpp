#include "core/tyre_rows.h"

namespace bitstep {

namespace {

// The tyre's impulse kept within its friction circle: where
// |(f, s)| > mu_s N it slides, and the impulse is scaled onto mu_d N.
// The length is formed only past the cheap bound |f| + |s| <= mu_s N.
// N is the suspension row's impulse as it stands (as contact friction takes
// the normal impulse's).
void within_circle(const TyreRow& row, Fixed& forward, Fixed& side) {
  const Fixed hold = mul_in_range(row.static_friction, row.suspension_impulse);
  if (abs(forward) + abs(side) <= hold) return;
  const Fixed magnitude = length(Vec3{forward, side, Fixed{}});
  if (magnitude <= hold) return;
  const Fixed slide = mul_in_range(row.dynamic_friction, row.suspension_impulse);
  forward = mul_div(forward, slide, magnitude);
  side = mul_div(side, slide, magnitude);
}

// The suspension's soft row (its coefficients: suspension_row in car.cpp):
// the accumulated impulse N moves to the one that meets
//   J v - target + softness N = 0,
// N' = N - m_soft (J v - target + softness N), m_soft = 1 / (J M^-1 J^T +
// softness), and stays >= 0: a suspension pushes, never pulls.
void solve_suspension(SolverBody& a, SolverBody& b, TyreRow& row) {
  const Fixed old = row.suspension_impulse;
  const Fixed error = relative_velocity(a, b, row.suspension) - row.suspension_target + mul_in_range(row.softness, old);
  const Fixed impulse = max(old - mul_in_range(row.suspension_mass, error), Fixed{});
  row.suspension_impulse = impulse;
  apply_impulse(a, b, row.suspension, impulse - old);
}

}  // namespace

void prepare_tyre_rows(const std::vector<Body>& bodies, const std::vector<SolverBody>& solver_bodies,
                       const std::vector<TyreContact>& tyres, std::vector<TyreRow>& rows) {
  rows.clear();
  for (const TyreContact& tyre : tyres) {
    const SolverBody& ground = solver_bodies[tyre.ground];
    const SolverBody& chassis = solver_bodies[tyre.chassis];
    TyreRow row;
    row.a = tyre.ground;
    row.b = tyre.chassis;
    const Vec3 ra = tyre.point - bodies[tyre.ground].pose.position;
    const Vec3 rb = tyre.point - bodies[tyre.chassis].pose.position;
    row.suspension = make_jacobian(ground, chassis, ra, rb, tyre.normal);
    // 1 / (J M^-1 J^T + softness), from m = 1 / (J M^-1 J^T): m / (1 + softness m).
    row.suspension_mass = row.suspension.mass / (Fixed::one() + tyre.softness * row.suspension.mass);
    row.suspension_target = tyre.suspension_target;
    row.softness = tyre.softness;
    row.suspension_impulse = tyre.suspension_impulse;
    row.rows[0] = make_jacobian(ground, chassis, ra, rb, tyre.forward);
    row.rows[1] = make_jacobian(ground, chassis, ra, rb, tyre.side);
    row.lower = tyre.drive - tyre.brake;
    row.upper = tyre.drive + tyre.brake;
    row.static_friction = tyre.static_friction;
    row.dynamic_friction = tyre.dynamic_friction;
    row.impulse[0] = tyre.forward_impulse;
    row.impulse[1] = tyre.side_impulse;
    rows.push_back(row);
  }
}

void warm_start_tyres(std::vector<SolverBody>& bodies, std::vector<TyreRow>& rows, bool warm) {
  for (TyreRow& row : rows) {
    if (!warm) row.suspension_impulse = Fixed{};
    apply_impulse(bodies[row.a], bodies[row.b], row.suspension, row.suspension_impulse);
  }
  for (TyreRow& row : rows) {
    Fixed forward = clamp(warm ? row.impulse[0] : Fixed{}, row.lower, row.upper);
    Fixed side = warm ? row.impulse[1] : Fixed{};
    within_circle(row, forward, side);
    row.impulse[0] = forward;
    row.impulse[1] = side;
    apply_impulse(bodies[row.a], bodies[row.b], row.rows[0], forward);
    apply_impulse(bodies[row.a], bodies[row.b], row.rows[1], side);
  }
}

// Every wheel's suspension first, then the tyres, each within the friction
// circle of its suspension's impulse as it then stands: each tyre row's impulse
// moves to the one that stops its relative velocity (l - m J v, m the
// row's effective mass); the forward one within the drive's and brake's
// bounds (no brake: the wheel rolls, and only the drive pushes), then both
// within the friction circle.
void solve_tyres(std::vector<SolverBody>& bodies, std::vector<TyreRow>& rows) {
  for (TyreRow& row : rows) solve_suspension(bodies[row.a], bodies[row.b], row);
  for (TyreRow& row : rows) {
    SolverBody& a = bodies[row.a];
    SolverBody& b = bodies[row.b];
    const Fixed old_forward = row.impulse[0], old_side = row.impulse[1];
    Fixed forward = old_forward - mul_in_range(row.rows[0].mass, relative_velocity(a, b, row.rows[0]));
    Fixed side = old_side - mul_in_range(row.rows[1].mass, relative_velocity(a, b, row.rows[1]));
    forward = clamp(forward, row.lower, row.upper);
    within_circle(row, forward, side);
    row.impulse[0] = forward;
    row.impulse[1] = side;
    apply_impulse(a, b, row.rows[0], forward - old_forward);
    apply_impulse(a, b, row.rows[1], side - old_side);
  }
}

void store_tyre_impulses(const std::vector<TyreRow>& rows, std::vector<TyreContact>& tyres) {
  for (size_t i = 0; i < rows.size(); ++i) {
    tyres[i].suspension_impulse = rows[i].suspension_impulse;
    tyres[i].forward_impulse = rows[i].impulse[0];
    tyres[i].side_impulse = rows[i].impulse[1];
  }
}

}  // namespace bitstep
