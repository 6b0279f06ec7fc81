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
    if (m.count >= 2) plan.items[several_points].push_back(i);
    if (m.rocking[0].active || m.rocking[1].active) plan.items[rocking_rows].push_back(i);
  }
  for (uint32_t i = 0; i < rows.size(); ++i) {
    if (!rows[i].in_resting_face) plan.items[free_rows].push_back(i);
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
// scene (slabs by position) made the workers hand bodies to each other on
// every row, and two workers ran slower than one. A pile whose bodies'
// slots are scattered in space shares most of its bodies; its workers wait
// more. The shares decide only how fast the sweeps run, never what they
// compute.
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
// wall64 shares 46 of 2,080, pyramid20 15 of 210, the thrown pile 45 of 75).
// Then the shares of all the workers.
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
                  const std::vector<PointRow>& rows, const std::vector<ManifoldRow>& manifolds, OrderedSweeps& plan) {
  plan.item.clear();
  plan.place_a.clear();
  plan.place_b.clear();
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
    for (size_t i = 0; i < n; ++i) {
      const uint32_t item = items[steps[s].reversed ? n - 1 - i : i];
      const uint32_t body_a = manifold_items ? manifolds[item].a : rows[item].a;
      const uint32_t body_b = manifold_items ? manifolds[item].b : rows[item].b;
      plan.updates_of[worker_of[item]].push_back(static_cast<uint32_t>(plan.item.size()));
      plan.item.push_back(item);
      plan.place_a.push_back(place_of(body_a));
      plan.place_b.push_back(place_of(body_b));
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

// One update. An immovable side is the worker's spare copy of it (with
// zero inverse mass and inertia the update writes the same values back).
void update(const SweepRun& run, SweepKind kind, uint32_t item, uint32_t ia, uint32_t ib, bool movable_a,
            bool movable_b, SolverBody& spare_a, SolverBody& spare_b) {
  std::vector<SolverBody>& bodies = *run.bodies;
  std::vector<PointRow>& rows = *run.rows;
  if (!movable_a) spare_a = bodies[ia];
  if (!movable_b) spare_b = bodies[ib];
  SolverBody& a = movable_a ? bodies[ia] : spare_a;
  SolverBody& b = movable_b ? bodies[ib] : spare_b;
  switch (kind) {
    case SweepKind::warm_point: warm_start_point(a, b, rows[item]); break;
    case SweepKind::warm_manifold: warm_start_manifold(a, b, (*run.manifolds)[item]); break;
    case SweepKind::friction: solve_friction(a, b, (*run.manifolds)[item]); break;
    case SweepKind::manifold_normal: solve_manifold_normal(a, b, (*run.manifolds)[item]); break;
    case SweepKind::rocking: solve_rocking(a, b, (*run.manifolds)[item]); break;
    case SweepKind::point_normal: solve_normal(a, b, rows[item]); break;
    case SweepKind::point_push: solve_push(a, b, rows[item]); break;
  }
}

void run_worker(void* context, int worker) {
  SweepRun& run = *static_cast<SweepRun*>(context);
  if (worker >= run.workers) return;
  OrderedSweeps& plan = *run.plan;
  SolverBody spare_a, spare_b;
  for (size_t s = 0; s < run.step_count; ++s) {
    const SweepKind kind = run.steps[s].kind;
    const bool manifold_item = on_manifolds(kind);
    const std::vector<uint32_t>& updates = plan.updates_of[worker];
    const size_t at = s * static_cast<size_t>(run.workers) + static_cast<size_t>(worker);
    const uint32_t begin = s == 0 ? 0 : plan.list_end[at - static_cast<size_t>(run.workers)];
    for (uint32_t k = begin; k < plan.list_end[at]; ++k) {
      const uint32_t u = updates[k];
      const uint32_t pa = plan.place_a[u], pb = plan.place_b[u];
      const uint32_t item = plan.item[u];
      const uint32_t ia = manifold_item ? (*run.manifolds)[item].a : (*run.rows)[item].a;
      const uint32_t ib = manifold_item ? (*run.manifolds)[item].b : (*run.rows)[item].b;
      const bool wait_a = pa < OrderedSweeps::no_wait, wait_b = pb < OrderedSweeps::no_wait;
      if (wait_a) wait_for(plan.progress[ia], pa);
      if (wait_b) wait_for(plan.progress[ib], pb);
      update(run, kind, item, ia, ib, pa != OrderedSweeps::immovable, pb != OrderedSweeps::immovable, spare_a, spare_b);
      if (wait_a) plan.progress[ia].store(pa + 1, std::memory_order_release);
      if (wait_b) plan.progress[ib].store(pb + 1, std::memory_order_release);
    }
  }
}

}  // namespace

bool run_ordered_sweeps(Executor& executor, const std::vector<SweepStep>& steps, const std::vector<uint8_t>& movable, std::vector<SolverBody>& bodies,
                        std::vector<PointRow>& rows, const std::vector<ManifoldRow>& manifolds, OrderedSweeps& plan) {
  list_items(rows, manifolds, plan);
  const int workers = std::min(executor.workers(), max_workers);
  if (!share_out(workers, movable, rows, manifolds, plan)) return false;
  plan_updates(steps.data(), steps.size(), workers, movable, rows, manifolds, plan);
  if (plan.progress_size < bodies.size()) {
    plan.progress = std::make_unique<std::atomic<uint32_t>[]>(bodies.size());
    plan.progress_size = bodies.size();
  }
  for (size_t i = 0; i < bodies.size(); ++i) plan.progress[i].store(0, std::memory_order_relaxed);
  SweepRun run{steps.data(), steps.size(), workers, &bodies, &rows, &manifolds, &plan};
  executor.run(run_worker, &run);
  ++plan.shared_runs;
  return true;
}

}  // namespace bitstep
