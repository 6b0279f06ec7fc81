// The solver's sweeps on several workers, with the bits of one thread.
//
// A sweep updates its items (manifolds or point rows) one after another,
// each reading and writing the velocities of its two bodies. Two updates
// that share no movable body commute exactly, so any schedule in which every
// body sees its updates in the one-thread order computes the same integers:
// the result does not depend on the number of workers or on timing, and no
// sweep order changes (a graph-colouring order, Box2D v3's, changes the
// results, and a tall wall solved in it collapses).
//
// The plan numbers, for each movable body, its updates in the one-thread
// order (a body's "places"); an update waits until its bodies' progress
// counters reach its places, runs, and advances them. Immovable sides
// (static or asleep: zero inverse mass and inertia, which every update leaves
// as it was) are neither waited for nor written: each update works on its
// own copy of them. Each worker owns a share of the manifolds (and their
// rows) in every sweep (share_out says which), so a body's data stays on one
// core except where shares meet, and runs its updates in one-thread order:
// an update waits only for updates before it in that order, so with every
// worker running no schedule deadlocks. Only bodies touched by two shares
// count places.
#pragma once

#include <atomic>
#include <cstdint>
#include <memory>
#include <vector>

#include "core/executor.h"

namespace bitstep {

struct SolverBody;
struct PointRow;
struct ManifoldRow;
struct SweepRows;

enum class SweepKind : uint8_t {
  warm_point,       // warm_start_point over every row
  warm_manifold,    // warm_start_manifold over every manifold
  friction,         // solve_friction over every manifold
  manifold_normal,  // solve_manifold_normal over manifolds of 2 points or more
  rocking,          // solve_rocking over manifolds with a rocking row
  point_normal,     // solve_normal over rows outside a resting face
  point_push,       // solve_push over every row
};

struct SweepStep {
  SweepKind kind;
  bool reversed;  // items from last to first
};

// Workers a plan can share its sweeps among; an executor's workers beyond
// these return at once.
constexpr int max_workers = 64;

// The plan's working memory, kept between steps (no allocation once warm).
struct OrderedSweeps {
  // Places below these are waited for.
  static constexpr uint32_t immovable = UINT32_MAX;    // a static or sleeping side
  static constexpr uint32_t no_wait = UINT32_MAX - 1;  // a body of one worker's share alone
  // One update: its item (a point row, a manifold, or a place in a sweep's
  // own array: SweepRows), its two bodies and their places.
  struct Update {
    uint32_t item, body_a, body_b, place_a, place_b;
  };
  // Per worker, its updates in one-thread order, sweep after sweep, each
  // worker's in one array it reads straight through (an update's record
  // looked up through an index into shared arrays made a worker running
  // every update slower than the one-thread loops); list_end[step * workers +
  // w]: where worker w's updates of the step end.
  std::vector<Update> updates_of[max_workers];
  std::vector<uint32_t> list_end;
  std::vector<uint8_t> manifold_worker, row_worker;  // each manifold's and row's worker
  std::vector<uint32_t> items[5];    // per list (list_of): items in one-thread order
  std::vector<uint32_t> next_place;  // per slot, while planning
  static constexpr uint8_t unowned = UINT8_MAX, shared = UINT8_MAX - 1;
  std::vector<uint8_t> owner;        // per slot, while planning: the worker whose share holds it, or shared
  std::vector<SweepStep> steps;      // the caller's, kept to reuse its memory
  // The plan's inputs as words (plan_inputs), this call's and the last
  // plan's: the same, the plan stands. plan_shared: the last plan shares the
  // sweeps (share_out).
  std::vector<uint32_t> key, last_key;
  bool plan_shared = false;
  std::vector<uint8_t> movable;      // the caller's: per slot, an awake dynamic body
  std::unique_ptr<std::atomic<uint32_t>[]> progress;  // per slot
  size_t progress_size = 0;
  uint64_t shared_runs = 0;  // runs on several workers, over the world's life
};

// Runs `steps` in order over the rows, spread over the executor's workers:
// the same integers as running them one after another on one thread.
// `movable` per slot: an awake dynamic body. Runs nothing and returns false
// when the workers would mostly wait for each other (more than 1 in 8 of
// the bodies touched by two shares: a pile whose slots are scattered in
// space); the caller then runs the sweeps on its own thread.
bool run_ordered_sweeps(Executor& executor, const std::vector<SweepStep>& steps, const std::vector<uint8_t>& movable,
                        std::vector<SolverBody>& bodies,
                        std::vector<PointRow>& rows, const std::vector<ManifoldRow>& manifolds,
                        const SweepRows* sweep_rows, OrderedSweeps& plan);

}  // namespace bitstep
