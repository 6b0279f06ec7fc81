// Shock propagation (Guendelman, Bridson and Fedkiw), the last pass of the
// velocity solve: rank by rank upward from the ground and sideways from
// walls (shock_levels.h), every body ranked below is immovable (infinite
// mass), so each body is stopped against its supports exactly instead of
// sharing the correction with them, and a stack's column of contacts
// converges in one pass however tall it is. Bodies without support are
// left as the iterations left them. Internal to core/.
#pragma once

#include <vector>

#include "core/contact.h"
#include "core/joint_solver.h"
#include "core/solver_scratch.h"

namespace bitstep {

// Reads scratch.rows and scratch.manifolds, updates scratch.bodies'
// velocities, uses the scratch's shock vectors. In phases:
// shock_levels ranks the bodies; order_manifolds picks and sorts the
// manifolds; group_supports finds the bodies held up through several
// contacts; gather_rows saves the impulses the step may change; then rank by
// rank, and within a rank cluster by cluster (order_manifolds), passes over
// the cluster's manifolds until they converge (settle_unconverged_cluster
// where they do not), after which its bodies are immovable; last, the
// islands the iterations held where a cluster did not converge get the
// iterations' velocities back (shock_groups.h).
// A body held by a joint is left as the iterations left it (never ranked):
// the shock step solves contacts alone, and freezing one link of a chain
// or a ragdoll against its support would let the next link tear the joint
// or be frozen by it.
void propagate_shock(const Settings& settings, const std::vector<Body>& bodies, std::vector<Contact>& contacts,
                     const std::vector<JointRow>& joint_rows, SolverScratch& scratch);

// The phases, exposed for their tests.

// The manifolds the shock step solves (positions in manifold_rows), by
// (rank of the higher body, cluster, position); a cluster is the bodies of
// one rank joined by the rank's manifolds between them, numbered by its
// lowest slot. Both bodies ranked, and either
// within a rank, or the lower one holding the higher up, or a sideways
// contact within one height. Left to the iterations: contacts between
// heights that are not supports, those by which the higher-ranked body
// holds the lower up, and speculative (apart) ones that are not sideways.
void order_manifolds(const Settings& settings, const ShockLevels& levels, const std::vector<ManifoldRow>& manifold_rows,
                     std::vector<ShockEntry>& order, ShockOrderWorkspace& workspace);

// Bodies held up through more than one contact of `order` (by several
// bodies, or by several shapes of one: a table's four legs on the table
// below) are glued to all their supports at once (glue_all), else to one
// at a time (in a cluster held already whose supports part, not at all:
// the cluster is given up, shock.cpp). One neither glue can hold (its supports move differently, or
// its load's centre lies outside each contact alone) is left as the
// iterations left it: solved against each support in turn, one-sided, it
// would be driven toward whichever rises fastest and, through the rotation
// that gives it, the bodies above it faster still (launching the top bricks
// of a tall wall). Sideways contacts are not supports: a body pressed
// against a wall or a frozen neighbour is solved against it one-sided.
// Fills groups: several[body], and each such body's support manifolds
// (positions in `order`, in order) at entries[begin[body] .. begin[body + 1]).
void group_supports(size_t body_count, const std::vector<uint32_t>& level, const std::vector<ManifoldRow>& manifold_rows,
                    const std::vector<ShockEntry>& order, SupportGroups& groups);

// Points scratch.shock_manifolds at scratch.order's manifold rows and
// saves the contacts' impulses (scratch.shock_saved); restore_rows puts
// them back and drops the one-sided copies (one_sided_copy) and their point
// rows, appended to scratch.rows.
void gather_rows(std::vector<Contact>& contacts, SolverScratch& scratch);
void restore_rows(std::vector<Contact>& contacts, SolverScratch& scratch);
// A copy of the manifold at `position` of the shock order with body a (or
// b) immovable, its point rows copied to the end of scratch.rows;
// scratch.shock_manifolds[position] then points at it.
ManifoldRow& one_sided_copy(SolverScratch& scratch, size_t position, bool freeze_a);

// Whether manifold m (its rows in `rows`) touches and moves faster than
// `speed` (m/s) at the bodies' velocities: a point approaching, or the
// surfaces sliding or twisting at the manifold's centre. Judged for a
// cluster at its velocities before its passes, with the ranks below as the
// shock step left them: a box the iterations carried along on a rocking
// support, once the shock step has stopped the support, slides on it, and
// would keep sliding slowly for good if only approach were looked at.
bool moving_at_contact(const std::vector<SolverBody>& solver_bodies, const std::vector<PointRow>& rows,
                       const ManifoldRow& m, Fixed speed);

// Passes that only go round a cycle. In settled piles most ranks never
// converge: within a few passes their velocities cycle (a box pushed back
// and forth by rows whose impulses grow in opposite directions), and the
// rest of the shock_iterations passes go round and round (in a settled
// thrown pile, most of a rank's passes). Called
// after pass `pass` of a rank has run, with the rank's bodies. When the
// last `period` passes left the same velocities as the `period` before them
// (a whole period repeated; periods 2 and 4: a pass's point rows run in the
// direction of its parity, so an odd period is no cycle), returns the pass
// to go on after, last_pass - (last_pass - pass) % period: the rank ends in
// the phase of the cycle where running every pass would have left it. That
// is the same result unless the growing impulses would have reached a bound
// (a friction cone, the clamp at zero) in the passes skipped (a minority of
// the cycles in a settled pile). Else returns `pass`. history keeps the
// rank's velocities after its last 8 passes.
int skip_repeating_passes(const std::vector<SolverBody>& solver_bodies, const std::vector<RankBody>& rank,
                          std::vector<BodyRates>& history, int pass, int last_pass);

// A cluster of a rank whose passes did not converge: they end at an
// arbitrary point of an oscillation (a box on one corner leaning on a
// glued box of its own rank loses a little of its rotation each pass; a
// row whose point is a hair apart hands back the iterations' impulse and
// the next glue undoes it), and settled heaps would creep on what the last
// pass left. A cluster the iterations already hold (held_already: no
// sideways contact, and at every touching contact, against the ranks below
// as the shock step left them, no point approaching and no sliding or
// twisting faster than 1 mm/s) gets the iterations' velocities back
// (before_shock); any other keeps, body by body, whichever of its two
// velocities has the lower kinetic energy: the shock step may stop motion
// it did not finish solving, never add to it.
void settle_unconverged_cluster(const std::vector<Body>& bodies, const std::vector<RankBody>& before_shock,
                             bool held_already, std::vector<SolverBody>& solver_bodies);

}  // namespace bitstep
