// A raycast car's wheels as rows of the contact solve (core/car.h finds
// where the wheels touch; this solves what they hold). Each grounded wheel
// is three rows at its ground point between the chassis and the body under
// it, solved in every velocity iteration with the contacts and joints, so
// that they hold the velocity the step's forces (gravity on a slope among
// them) give the chassis, not only the one it had when the step began:
// - the suspension, along the ground's normal: a soft unilateral row, the
//   spring and damper integrated implicitly (its impulse N >= 0: it pushes,
//   never pulls), stable however stiff the spring is for the step;
// - the tyre: a row along the wheel's heading (drive and brake) and one
//   across it (side grip), their impulse (l_f, l_s) within the friction
//   circle of the suspension row's current impulse N, as contact friction
//   is within the normal impulse: it sticks while |(l_f, l_s)| <= mu_s N
//   and slides at mu_d N.
// Internal to core/.
#pragma once

#include <cstdint>
#include <vector>

#include "core/solver_rows.h"

namespace bitstep {

// What one grounded wheel asks of the solve this step (made by drive_cars).
struct TyreContact {
  uint32_t car = 0, wheel = 0;        // which wheel (its place in World::cars())
  uint32_t chassis = 0, ground = 0;   // body slots
  Vec3 point;                         // m: where the wheel touches the ground
  Vec3 normal;                        // unit: the ground's, along which the suspension pushes the chassis
  Vec3 forward, side;                 // unit, in the ground's plane: the wheel's heading, and n x heading
  // The suspension as a soft row (made by drive_cars, which has the step;
  // see suspension_row there): J v + softness N = target, N >= 0.
  Fixed suspension_target;            // m/s: k s / (c + h k), outward, for compression s
  Fixed softness;                     // 1/kg: gamma = 1 / (h (c + h k))
  Fixed drive;                        // N s, along forward: throttle x drive force x dt
  Fixed brake;                        // N s: the most the brake holds this step, brake x brake force x dt
  Fixed static_friction, dynamic_friction;  // the tyre's grip mixed with the ground's
  // The impulses on the chassis (N s, along the normal, forward and side;
  // the ground takes the opposite): last step's, which start the solve,
  // then the ones it settled on.
  Fixed suspension_impulse, forward_impulse, side_impulse;
};

// A wheel in the solve: three axis parts with the chassis as b and the
// ground as a, so J v is the chassis's wheel point's velocity relative to
// the ground's along the row, and an impulse l pushes the chassis by +l.
struct TyreRow {
  uint32_t a = 0, b = 0;  // ground, chassis
  Jacobian suspension;    // along the ground's normal
  Fixed suspension_mass;  // kg: the soft row's 1 / (J M^-1 J^T + softness)
  Fixed suspension_target, softness;
  Fixed suspension_impulse;  // accumulated, >= 0: the friction circle's N
  Jacobian rows[2];       // forward, side
  Fixed impulse[2];       // accumulated: forward (drive + brake), side; last step's to begin with
  Fixed lower, upper;     // N s: the forward impulse's bounds, drive -+ brake
  Fixed static_friction, dynamic_friction;
};

// One wheel's rows per tyre contact, in their order.
void prepare_tyre_rows(const std::vector<Body>& bodies, const std::vector<SolverBody>& solver_bodies,
                       const std::vector<TyreContact>& tyres, std::vector<TyreRow>& rows);
// Starts every wheel from last step's impulses (`warm`; else from no
// suspension impulse and its drive alone), within its bounds and friction
// circle.
void warm_start_tyres(std::vector<SolverBody>& bodies, std::vector<TyreRow>& rows, bool warm);
// One velocity iteration over the wheels: each one's suspension, then its
// tyre within the suspension's impulse.
void solve_tyres(std::vector<SolverBody>& bodies, std::vector<TyreRow>& rows);
// The settled impulses back into the tyre contacts.
void store_tyre_impulses(const std::vector<TyreRow>& rows, std::vector<TyreContact>& tyres);

}  // namespace bitstep
