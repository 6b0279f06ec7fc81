// The solve's working memory, kept by the world between steps: the
// rows, the row cache, the sweeps' copies and plans, the shock step's and
// the position passes' workspaces. Internal to core/.
#pragma once

#include <cstddef>
#include <cstdint>
#include <vector>

#include "core/glue_face.h"
#include "core/held_islands.h"
#include "core/island_passes.h"
#include "core/ordered_sweeps.h"
#include "core/position_passes.h"
#include "core/row_cache.h"
#include "core/shock_levels.h"
#include "core/soft_step.h"
#include "core/solver_rows.h"
#include "core/stable_pool.h"
#include "core/tree_islands.h"

namespace bitstep {

// Kept by the world between steps so that a
// settled scene's step allocates nothing. Never state: every vector is
// rebuilt from the bodies and contacts before it is read.
struct SolverScratch {
  std::vector<BodyRates> start_velocities;  // per slot, before this step's forces (restitution measures these)
  std::vector<SolverBody> bodies;
  std::vector<PointRow> rows;
  std::vector<ManifoldRow> manifolds;
  std::vector<SolvedContact> solved;  // the contacts the rows are built for, in order
  std::vector<uint32_t> free_rows;     // the rows outside a resting face (the iterations' point rows)
  std::vector<PointRow> collision_rows;  // the collision pass's (guendelman), apart from the cached solve's
  std::vector<ManifoldRow> collision_manifolds;
  SoftStepScratch soft_step;  // the soft step's (soft_step.h)
  // The shock step (shock.cpp).
  ShockLevels levels;
  std::vector<ShockEntry> order;
  ShockOrderWorkspace order_workspace;
  SupportGroups supports;
  ShockGroups groups;
  std::vector<GlueAll> glued_to_all;      // per slot: glue_all's answer in the last pass
  std::vector<uint8_t> glued_alone;       // per slot: glued to its one support in the last pass
  std::vector<BodyRates> glued_velocity;  // per slot: the velocity the last glue gave it
  std::vector<ManifoldRow*> shock_manifolds;  // per position in the order: the row solved there
  StablePool<ManifoldRow> one_sided;          // copies made one-sided (shock_solve.h)
  std::vector<Fixed> shock_saved;             // the iterations' impulses (save_impulses) during the shock step
  size_t rows_before_shock = 0;               // rows past this are the one-sided copies' point rows
  std::vector<RankBody> rank_bodies;
  std::vector<BodyRates> rank_history;  // the rank's velocities after its last 8 passes (skip_repeating_passes)
  GlueFaces glue_faces;  // the glues' pose-only parts, measured once a step (shock_solve.h)
  std::vector<uint32_t> frozen_bodies;
  std::vector<Fixed> saved_inverse_mass;
  std::vector<Fixed> saved_impulses;  // the contact pass's, kept aside during the collision pass
  // Exact reuse of the pose-dependent row parts (row_cache.h): the last
  // cached solve's rows, moved aside before the next solve builds its own
  // unless it reuses them in place.
  RowCache row_cache;
  std::vector<BodyRowInputs> body_row_inputs;  // this solve's, per slot
  std::vector<PointRow> last_rows;
  std::vector<ManifoldRow> last_manifolds;
  bool rows_from_cached_solve = false;  // rows / manifolds hold the last cached solve's
  // The solves that build `manifolds`, numbered from 1; the one whose rows
  // this solve's were reused from (ManifoldRow::reused_from), 0 for none.
  uint64_t solves = 0, rows_reused_from = 0;
  // The iterations' copies of the manifold rows' parts, one array per
  // sweep: made from this many manifold rows (their 1,152 bytes each then
  // outgrow a core's cache, and the copy costs less than the rows streamed
  // three times a pass), on one thread or on several. Below it the sweeps
  // read the rows (there a copy costs more than it saves, the more so on two
  // threads). The same bits either way (replay_tests runs both).
  SweepRows sweep_rows;
  size_t sweep_copies_from = 2048;
  // The iterations and position passes on several workers (ordered_sweeps.h).
  OrderedSweeps sweeps;
  // The passes beyond the world's for islands whose joints ask for more.
  IslandPasses island_passes;
  HeldIslands held_islands;  // the velocity passes per island (held_islands.h)
  TreeIslands tree_islands;  // the joint islands one tree solve holds (tree_islands.h)
  PositionScratch positions;  // the position passes' (position_passes.h)
};

}  // namespace bitstep
