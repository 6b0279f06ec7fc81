// Where the shock step's answer is not kept. Its clusters' passes need not
// converge: in settled heaps they go round cycles (a box pushed back and
// forth by rows whose impulses grow in opposite directions), and the
// velocities the last pass leaves are arbitrary. Settled heaps would creep
// on them (in both pipelines, some by centimetres), while the iterations
// alone bring such a heap to exact rest. So an island (dynamic bodies
// joined by touching contacts) that the iterations already hold, none of
// its touching contacts approaching, sliding or twisting faster than
// `quiet`, and which the last pass of some cluster still changed, keeps the
// iterations' velocities (tests/core/resting_energy_tests.cpp: at most 3
// of 32 heaps at rest move over 1 mm). Convergence is judged island by
// island: judged rank by rank across the scene, a heap's unconverged ranks
// would send a stack metres away back to the iterations' velocities every
// step, and it would drift (resting_energy_tests.cpp: a stack beside such a
// heap stays put). Stacks, pyramids and walls converge and keep the shock
// step's answer: the iterations alone let them drift. Internal to core/.
#pragma once

#include <vector>

#include "core/solver_rows.h"

namespace bitstep {

// Before the shock step: keeps every body's velocity (the iterations'),
// and clears groups.unconverged, where the shock step lists the bodies
// whose velocity a cluster's last pass still changed.
void keep_velocities(const std::vector<SolverBody>& bodies, ShockGroups& groups);

// After it: finds the islands of the bodies listed there (union-find
// over the touching manifolds between two movable bodies) and gives every
// body of an island the iterations hold (moving_at_contact at the kept
// velocities, no faster than `quiet`) its kept velocity back. Returns how
// many bodies got it. Does nothing (and costs nothing) when every cluster
// converged.
size_t keep_iterations_where_held(const std::vector<ManifoldRow>& manifolds, const std::vector<PointRow>& rows,
                                  Fixed quiet, ShockGroups& groups, std::vector<SolverBody>& bodies);

}  // namespace bitstep
