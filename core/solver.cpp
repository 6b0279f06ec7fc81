#include "core/solver.h"

#include <algorithm>
#include <cstddef>

#include "core/contact_rows.h"
#include "core/held_islands.h"
#include "core/position_passes.h"
#include "core/shock.h"
#include "core/soft_step.h"
#include "core/tree_islands.h"

namespace bitstep {

namespace {

// Manifolds per worker below which the sweeps stay on one thread: waking the
// workers costs more than they save.
constexpr size_t min_parallel_manifolds = 32;

// One solve as its stages see it: the context, the pass, and what earlier
// stages decided for later ones.
struct Solve {
  const SolveContext& context;
  SolvePass kind;
  std::vector<PointRow>* rows = nullptr;  // this pass's rows (prepare_contacts)
  std::vector<ManifoldRow>* manifold_rows = nullptr;
  Executor* row_executor = nullptr;  // who builds and copies rows: the caller's thread alone with joints
  bool cached = false;    // the row cache serves this pass
  bool warm = false;      // the impulses start from last step's
  bool parallel = false;  // the sweeps run on the executor's workers
  bool copies = false;    // the iterations sweep the rows' copies (SweepRows)
  bool swept = false;     // the workers ran the warm start and the iterations
  int passes = 0;         // velocity passes over every row (plan_passes)

  const Settings& settings() const { return context.settings; }
  SolverScratch& scratch() const { return context.scratch; }
  std::vector<SolverBody>& bodies() const { return context.scratch.bodies; }
  std::vector<JointRow>& joint_rows() const { return context.joints.rows; }
  std::vector<TyreRow>& tyre_rows() const { return context.tyres.rows; }
};

void warm_start(std::vector<SolverBody>& bodies, const std::vector<PointRow>& rows,
                const std::vector<ManifoldRow>& manifold_rows) {
  for (const PointRow& row : rows) warm_start_point(bodies[row.a], bodies[row.b], row);
  for (const ManifoldRow& m : manifold_rows) warm_start_manifold(bodies[m.a], bodies[m.b], m);
}

// The iterations' point rows: those outside a resting face, whose rows the
// manifold's centroid and rocking rows stand for (build_rows), in order. A
// standing wall's are almost none: listed once, the ~220-byte rows are not
// loaded again in every pass only to be skipped.
void sweep_free_rows(std::vector<SolverBody>& bodies, std::vector<PointRow>& rows, const std::vector<uint32_t>& free_rows,
                     int pass) {
  const size_t n = free_rows.size();
  for (size_t k = 0; k < n; ++k) {
    PointRow& row = rows[free_rows[pass % 2 == 0 ? k : n - 1 - k]];
    solve_normal(bodies[row.a], bodies[row.b], row);
  }
}

// One sweep of the iterations over manifolds (rows or their sweep copies),
// in order.
template <class Row, class Solve>
void sweep_manifolds(std::vector<SolverBody>& bodies, const std::vector<Row>& rows, Solve solve) {
  for (const Row& m : rows) solve(bodies[m.a], bodies[m.b], m);
}

// The same over their copies (SweepRows::free).
void sweep_free_rows(std::vector<SolverBody>& bodies, const std::vector<FreeRow>& free, int pass) {
  const size_t n = free.size();
  for (size_t k = 0; k < n; ++k) {
    const FreeRow& row = free[pass % 2 == 0 ? k : n - 1 - k];
    solve_normal(bodies[row.a], bodies[row.b], row);
  }
}

void write_velocities(const std::vector<SolverBody>& solver_bodies, std::vector<Body>& bodies) {
  for (size_t i = 0; i < bodies.size(); ++i) {
    Body& body = bodies[i];
    if (!is_awake_dynamic(body)) continue;
    body.linear_velocity = solver_bodies[i].velocity.linear;
    body.angular_velocity = solver_bodies[i].velocity.angular;
  }
}


// The stages, in the order of the tables below.

// Each body's velocity and mass properties, as the rows read them.
void gather_bodies(const std::vector<Body>& bodies, std::vector<SolverBody>& out) {
  out.assign(bodies.size(), SolverBody{});
  for (size_t i = 0; i < bodies.size(); ++i) {
    const Body& body = bodies[i];
    if (!body.alive || body.asleep) continue;  // a sleeping body is immovable: zero inverse mass
    out[i] = {{body.linear_velocity, body.angular_velocity}, {}, body.inverse_mass, body.inverse_inertia_world};
  }
  for (SolverBody& body : out) body.still = immovable(body) && body.velocity == BodyRates{};
}

void gather(Solve& s) {
  gather_bodies(s.context.bodies, s.bodies());
  if (s.kind == SolvePass::collision) save_impulses(s.context.contacts, s.scratch().saved_impulses);
}

// The joints' and tyres' rows (they read no contact row; not in the
// collision pass, whose restitution acts on contacts alone). With joints
// the sweeps stay on this thread, and so do the rows and their copies:
// made on other workers they would only have to move here, and a scene
// with joints runs slower on two workers than on one.
void prepare_joints(Solve& s) {
  const SolveContext& c = s.context;
  s.joint_rows().clear();
  s.tyre_rows().clear();
  if (s.kind != SolvePass::collision) {
    prepare_joint_rows(c.settings, c.bodies, c.joints.joints, s.bodies(), s.joint_rows(), c.joints.tree);
    prepare_tyre_rows(c.bodies, s.bodies(), c.tyres.contacts, s.tyre_rows());
  }
  s.row_executor = s.joint_rows().empty() ? c.executor : nullptr;
}

// The contacts' rows (contact_rows.h). The collision pass (its manifolds
// are those that hit) builds every row, into rows of its own. A cached
// solve reuses the last cached solve's rows where it can: in place when it
// lays its contacts out as that solve did (a settled scene: one set of
// rows, not two), else from the other buffer, into which that solve's rows
// move aside.
void prepare_contacts(Solve& s) {
  const SolveContext& c = s.context;
  SolverScratch& scratch = s.scratch();
  RowCache& cache = scratch.row_cache;
  const bool collision = s.kind == SolvePass::collision;
  s.cached = cache.enabled && !collision;
  if (s.cached) {
    std::vector<BodyRowInputs>& now = scratch.body_row_inputs;
    now.resize(c.bodies.size());
    for (size_t i = 0; i < c.bodies.size(); ++i) {
      const Body& body = c.bodies[i];
      now[i] = {body.pose.position, s.bodies()[i].inverse_mass, s.bodies()[i].inverse_inertia,
                body.material.static_friction, body.material.dynamic_friction};
    }
    cache.compare_bodies(now);
  }
  if (!collision) {
    ++scratch.solves;
    scratch.rows_reused_from = s.cached ? cache.entries_solve : 0;
    if (s.cached) cache.entries_solve = scratch.solves;
  }
  const size_t row_count = plan_rows(c.settings, c.bodies, s.bodies(), c.contacts, s.kind, scratch.solved);
  s.rows = collision ? &scratch.collision_rows : &scratch.rows;
  s.manifold_rows = collision ? &scratch.collision_manifolds : &scratch.manifolds;
  const bool in_place = s.cached && scratch.rows_from_cached_solve && cache.same_layout(c.contacts, scratch.solved);
  if (!collision) {
    if (scratch.rows_from_cached_solve && !in_place) {
      std::swap(*s.rows, scratch.last_rows);
      std::swap(*s.manifold_rows, scratch.last_manifolds);
    }
    scratch.rows_from_cached_solve = false;
  }
  const RowSetup setup{c.settings,
                       c.bodies,
                       s.bodies(),
                       scratch.start_velocities,
                       c.contacts,
                       s.kind,
                       scratch.solved,
                       row_count,
                       *s.rows,
                       *s.manifold_rows,
                       s.cached ? &cache : nullptr,
                       in_place ? *s.rows : scratch.last_rows,
                       in_place ? *s.manifold_rows : scratch.last_manifolds,
                       in_place};
  prepare_rows(setup, s.row_executor);
  if (s.cached) {
    if (!in_place) std::swap(cache.entries, cache.next);
    scratch.rows_from_cached_solve = true;
  }
}

// How many velocity passes sweep every row, and which rows the passes
// after them sweep (held_islands.h; the collision pass: the world's).
void plan_passes(Solve& s) {
  HeldIslands& plan = s.scratch().held_islands;
  if (s.kind == SolvePass::collision) {
    plan.all_passes = s.settings().velocity_iterations;
    plan.more_passes = 0;
  } else {
    plan_held_islands(s.settings(), s.bodies(), s.scratch().start_velocities, *s.rows, *s.manifold_rows,
                      s.joint_rows(), s.tyre_rows(), plan);
  }
  s.passes = plan.all_passes;
}

// Which joint islands one tree solve holds (tree_islands.h).
void mark_tree_islands(Solve& s) {
  mark_tree_islands(s.bodies(), *s.manifold_rows, s.tyre_rows(), s.context.joints.tree, s.joint_rows(),
                    s.scratch().tree_islands);
}

// Without warm starting (and in the collision pass, whose impulses are its
// own) every row starts from zero.
void begin_impulses(Solve& s) {
  s.warm = s.settings().warm_starting && s.kind != SolvePass::collision;
  if (s.warm) return;
  for (JointRow& row : s.joint_rows()) {
    Joint& joint = *row.joint;
    joint.point_impulse = Vec3{};
    joint.distance_impulse = joint.limit_impulse = joint.hinge_impulse[0] = joint.hinge_impulse[1] = Fixed{};
    joint.angular_impulse = Vec3{};
    joint.motor_impulse = Fixed{};
  }
  for (const PointRow& row : *s.rows) row.point->normal_impulse = Fixed{};
  for (const ManifoldRow& m : *s.manifold_rows) {
    m.manifold->friction_impulse[0] = m.manifold->friction_impulse[1] = m.manifold->twist_impulse = Fixed{};
    m.manifold->rolling_impulse[0] = m.manifold->rolling_impulse[1] = Fixed{};
  }
}

// Where the sweeps run (the executor's workers where there is enough to
// share and neither a joint nor a tyre is in the solve), and whether they
// read the rows or their copies (SolverScratch::sweep_copies_from).
void split_rows(Solve& s) {
  const SolveContext& c = s.context;
  s.parallel = c.executor && c.executor->workers() > 1 && s.joint_rows().empty() && s.tyre_rows().empty() &&
               s.manifold_rows->size() >= min_parallel_manifolds * static_cast<size_t>(c.executor->workers());
  s.copies = s.manifold_rows->size() >= s.scratch().sweep_copies_from;
  if (s.copies) split_sweep_rows(*s.manifold_rows, *s.rows, s.scratch().sweep_rows, s.row_executor);
}

// The warm start and the iterations on the workers: the same sweeps, in
// the same order for every body (ordered_sweeps.h). Where the plan cannot
// share them, the stages after run them on this thread.
void sweep_on_workers(Solve& s) {
  if (!s.parallel) return;
  SolverScratch& scratch = s.scratch();
  const std::vector<Body>& bodies = s.context.bodies;
  std::vector<SweepStep>& steps = scratch.sweeps.steps;
  steps.clear();
  if (s.warm) steps.insert(steps.end(), {{SweepKind::warm_point, false}, {SweepKind::warm_manifold, false}});
  for (int pass = 0; pass < s.passes; ++pass) {
    steps.insert(steps.end(), {{SweepKind::friction, false},
                               {SweepKind::manifold_normal, false},
                               {SweepKind::rocking, false},
                               {SweepKind::point_normal, pass % 2 == 1}});
  }
  std::vector<uint8_t>& movable = scratch.sweeps.movable;
  movable.resize(bodies.size());
  for (size_t i = 0; i < bodies.size(); ++i) movable[i] = is_awake_dynamic(bodies[i]) ? 1 : 0;
  s.parallel = s.swept = run_ordered_sweeps(*s.context.executor, steps, movable, s.bodies(), *s.rows,
                                            *s.manifold_rows, s.copies ? &scratch.sweep_rows : nullptr, scratch.sweeps);
}

void warm_start(Solve& s) {
  if (s.swept) return;
  if (s.warm) warm_start_joints(s.bodies(), s.joint_rows());
  if (s.warm) warm_start(s.bodies(), *s.rows, *s.manifold_rows);
  warm_start_tyres(s.bodies(), s.tyre_rows(), s.warm);
}

// The velocity iterations on this thread: per pass the manifolds' friction,
// centroid and rocking rows, the free point rows, the joints, the tyres.
void iterate(Solve& s) {
  if (s.swept) return;
  SolverScratch& scratch = s.scratch();
  std::vector<SolverBody>& bodies = s.bodies();
  SweepRows& sweep_rows = scratch.sweep_rows;
  std::vector<uint32_t>& free_rows = scratch.free_rows;  // the copies list their own
  free_rows.clear();
  if (!s.copies) {
    for (uint32_t i = 0; i < s.rows->size(); ++i) {
      if (is_free_row((*s.rows)[i])) free_rows.push_back(i);
    }
  }
  for (int pass = 0; pass < s.passes; ++pass) {
    if (s.copies) {
      sweep_manifolds(bodies, sweep_rows.friction, solve_friction<FrictionRow>);
      sweep_manifolds(bodies, sweep_rows.centroids, solve_manifold_normal<CentroidRow>);
      sweep_manifolds(bodies, sweep_rows.rocking, solve_rocking<RockingRow>);
      sweep_free_rows(bodies, sweep_rows.free, pass);
    } else {
      sweep_manifolds(bodies, *s.manifold_rows, solve_friction<ManifoldRow>);
      sweep_manifolds(bodies, *s.manifold_rows, solve_manifold_normal<ManifoldRow>);
      sweep_manifolds(bodies, *s.manifold_rows, solve_rocking<ManifoldRow>);
      sweep_free_rows(bodies, *s.rows, free_rows, pass);
    }
    solve_joints(bodies, s.joint_rows(), s.context.joints.tree);
    solve_tyres(bodies, s.tyre_rows());
  }
}

// The copies' impulses back into the manifolds.
void write_back_copies(Solve& s) {
  if (s.copies) write_back_impulses(*s.manifold_rows, *s.rows, s.scratch().sweep_rows, s.row_executor);
}

// The passes after the held ones, over the islands in motion, on this
// thread (held_islands.h).
void moving_passes(Solve& s) {
  run_moving_passes(s.bodies(), *s.rows, *s.manifold_rows, s.joint_rows(), s.context.joints.tree, s.tyre_rows(),
                    s.scratch().held_islands);
}

// The tyres' impulses, back where they are kept.
void store_impulses(Solve& s) { store_tyre_impulses(s.tyre_rows(), s.context.tyres.contacts); }

// Islands whose joints ask for more velocity passes than the world's run
// them here, over their own rows (island_passes.h; with joints the sweeps
// above ran on this thread).
void island_passes(Solve& s) {
  IslandPasses& plan = s.scratch().island_passes;
  plan_island_passes(s.settings(), s.bodies(), *s.rows, *s.manifold_rows, s.joint_rows(), plan);
  run_extra_velocity_passes(s.bodies(), *s.rows, *s.manifold_rows, s.joint_rows(), s.context.joints.tree, plan);
}

// The collision pass keeps its impulses apart from the contact pass's.
void keep_collision_impulses(Solve& s) { restore_impulses(s.scratch().saved_impulses, s.context.contacts); }

void shock_step(Solve& s) {
  const SolveContext& c = s.context;
  if (c.settings.shock_propagation) propagate_shock(c.settings, c.bodies, c.contacts, s.joint_rows(), s.scratch());
}

// The position passes (position_passes.h), on the workers where the
// iterations ran there. When no row asks for a push (no overlap beyond the
// slop, no impact's displacement), every row computes a zero impulse from
// zero push velocities: skipping the passes gives the same bits.
void position_passes(Solve& s) {
  const Settings& settings = s.settings();
  SolverScratch& scratch = s.scratch();
  const std::vector<PointRow>& rows = *s.rows;
  const bool anything_to_push =
      std::any_of(rows.begin(), rows.end(), [](const PointRow& row) { return row.push_target != Fixed{}; }) ||
      joints_to_push(s.joint_rows());
  if (settings.baumgarte || !anything_to_push) return;
  std::vector<SweepStep>& steps = scratch.sweeps.steps;
  steps.clear();
  for (int pass = 0; pass < settings.position_iterations; ++pass) steps.push_back({SweepKind::point_push, pass % 2 == 1});
  if (s.parallel && run_ordered_sweeps(*s.context.executor, steps, scratch.sweeps.movable, s.bodies(), *s.rows,
                                       *s.manifold_rows, s.copies ? &scratch.sweep_rows : nullptr, scratch.sweeps)) {
    return;
  }
  push_apart(settings, s.bodies(), rows, s.joint_rows(), s.context.joints.tree, scratch.island_passes,
             scratch.positions);
}

void write_velocities(Solve& s) { write_velocities(s.bodies(), s.context.bodies); }

// The push velocities for the position integration (zero for the bodies
// that do not move).
void write_push(Solve& s) {
  PushVelocities& push = s.context.push;
  const std::vector<Body>& bodies = s.context.bodies;
  push.linear.assign(bodies.size(), Vec3{});
  push.angular.assign(bodies.size(), Vec3{});
  for (size_t i = 0; i < bodies.size(); ++i) {
    if (!is_awake_dynamic(bodies[i])) continue;
    push.linear[i] = s.bodies()[i].push.linear;
    push.angular[i] = s.bodies()[i].push.angular;
  }
}

// The soft step's substeps (soft_step.h), on this thread.
void soft_step(Solve& s) {
  warm_start_tyres(s.bodies(), s.tyre_rows(), s.warm);
  run_soft_step(s.settings(), s.context.bodies, s.bodies(),
                {*s.rows, *s.manifold_rows, s.joint_rows(), s.context.joints.tree, s.tyre_rows()},
                s.scratch().start_velocities, s.scratch().soft_step);
}

using Stage = void (*)(Solve&);

// The guendelman collision pass: restitution on the contacts that hit,
// nothing pushed, its impulses its own.
constexpr Stage collision_stages[] = {gather,           prepare_joints,  prepare_contacts, plan_passes,
                                      begin_impulses,   split_rows,      sweep_on_workers, warm_start,
                                      iterate,          write_back_copies, moving_passes,  store_impulses,
                                      island_passes,    keep_collision_impulses, write_velocities};
// The standard solve and the guendelman contact pass.
constexpr Stage contact_stages[] = {
    gather,         prepare_joints,   prepare_contacts, plan_passes,     mark_tree_islands, begin_impulses,
    split_rows,     sweep_on_workers, warm_start,       iterate,         write_back_copies, moving_passes,
    store_impulses, island_passes,    shock_step,       position_passes, write_velocities,  write_push};

// The soft step (Settings::soft_substeps).
constexpr Stage soft_stages[] = {gather,    prepare_joints, prepare_contacts, begin_impulses, soft_step,
                                 store_impulses, write_velocities, write_push};

}  // namespace

void solve_contacts(const SolveContext& context, SolvePass kind) {
  Solve solve{context, kind};
  if (kind == SolvePass::collision) {
    for (const Stage stage : collision_stages) stage(solve);
  } else if (context.settings.soft_substeps > 0) {
    for (const Stage stage : soft_stages) stage(solve);
  } else {
    for (const Stage stage : contact_stages) stage(solve);
  }
}

}  // namespace bitstep
