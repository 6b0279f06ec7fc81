// The contacts' rows: which contacts a solve takes (plan_rows) and their
// point and manifold rows, built from the manifolds, the bodies and the
// pass (prepare_rows), with last step's pose-dependent parts reused where
// their inputs did not change by a bit (row_cache.h). The solve's prepare
// stage (solver.cpp). Internal to core/.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/body.h"
#include "core/contact.h"
#include "core/executor.h"
#include "core/row_cache.h"
#include "core/settings.h"
#include "core/solver_rows.h"

namespace bitstep {

// What a solve does (the pipelines of Settings::pipeline).
enum class SolvePass : uint8_t {
  standard,   // restitution at the moment of impact, resting contact, split impulse, shock step
  collision,  // guendelman: restitution on the velocities before this step's forces; impulses of
              // its own (the contact pass warm-starts from last step's contact pass)
  contact,    // guendelman: inelastic after the forces, split impulse, shock step
};

// The contacts this solve takes (an awake body; in the collision pass, only
// those that hit), in order, and where each one's point rows begin
// (`solved`); the number of point rows.
size_t plan_rows(const Settings& settings, const std::vector<Body>& bodies, const std::vector<SolverBody>& solver_bodies,
                 const std::vector<Contact>& contacts, SolvePass pass, std::vector<SolvedContact>& solved);

// What building the planned contacts' rows reads and writes: each solved
// contact's point rows at rows[first ..) and its manifold row at
// manifold_rows[slot]. Last step's parts come from last_rows and
// last_manifolds where the cache finds them. Those may be rows and
// manifold_rows themselves when the plan lays every contact where the last
// cached solve did (in_place; the cache's entries are then rewritten where
// they lie too): each slot then reads only its own last contents, before
// it writes them.
struct RowSetup {
  const Settings& settings;
  const std::vector<Body>& bodies;
  const std::vector<SolverBody>& solver_bodies;
  const std::vector<BodyRates>& start_velocities;  // per slot, before this step's forces
  std::vector<Contact>& contacts;
  SolvePass pass;
  const std::vector<SolvedContact>& solved;
  size_t row_count;
  std::vector<PointRow>& rows;
  std::vector<ManifoldRow>& manifold_rows;
  RowCache* cache;  // null: build every row
  const std::vector<PointRow>& last_rows;
  const std::vector<ManifoldRow>& last_manifolds;
  bool in_place;
};

// Sizes the rows and builds every planned contact's, on the executor's
// workers (null: the caller's thread) when there are enough: each
// contact's rows are a function of its own inputs, written into their own
// places, so the same bits on any number.
void prepare_rows(const RowSetup& setup, Executor* executor);

}  // namespace bitstep
