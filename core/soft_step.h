// The soft step (Box2D v3's solver, after Catto's "Solver2D"): the contact
// rows are built once a step, then solved in substeps of h = dt / n. Each
// substep gives the bodies their share of the step's forces, applies the
// accumulated impulses again (warm start), solves every row once with a
// soft bias toward closing the overlap, moves the bodies (in the solve's
// bookkeeping only: each contact's separation is updated from the bodies'
// displacement along its row, J . delta), and relaxes: solves every row
// again without the bias, so the push-out leaves no velocity behind.
// Restitution comes last, from the approach speed the step began with.
//
// A soft contact is a spring and damper on the overlap, integrated
// implicitly (Erin Catto, "Soft Step", 2024): with w = 2 pi hertz and
// damping ratio z, per substep h,
//   a1 = 2 z + h w, a2 = h w a1, a3 = 1 / (1 + a2),
//   bias rate = w / a1, mass scale = a2 a3, impulse scale = a3,
// and the row's impulse is
//   -m (mass scale (J v + bias rate s) ) - impulse scale lambda_acc
// for an overlap s < 0 (the bias capped at max_push_out_speed). A gap
// (s > 0) may close by s / h, as a speculative contact. The stiffness is
// what makes stacks and mass ratios converge in few passes: a heavy body on
// a light one cannot drive it through the ground in one pass, it pushes on
// a spring.
//
// The accumulated impulses are per substep (impulse over h), and so are
// the joints' and tyres'. The velocities the step ends with are the last
// relax's; the bodies move by the sum of the substeps' solved velocities
// times h, which reaches World's position integration as push velocities
// (mean solved velocity minus final velocity). Internal to core/.
#pragma once

#include <vector>

#include "core/joint_solver.h"
#include "core/settings.h"
#include "core/solver_rows.h"
#include "core/tyre_rows.h"

namespace bitstep {

// A soft constraint's coefficients for a substep of h (see above).
struct Softness {
  Fixed bias_rate;      // 1/s
  Fixed mass_scale;     // 1
  Fixed impulse_scale;  // 1
};
Softness make_softness(Fixed hertz, Fixed damping_ratio, Fixed h);

// The soft step's working memory, kept from step to step.
struct SoftStepScratch {
  std::vector<uint8_t> in_rows;         // per slot: some row acts on it
  std::vector<BodyRates> force_share;  // per slot: the step's force velocity change / n
  std::vector<BodyRates> moved;        // per slot: displacement (m, rad) since the step began
  std::vector<BodyRates> solved_sum;   // per slot: the sum of the substeps' solved velocities
  std::vector<Fixed> approach;         // per point row: J v before the step's forces
  std::vector<uint8_t> pressed;        // per point row: a substep gave it a positive impulse
};

struct SoftStepRows {
  std::vector<PointRow>& rows;
  std::vector<ManifoldRow>& manifolds;
  std::vector<JointRow>& joints;
  JointTree& tree;
  std::vector<TyreRow>& tyres;
};

// The substeps, the restitution and the push velocities (out, per slot)
// that move each body by its substeps' displacement. `start_velocities`:
// each body's before the step's forces; `bodies` hold the velocities after
// them on entry, the step's final velocities on return.
void run_soft_step(const Settings& settings, const std::vector<Body>& world_bodies, std::vector<SolverBody>& bodies,
                   const SoftStepRows& rows, const std::vector<BodyRates>& start_velocities, SoftStepScratch& scratch);

}  // namespace bitstep
