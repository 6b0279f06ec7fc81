// The solver's rows: the per-body state of a solve and the constraint rows
// of contact points and manifolds, with the one-row updates shared by the
// iterations (solver.cpp) and the shock step (shock.cpp). Internal to core/.
#pragma once

#include <vector>

#include "core/body.h"
#include "core/contact.h"
#include "core/executor.h"
#include "core/manifold.h"

namespace bitstep {

// A linear and an angular rate: a body's velocity (m/s, rad/s) or its
// split-impulse pseudo-velocity.
struct BodyRates {
  Vec3 linear, angular;
  friend bool operator==(const BodyRates&, const BodyRates&) = default;
};

// The hot state of one body during the solve (hot data contiguous, structure of
// arrays for the solver's per-body state): velocities,
// pseudo-velocities and the inverse mass properties, contiguous by slot.
struct SolverBody {
  BodyRates velocity;
  BodyRates push;  // split-impulse pseudo-velocity
  Fixed inverse_mass;
  Mat33 inverse_inertia;  // world frame
  // Immovable and at rest for the whole solve (static, asleep, a kinematic
  // body standing still): zero inverse mass and inertia, so its parts of
  // every row are zero, and zero rates that no impulse changes. The rows
  // leave out its products, each exactly 0 (the same bits): a pile's
  // contacts with the ground do half the work.
  bool still = false;
};

// One row of a constraint along a unit direction d (a constraint part, after
// Jolt's AxisConstraintPart), precomputed once per step: the relative
// velocity along d is
//   J v = d . (v_b - v_a) + (r_b x d) . w_b - (r_a x d) . w_a
// and an impulse lambda changes v_a by -lambda d / m_a, w_a by
// -lambda I_a^-1 (r_a x d), and b the opposite way. Keeping d / m, r x d and
// I^-1 (r x d) turns every solver update into scalar-times-vector work.
// Angular rows (twist, rocking, rolling) are AngularParts, below.
struct Jacobian {
  Vec3 direction;
  Vec3 arm_a, arm_b;          // r_a x d, r_b x d
  Vec3 linear_a, linear_b;    // d / m_a, d / m_b (zero for an immovable body)
  Vec3 turn_a, turn_b;        // I_a^-1 (r_a x d), I_b^-1 (r_b x d)
  Fixed mass;                 // 1 / (J M^-1 J^T), kg
};

// An angular-only row (after Jolt's AngleConstraintPart: twist, rocking,
// rolling resistance): J v = (w_b - w_a) . u, and an impulse lambda turns a
// by -lambda I_a^-1 u and b by +lambda I_b^-1 u. No linear part and one
// axis for both bodies: 80 bytes where a Jacobian takes 176.
struct AngularPart {
  Vec3 axis;            // u
  Vec3 turn_a, turn_b;  // I_a^-1 u, I_b^-1 u (zero for an immovable body)
  Fixed mass;           // 1 / (u . I_a^-1 u + u . I_b^-1 u), kg m^2
};

// Whether a body does not move in the solve (static, kinematic, asleep):
// zero inverse mass and inertia, so its products in a row are all zero.
bool immovable(const SolverBody& body);
// The row along unit d between points at arms r_a, r_b from the bodies'
// centres of mass (a contact normal or tangent, a joint axis).
Jacobian make_jacobian(const SolverBody& a, const SolverBody& b, Vec3 ra, Vec3 rb, Vec3 d);
// The angular row (w_b - w_a) . n about unit n.
AngularPart make_twist(const SolverBody& a, const SolverBody& b, Vec3 n);

// One contact point as a constraint: a normal row (n from a to b) asking
// J v >= velocity_target with impulse >= 0.
struct PointRow {
  uint32_t a, b;
  Jacobian normal;
  Fixed velocity_target;  // m/s: restitution bounce, speculative approach or Baumgarte bias
  Fixed push_target;      // m/s: split-impulse separation speed
  ContactPoint* point;    // where the accumulated impulse lives
  bool in_resting_face = false;  // its manifold's centroid and rocking rows stand for it
  bool impact = false;           // push_target is an exact rebound displacement rate, either sign
};

// A manifold's points taken together, at their centroid:
// - a normal row whose impulse is shared equally by the points: a pure force
//   through the centroid (no torque about it), so a stack's load is solved
//   symmetrically before the point rows correct the torques (after JigLib's
//   averaged extra point);
// - friction: two tangent rows and a twist row about the normal, anchored at
//   the centroid and bounded by the manifold's total normal impulse (friction
//   anchored at the manifold centre, a remedy for stacks from the engines
//   bitstep follows: Kenwright's simple impulse engine, JigLib).
struct ManifoldRow {
  uint32_t a, b;
  size_t first, count;  // its points in the point-row list
  Jacobian normal;      // at the centroid
  Jacobian tangent[2];  // at the centroid
  AngularPart twist;    // (w_b - w_a) . n
  Vec3 offset_a, offset_b;  // m: the centroid from each body's centre of mass
  Fixed velocity_target;
  Fixed twist_radius;   // m: mean distance of the points from the centroid
  Fixed static_friction, dynamic_friction;
  Manifold* manifold;
  // Rocking rows: the relative rotation about two in-plane axes, each a set
  // of point impulses lambda alpha_i with sum alpha_i = 0 (no net force), so
  // its net effect is the angular impulse lambda u (see make_rocking).
  struct Rocking {
    AngularPart row;  // along u
    Fixed alpha[max_manifold_points];
    bool active = false;
  } rocking[2];
  Fixed share_mass;        // normal.mass / count: each point's share of the centroid row
  bool one_sided = false;  // shock step: the lower body's side dropped (shock.cpp)
  // Rolling resistance: two angular rows (w_b - w_a) . t_k about the
  // tangents, their impulse within rolling_limit times the manifold's total
  // normal impulse (m: the pair's c times the rolling radius). 0: no rows,
  // as between two boxes.
  AngularPart rolling[2] = {};
  Fixed rolling_limit;
  // Its place in this solve's manifold rows, and the place in the solve
  // numbered SolverScratch::rows_reused_from of the row it was copied from
  // (row_cache.h: the same key, normal, points and friction), or none.
  // glue_all's faces know from these that their inputs stand (shock_solve.cpp).
  static constexpr uint32_t none = UINT32_MAX;
  uint32_t index = 0, reused_from = none;
};

// The contact point of m's i-th point row: the rows are built in the
// manifold's point order (build_rows in contact_rows.cpp, one-sided copies
// keep it), so it is read from the manifold, without loading the row (a
// PointRow is ~220 bytes; a resting face's rows are not otherwise read in
// an iteration).
inline ContactPoint& point_of(const ManifoldRow& m, size_t i) { return m.manifold->points[i]; }

// The iterations' copies of a manifold row's parts, one array per sweep
// (SweepRows), made once a solve (split_sweep_rows). A pass of the
// iterations sweeps the manifolds three times (friction, the centroid row,
// rocking) and the free point rows once; over whole ManifoldRows (1,152
// bytes, streamed whole by the prefetcher) and the contacts' manifolds
// (their impulses 56 bytes apart) each sweep would read everything, and a
// big wall's manifolds would stream from beyond the core's cache every pass.
// Each sweep streams only the part it reads, and the accumulated
// impulses lie together (ManifoldImpulses), read from the manifolds once
// and written back once a solve. The same arithmetic on the same values.
struct ManifoldImpulses {
  Fixed normal[max_manifold_points];  // per point (Manifold::points[i].normal_impulse)
  Fixed friction[2];
  Fixed twist;
  Fixed rolling[2];
};
struct FrictionRow {
  uint32_t a, b;
  size_t count;
  ManifoldImpulses* impulses;
  Jacobian tangent[2];
  AngularPart twist;
  Fixed static_friction, dynamic_friction, twist_radius;
  Fixed rolling_limit;
  const AngularPart* rolling;  // the manifold row's two rolling rows (read only where rolling_limit > 0)
};
struct CentroidRow {
  uint32_t a, b;
  size_t count;
  ManifoldImpulses* impulses;
  Jacobian normal;
  Fixed share_mass, velocity_target;
};
struct RockingRow {
  uint32_t a, b;
  size_t count;
  ManifoldImpulses* impulses;
  ManifoldRow::Rocking rocking[2];
};
// A point row outside a resting face (the iterations' point rows).
struct FreeRow {
  uint32_t a, b;
  Jacobian normal;
  Fixed velocity_target;
  Fixed* impulse;  // its point's in ManifoldImpulses::normal
};

// Which manifolds and rows each sweep visits: friction every manifold, the
// centroid row those of 2 points or more, rocking those with an active
// rocking row (the others' updates change nothing), the point rows those
// outside a resting face. The ordered sweeps list the same.
inline bool has_centroid_row(const ManifoldRow& m) { return m.count >= 2; }
inline bool has_rocking_rows(const ManifoldRow& m) { return m.rocking[0].active || m.rocking[1].active; }
inline bool is_free_row(const PointRow& row) { return !row.in_resting_face; }

struct SweepRows {
  std::vector<ManifoldImpulses> impulses;  // per manifold row
  std::vector<FrictionRow> friction;       // per manifold row
  std::vector<CentroidRow> centroids;      // per manifold row with has_centroid_row, in order
  std::vector<RockingRow> rocking;         // per manifold row with has_rocking_rows, in order
  std::vector<FreeRow> free;               // per point row with is_free_row, in order
  // Per worker: where its share of each list begins (split_sweep_rows).
  struct Starts {
    size_t centroids, rocking, free;
  };
  std::vector<Starts> starts;
};
// Makes the copies, reading the manifolds' accumulated impulses; each of
// the executor's workers (null: the caller's thread) a contiguous share of
// the manifolds, at the places the shares before it leave.
void split_sweep_rows(const std::vector<ManifoldRow>& manifolds, const std::vector<PointRow>& rows, SweepRows& out,
                      Executor* executor);
// Writes the copies' accumulated impulses back to the manifolds.
void write_back_impulses(const std::vector<ManifoldRow>& manifolds, const std::vector<PointRow>& rows,
                         const SweepRows& copies, Executor* executor);

// A manifold's accumulated impulses, where the iterations keep them: in the
// contact's manifold for a ManifoldRow, in ManifoldImpulses for a copy.
inline Fixed& normal_impulse(const ManifoldRow& m, size_t i) { return m.manifold->points[i].normal_impulse; }
inline Fixed (&friction_impulse(const ManifoldRow& m))[2] { return m.manifold->friction_impulse; }
inline Fixed& twist_impulse(const ManifoldRow& m) { return m.manifold->twist_impulse; }
inline Fixed (&rolling_impulse(const ManifoldRow& m))[2] { return m.manifold->rolling_impulse; }
template <class Copy>
Fixed& normal_impulse(const Copy& m, size_t i) {
  return m.impulses->normal[i];
}
template <class Copy>
Fixed (&friction_impulse(const Copy& m))[2] {
  return m.impulses->friction;
}
template <class Copy>
Fixed& twist_impulse(const Copy& m) {
  return m.impulses->twist;
}
template <class Copy>
Fixed (&rolling_impulse(const Copy& m))[2] {
  return m.impulses->rolling;
}

// Inside the solver no product or sum can leave the Q32.32 range, so they
// skip the saturation test (mul_in_range, sum_products_in_range; the checked
// build still faults): the envelope bounds speeds by 500 m/s and 100 rad/s,
// sizes by 50 m (arms below 100 m), 1 / m by 100 kg^-1 and I^-1 by ~10^6
// (kg m^2)^-1, so J v stays below ~10^5 and an impulse's velocity change
// below the envelope's speeds; the range is 2^31 (~2.1e9).

// J (a, b) for either rate of the two bodies: nine exact products, rounded
// once; six when one body is still (its angular rate's three are 0, its
// linear rate adds 0 to the difference). Inlined always, as apply_rate:
// with the still cases gcc calls both out of line, and the calls show in
// the iterations' time.
[[gnu::always_inline]] inline Fixed relative_rate(const BodyRates& a, const BodyRates& b, const Jacobian& j,
                                                  bool a_still = false, bool b_still = false) {
  const Vec3 dv = b.linear - a.linear;
  if (a_still || b_still) {
    const BodyRates& mover = a_still ? b : a;
    const Vec3 w = a_still ? mover.angular : -mover.angular;
    const Vec3& arm = a_still ? j.arm_b : j.arm_a;
    const Fixed rates[6] = {dv.x, dv.y, dv.z, w.x, w.y, w.z};
    const Fixed rows[6] = {j.direction.x, j.direction.y, j.direction.z, arm.x, arm.y, arm.z};
    return sum_products_in_range(rates, rows);
  }
  const Fixed rates[9] = {dv.x, dv.y, dv.z, b.angular.x, b.angular.y, b.angular.z,
                          -a.angular.x, -a.angular.y, -a.angular.z};
  const Fixed rows[9] = {j.direction.x, j.direction.y, j.direction.z, j.arm_b.x, j.arm_b.y, j.arm_b.z,
                         j.arm_a.x, j.arm_a.y, j.arm_a.z};
  return sum_products_in_range(rates, rows);
}

// v lambda, each component rounded once. Inlined always: out of line, the
// vector goes through the stack both ways, which costs about what its three
// products do.
[[gnu::always_inline]] inline Vec3 scaled(Vec3 v, Fixed lambda) {
  return {mul_in_range(v.x, lambda), mul_in_range(v.y, lambda), mul_in_range(v.z, lambda)};
}

// Applies lambda along J to one rate of the two bodies. A zero impulse
// changes nothing (every product rounds to 0, and v - 0 = v): it is skipped,
// which at rest is most of the tangent, twist and rocking rows; so is a
// still body's side (its parts are zero).
// Two bodies of equal mass (a wall's bricks) have d / m_a = d / m_b, so
// their linear changes are the same three products: taken once.
[[gnu::always_inline]] inline void apply_rate(BodyRates& a, BodyRates& b, const Jacobian& j, Fixed lambda,
                                              bool a_still = false, bool b_still = false) {
  if (lambda == Fixed{}) return;
  Vec3 linear_a;
  if (!a_still) {
    linear_a = scaled(j.linear_a, lambda);
    a.linear -= linear_a;
    a.angular -= scaled(j.turn_a, lambda);
  }
  if (!b_still) {
    b.linear += !a_still && j.linear_b == j.linear_a ? linear_a : scaled(j.linear_b, lambda);
    b.angular += scaled(j.turn_b, lambda);
  }
}

// The same for an angular part: (w_b - w_a) . u as three exact products
// rounded once. The difference is taken first, as relative_rate takes
// v_b - v_a: in range it is exact, so the exact sum, and its rounding, are
// those of the six products w_b . u - w_a . u.
inline Fixed relative_spin(const SolverBody& a, const SolverBody& b, const AngularPart& j) {
  const Vec3 dw = b.velocity.angular - a.velocity.angular, u = j.axis;
  const Fixed rates[3] = {dw.x, dw.y, dw.z};
  const Fixed rows[3] = {u.x, u.y, u.z};
  return sum_products_in_range(rates, rows);
}
inline void apply_spin(SolverBody& a, SolverBody& b, const AngularPart& j, Fixed lambda) {
  if (lambda == Fixed{}) return;  // no change, as in apply_rate
  if (!a.still) a.velocity.angular -= scaled(j.turn_a, lambda);
  if (!b.still) b.velocity.angular += scaled(j.turn_b, lambda);
}

inline Fixed relative_velocity(const SolverBody& a, const SolverBody& b, const Jacobian& j) {
  return relative_rate(a.velocity, b.velocity, j, a.still, b.still);
}
inline void apply_impulse(SolverBody& a, SolverBody& b, const Jacobian& j, Fixed lambda) {
  apply_rate(a.velocity, b.velocity, j, lambda, a.still, b.still);
}
// J v and an impulse for either part (solve_disc takes both).
inline Fixed relative_velocity(const SolverBody& a, const SolverBody& b, const AngularPart& j) {
  return relative_spin(a, b, j);
}
inline void apply_impulse(SolverBody& a, SolverBody& b, const AngularPart& j, Fixed lambda) {
  apply_spin(a, b, j, lambda);
}

// One point row on either rate: the accumulated impulse (normal or split)
// moves toward the target rate and stays >= 0 unless the row is an equality.
// (The still flags as in relative_rate and apply_rate.)
inline void solve_point(BodyRates& a, BodyRates& b, const Jacobian& j, Fixed& accumulated, Fixed target,
                        bool equality = false, bool a_still = false, bool b_still = false) {
  Fixed total = accumulated + mul_in_range(j.mass, target - relative_rate(a, b, j, a_still, b_still));
  if (!equality) total = max(total, Fixed{});
  const Fixed delta = total - accumulated;
  accumulated = total;
  apply_rate(a, b, j, delta, a_still, b_still);
}
inline void solve_normal(SolverBody& a, SolverBody& b, const PointRow& row) {
  solve_point(a.velocity, b.velocity, row.normal, row.point->normal_impulse, row.velocity_target, false, a.still,
              b.still);
}
inline void solve_normal(SolverBody& a, SolverBody& b, const FreeRow& row) {
  solve_point(a.velocity, b.velocity, row.normal, *row.impulse, row.velocity_target, false, a.still, b.still);
}
inline void solve_push(SolverBody& a, SolverBody& b, const PointRow& row) {
  solve_point(a.push, b.push, row.normal, row.point->split_impulse, row.push_target, row.impact, a.still, b.still);
}

// A contact row of a jointed body pushed one way in the last position
// pass (position_passes.cpp, one_way_pushes): the body below stands still for the
// one above, which takes the whole push (its mass alone in `mass`).
struct OneWayPush {
  uint32_t row;       // in the solve's point rows
  bool a_below;       // a holds b up (else b holds a up)
  Fixed mass;         // 1 / (1 / m + (r x n) . I^-1 (r x n)) of the body above
};
inline void solve_push_one_way(SolverBody& a, SolverBody& b, const PointRow& row, const OneWayPush& one_way) {
  Jacobian j = row.normal;
  j.mass = one_way.mass;
  solve_point(a.push, b.push, j, row.point->split_impulse, row.push_target, row.impact, one_way.a_below || a.still,
              !one_way.a_below || b.still);
}

// A manifold in the shock step's order: by the support level of its
// higher body, then by its cluster, then by its index.
struct ShockEntry {
  uint32_t cluster;  // the lowest slot of the bodies of its rank that the rank's passes couple to it
  uint32_t level;
  uint32_t index;
  bool holds_up;  // between ranks: the lower body holds the other up against gravity
};

// order_manifolds' working memory, kept from step to step.
struct ShockOrderWorkspace {
  std::vector<uint32_t> parent;       // per slot: union-find parent (clusters)
  std::vector<uint32_t> level_start;  // per level + 1: where its entries begin (a counting sort)
  std::vector<ShockEntry> unsorted;
};

// The shock step's bodies held up through several contacts, and each
// one's support manifolds (shock.cpp, group_supports).
struct SupportGroups {
  std::vector<uint8_t> several;         // per slot: held up through more than one contact
  std::vector<uint32_t> begin;          // per slot + 1: where a body's support manifolds begin in `entries`
  std::vector<uint32_t> entries;        // positions in the shock order, grouped by the body they hold up
  std::vector<uint32_t> fill;           // per slot, while grouping (counts, then fill positions)
};

// What the shock step needs to give islands the iterations hold their
// velocities back (shock_groups.h).
struct ShockGroups {
  std::vector<BodyRates> before_shock;  // per slot: the iterations' velocity
  std::vector<uint32_t> unconverged;    // bodies whose velocity a rank's last pass still changed (with repeats)
  std::vector<BodyRates> before_last_pass;  // the rank's bodies' velocities before its last pass
  std::vector<BodyRates> after_passes;      // moving_before_passes's keep of the velocities the passes left
  std::vector<uint32_t> parent;         // per slot: union-find parent (an island's root is its lowest slot)
  std::vector<uint8_t> flags;           // per root: unconverged, moving
};

// A body of the rank the shock step is solving, and its velocity from the
// iterations.
struct RankBody {
  uint32_t body;
  BodyRates velocity;
};


// The contacts' accumulated impulses, in contact order, kept aside and put
// back: the collision pass keeps its own, the shock step corrects this
// step's velocities only.
void save_impulses(const std::vector<Contact>& contacts, std::vector<Fixed>& out);
void restore_impulses(const std::vector<Fixed>& saved, std::vector<Contact>& contacts);

// Warm starting: a row's, or a manifold's friction, twist and rolling
// rows', accumulated impulses from last step applied again.
inline void warm_start_point(SolverBody& a, SolverBody& b, const PointRow& row) {
  apply_impulse(a, b, row.normal, row.point->normal_impulse);
}
inline void warm_start_manifold(SolverBody& a, SolverBody& b, const ManifoldRow& m) {
  apply_impulse(a, b, m.tangent[0], m.manifold->friction_impulse[0]);
  apply_impulse(a, b, m.tangent[1], m.manifold->friction_impulse[1]);
  apply_spin(a, b, m.twist, m.manifold->twist_impulse);
  if (m.rolling_limit > Fixed{}) {
    apply_spin(a, b, m.rolling[0], m.manifold->rolling_impulse[0]);
    apply_spin(a, b, m.rolling[1], m.manifold->rolling_impulse[1]);
  }
}

// Friction (tangents and twist) at the centroid of a manifold, within the
// static or dynamic cone of its total normal impulse. Row: ManifoldRow or
// FrictionRow.
template <class Row>
void solve_friction(SolverBody& a, SolverBody& b, const Row& m);
// The centroid row: equal shares of a normal impulse through the centroid.
// Row: ManifoldRow or CentroidRow.
template <class Row>
void solve_manifold_normal(SolverBody& a, SolverBody& b, const Row& m);
// The rocking rows: relative rotation about the in-plane axes, no point
// pulling. Row: ManifoldRow or RockingRow.
template <class Row>
void solve_rocking(SolverBody& a, SolverBody& b, const Row& m);
// One pass over a manifold: friction, the centroid row, rocking, then its
// points (in alternating direction with the pass).
void solve_manifold(std::vector<SolverBody>& bodies, std::vector<PointRow>& rows, const ManifoldRow& m, int pass);

}  // namespace bitstep
