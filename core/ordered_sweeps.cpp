#include "core/ordered_sweeps.h"

#include <algorithm>
#include <thread>

#include "core/solver_rows.h"

namespace bitstep {

namespace {

// The item lists: every manifold, those of 2 points or more, those with a
// rocking row, the rows outside a resting face, every row.
enum List : size_t { all_manifolds, several_points, rocking_rows, free_rows, all_rows };

List list_of(SweepKind kind) {
  switch (kind) {
    case SweepKind::warm_point: return all_rows;
    case SweepKind::warm_manifold: return all_manifolds;
    case SweepKind::friction: return all_manifolds;
    case SweepKind::manifold_normal: return several_points;
    case SweepKind::rocking: return rocking_rows;
    case SweepKind::point_normal: return free_rows;
    case SweepKind::point_push: return all_rows;
  }
  return all_rows;
}

// Every list's items, in the one-thread order of their sweeps.
void list_items(const std::vector<PointRow>& rows, const std::vector<ManifoldRow>& manifolds, OrderedSweeps& plan) {
  for (std::vector<uint32_t>& list : plan.items) list.clear();
  for (uint32_t i = 0; i < manifolds.size(); ++i) {
    const ManifoldRow& m = manifolds[i];
    plan.items[all_manifolds].push_back(i);
    if (has_centroid_row(m)) plan.items[several_points].push_back(i);
    if (has_rocking_rows(m)) plan.items[rocking_rows].push_back(i);
  }
  for (uint32_t i = 0; i < rows.size(); ++i) {
    if (is_free_row(rows[i])) plan.items[free_rows].push_back(i);
    plan.items[all_rows].push_back(i);
  }
}

bool on_manifolds(SweepKind kind) {
  const List list = list_of(kind);
  return list == all_manifolds || list == several_points || list == rocking_rows;
}

// Gives each manifold (and its rows) to a worker: equal shares of the
// manifolds, contiguous in the one-thread order (contacts are in body
// order). Within a sweep every update of share w then comes before those of
// share w + 1, so share w + 1 can run a fraction of a sweep behind share w
// and rarely waits: in a wall or a pyramid, built row by row, only bodies on
// the rows where shares meet are touched by two. Shares cut across the
// scene (slabs by position) would make the workers hand bodies to each
// other on every row, and two workers would run slower than one. A pile
// whose bodies' slots are scattered in space shares most of its bodies; its
// workers wait more. The shares decide only how fast the sweeps run, never
// what they compute.
// Fills the shares of `workers` workers and each body's owner; returns
// the bodies shared by two shares, `moved` the bodies the sweeps move.
size_t assign_shares(size_t workers, const std::vector<uint8_t>& movable, const std::vector<PointRow>& rows,
                     const std::vector<ManifoldRow>& manifolds, OrderedSweeps& plan, size_t& moved) {
  const size_t count = manifolds.size();
  plan.manifold_worker.resize(count);
  plan.row_worker.resize(rows.size());
  for (size_t i = 0; i < count; ++i) {
    const uint8_t worker = static_cast<uint8_t>(i * workers / count);
    plan.manifold_worker[i] = worker;
    const size_t end = i + 1 < count ? manifolds[i + 1].first : rows.size();
    for (size_t r = manifolds[i].first; r < end; ++r) plan.row_worker[r] = worker;
  }
  // A body whose updates all belong to one worker sees them in that
  // worker's order already: only bodies touched by two count places.
  plan.owner.assign(movable.size(), OrderedSweeps::unowned);
  size_t shared = 0;
  moved = 0;
  for (size_t i = 0; i < count; ++i) {
    const uint8_t w = plan.manifold_worker[i];
    for (const uint32_t body : {manifolds[i].a, manifolds[i].b}) {
      uint8_t& owner = plan.owner[body];
      if (!movable[body] || owner == w || owner == OrderedSweeps::shared) continue;
      if (owner == OrderedSweeps::unowned) {
        owner = w;
        ++moved;
      } else {
        owner = OrderedSweeps::shared;
        ++shared;
      }
    }
  }
  return shared;
}

// Whether the contact order is local enough to share: split in two, at
// most 1 in 8 of the bodies the sweeps move are touched by both halves (a
// wall or a pyramid, built row by row, shares few; a small pile whose slots
// are scattered in space, most). Then the shares of all the workers.
bool share_out(int workers, const std::vector<uint8_t>& movable, const std::vector<PointRow>& rows,
               const std::vector<ManifoldRow>& manifolds, OrderedSweeps& plan) {
  size_t moved = 0;
  if (assign_shares(2, movable, rows, manifolds, plan, moved) * 8 > moved) return false;
  if (workers != 2) assign_shares(static_cast<size_t>(workers), movable, rows, manifolds, plan, moved);
  return true;
}

// Numbers every update's places, walking the sweeps in one-thread order,
// and lists each worker's updates per sweep.
void plan_updates(const SweepStep* steps, size_t step_count, int workers, const std::vector<uint8_t>& movable,
                  const std::vector<PointRow>& rows, const std::vector<ManifoldRow>& manifolds, bool copies,
                  OrderedSweeps& plan) {
  plan.next_place.assign(movable.size(), 0);
  const size_t w_count = static_cast<size_t>(workers);
  const auto place_of = [&](uint32_t body) {
    if (!movable[body]) return OrderedSweeps::immovable;
    return plan.owner[body] == OrderedSweeps::shared ? plan.next_place[body]++ : OrderedSweeps::no_wait;
  };
  for (size_t w = 0; w < w_count; ++w) plan.updates_of[w].clear();
  plan.list_end.resize(step_count * w_count);
  for (size_t s = 0; s < step_count; ++s) {
    const std::vector<uint32_t>& items = plan.items[list_of(steps[s].kind)];
    const bool manifold_items = on_manifolds(steps[s].kind);
    const std::vector<uint8_t>& worker_of = manifold_items ? plan.manifold_worker : plan.row_worker;
    const size_t n = items.size();
    // The centroid, rocking and free point rows' sweeps run on arrays of
    // their own (SweepRows), listed as their items are: an update names its
    // place in the list.
    const bool by_place = copies && (steps[s].kind == SweepKind::manifold_normal ||
                                     steps[s].kind == SweepKind::rocking || steps[s].kind == SweepKind::point_normal);
    for (size_t i = 0; i < n; ++i) {
      const uint32_t place = static_cast<uint32_t>(steps[s].reversed ? n - 1 - i : i);
      const uint32_t item = items[place];
      const uint32_t body_a = manifold_items ? manifolds[item].a : rows[item].a;
      const uint32_t body_b = manifold_items ? manifolds[item].b : rows[item].b;
      // Places are numbered in one-thread order: a's before b's.
      const uint32_t place_a = place_of(body_a);
      const uint32_t place_b = place_of(body_b);
      plan.updates_of[worker_of[item]].push_back({by_place ? place : item, body_a, body_b, place_a, place_b});
    }
    for (size_t w = 0; w < w_count; ++w) plan.list_end[s * w_count + w] = static_cast<uint32_t>(plan.updates_of[w].size());
  }
}

struct SweepRun {
  const SweepStep* steps;
  size_t step_count;
  int workers;
  std::vector<SolverBody>* bodies;
  std::vector<PointRow>* rows;
  const std::vector<ManifoldRow>* manifolds;
  const SweepRows* sweep_rows;
  OrderedSweeps* plan;
};

// Waits until the body's earlier updates are done (acquire: their writes
// are visible). Spins a little, then yields the core: with more workers than
// cores the update waited for may need this one's core.
void wait_for(const std::atomic<uint32_t>& progress, uint32_t place) {
  for (int spins = 0; progress.load(std::memory_order_acquire) != place; ++spins) {
    if (spins >= 64) std::this_thread::yield();
  }
}

// One update of a sweep of this kind on item i.
template <SweepKind kind>
void solve_item(SolverBody& a, SolverBody& b, uint32_t i, const SweepRun& run) {
  std::vector<PointRow>& rows = *run.rows;
  const SweepRows* copies = run.sweep_rows;
  const std::vector<ManifoldRow>& manifolds = *run.manifolds;
  if constexpr (kind == SweepKind::warm_point) warm_start_point(a, b, rows[i]);
  if constexpr (kind == SweepKind::warm_manifold) warm_start_manifold(a, b, manifolds[i]);
  if constexpr (kind == SweepKind::friction) {
    if (copies) solve_friction(a, b, copies->friction[i]);
    else solve_friction(a, b, manifolds[i]);
  }
  if constexpr (kind == SweepKind::manifold_normal) {
    if (copies) solve_manifold_normal(a, b, copies->centroids[i]);
    else solve_manifold_normal(a, b, manifolds[i]);
  }
  if constexpr (kind == SweepKind::rocking) {
    if (copies) solve_rocking(a, b, copies->rocking[i]);
    else solve_rocking(a, b, manifolds[i]);
  }
  if constexpr (kind == SweepKind::point_normal) {
    if (copies) solve_normal(a, b, copies->free[i]);
    else solve_normal(a, b, rows[i]);
  }
  if constexpr (kind == SweepKind::point_push) solve_push(a, b, rows[i]);
}

// A sweep's updates [begin, end) of one worker's list. An immovable side is
// the worker's spare copy of it (with zero inverse mass and inertia the
// update writes the same values back). The kind is a template argument:
// dispatched once per sweep, not once per update.
template <SweepKind kind>
void run_updates(const SweepRun& run, const OrderedSweeps::Update* begin, const OrderedSweeps::Update* end) {
  OrderedSweeps& plan = *run.plan;
  std::vector<SolverBody>& bodies = *run.bodies;
  SolverBody spare_a, spare_b;
  for (const OrderedSweeps::Update* u = begin; u != end; ++u) {
    const bool wait_a = u->place_a < OrderedSweeps::no_wait, wait_b = u->place_b < OrderedSweeps::no_wait;
    if (wait_a) wait_for(plan.progress[u->body_a], u->place_a);
    if (wait_b) wait_for(plan.progress[u->body_b], u->place_b);
    const bool movable_a = u->place_a != OrderedSweeps::immovable, movable_b = u->place_b != OrderedSweeps::immovable;
    if (!movable_a) spare_a = bodies[u->body_a];
    if (!movable_b) spare_b = bodies[u->body_b];
    solve_item<kind>(movable_a ? bodies[u->body_a] : spare_a, movable_b ? bodies[u->body_b] : spare_b, u->item, run);
    if (wait_a) plan.progress[u->body_a].store(u->place_a + 1, std::memory_order_release);
    if (wait_b) plan.progress[u->body_b].store(u->place_b + 1, std::memory_order_release);
  }
}

void run_worker(void* context, int worker) {
  const SweepRun& run = *static_cast<SweepRun*>(context);
  if (worker >= run.workers) return;
  const OrderedSweeps& plan = *run.plan;
  const OrderedSweeps::Update* updates = plan.updates_of[worker].data();
  const size_t workers = static_cast<size_t>(run.workers);
  for (size_t s = 0; s < run.step_count; ++s) {
    const size_t at = s * workers + static_cast<size_t>(worker);
    const OrderedSweeps::Update* begin = updates + (s == 0 ? 0 : plan.list_end[at - workers]);
    const OrderedSweeps::Update* end = updates + plan.list_end[at];
    switch (run.steps[s].kind) {
      case SweepKind::warm_point: run_updates<SweepKind::warm_point>(run, begin, end); break;
      case SweepKind::warm_manifold: run_updates<SweepKind::warm_manifold>(run, begin, end); break;
      case SweepKind::friction: run_updates<SweepKind::friction>(run, begin, end); break;
      case SweepKind::manifold_normal: run_updates<SweepKind::manifold_normal>(run, begin, end); break;
      case SweepKind::rocking: run_updates<SweepKind::rocking>(run, begin, end); break;
      case SweepKind::point_normal: run_updates<SweepKind::point_normal>(run, begin, end); break;
      case SweepKind::point_push: run_updates<SweepKind::point_push>(run, begin, end); break;
    }
  }
}

// Everything a plan is made from, as words: the workers, the sweeps, which
// bodies move, and each manifold's and row's two bodies and whether the
// row lies in a resting face.
void plan_inputs(int workers, const std::vector<SweepStep>& steps, const std::vector<uint8_t>& movable,
                 const std::vector<PointRow>& rows, const std::vector<ManifoldRow>& manifolds, bool copies,
                 std::vector<uint32_t>& key) {
  key.clear();
  key.push_back(static_cast<uint32_t>(workers));
  key.push_back(copies ? 1u : 0u);
  key.push_back(static_cast<uint32_t>(steps.size()));
  for (const SweepStep& s : steps) key.push_back(static_cast<uint32_t>(s.kind) * 2 + (s.reversed ? 1 : 0));
  key.push_back(static_cast<uint32_t>(movable.size()));
  for (const uint8_t m : movable) key.push_back(m);
  key.push_back(static_cast<uint32_t>(manifolds.size()));
  // Which lists a manifold is in: a count or a rocking row that changes
  // with the same bodies and rows changes the centroid and rocking lists.
  for (const ManifoldRow& m : manifolds) {
    key.insert(key.end(), {m.a, m.b, (has_centroid_row(m) ? 1u : 0u) + (has_rocking_rows(m) ? 2u : 0u)});
  }
  key.push_back(static_cast<uint32_t>(rows.size()));
  for (const PointRow& r : rows) key.insert(key.end(), {r.a, r.b, r.in_resting_face ? 1u : 0u});
}

}  // namespace

bool run_ordered_sweeps(Executor& executor, const std::vector<SweepStep>& steps, const std::vector<uint8_t>& movable,
                        std::vector<SolverBody>& bodies, std::vector<PointRow>& rows,
                        const std::vector<ManifoldRow>& manifolds, const SweepRows* sweep_rows, OrderedSweeps& plan) {
  const int workers = std::min(executor.workers(), max_workers);
  // The plan is a function of its inputs alone: made again only when one
  // of them changed (a standing wall's every step is the same plan, and
  // making it runs on one thread while the workers wait).
  const bool copies = sweep_rows != nullptr;
  plan_inputs(workers, steps, movable, rows, manifolds, copies, plan.key);
  if (plan.key != plan.last_key) {
    std::swap(plan.key, plan.last_key);
    list_items(rows, manifolds, plan);
    plan.plan_shared = share_out(workers, movable, rows, manifolds, plan);
    if (plan.plan_shared) plan_updates(steps.data(), steps.size(), workers, movable, rows, manifolds, copies, plan);
  }
  if (!plan.plan_shared) return false;
  if (plan.progress_size < bodies.size()) {
    plan.progress = std::make_unique<std::atomic<uint32_t>[]>(bodies.size());
    plan.progress_size = bodies.size();
  }
  for (size_t i = 0; i < bodies.size(); ++i) plan.progress[i].store(0, std::memory_order_relaxed);
  SweepRun run{steps.data(), steps.size(), workers, &bodies, &rows, &manifolds, sweep_rows, &plan};
  executor.run(run_worker, &run);
  ++plan.shared_runs;
  return true;
}

}  // namespace bitstep
