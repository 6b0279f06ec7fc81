// The shock step's solves of one body against bodies already made
// immovable (shock.cpp): a manifold's rows made one-sided, and the glue
// that stops a body on its supports as one block. Internal to core/.
#pragma once

#include <cstdint>
#include <vector>

#include "core/glue_face.h"
#include "core/solver_rows.h"

namespace bitstep {

// Drops the turn of body a (freeze_a) or b from every row of m (the points'
// normal rows in `rows`, the centroid, friction, twist, rolling and rocking
// rows) and recomputes each effective mass from the other body alone; sets
// m.one_sided.
void make_one_sided(ManifoldRow& m, std::vector<PointRow>& rows, const SolverBody& a, const SolverBody& b,
                    bool freeze_a);

// Glues `mover` to the rigid motion of `support` through one face contact
// m (3 or 4 points) when the contact can deliver it: true and the rows'
// accumulated impulses rewritten, else false and nothing changed.
// `face`: this manifold's, kept in `faces` between calls.
bool glue(SolverBody& mover, const SolverBody& support, const Body& body, bool mover_is_b, const ManifoldRow& m,
          std::vector<PointRow>& rows, GlueFace& face, GlueFaces& faces);

// Glues `mover` to all its supports at once (the manifolds
// manifolds[entries[0 .. entry_count)]), taken as one face, when they
// share one rigid motion and face the same way and the face can deliver
// it; nothing changed otherwise. level: the shock ranks (the mover is the
// higher-ranked body of each manifold).
// `face`: the mover's, kept in `faces` between calls.
GlueAll glue_all(SolverBody& mover, const Body& body, const std::vector<SolverBody>& solver_bodies,
              const std::vector<Body>& bodies, const uint32_t* entries, size_t entry_count,
              const std::vector<uint32_t>& level, const std::vector<ManifoldRow*>& manifolds,
              std::vector<PointRow>& rows, GlueFace& face, GlueFaces& faces);

}  // namespace bitstep
