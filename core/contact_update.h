// The narrowphase pass of the step: this step's contacts from the broadphase
// pairs, each matched with last step's contact of the same key so that its
// points inherit their accumulated impulses by feature id.
#pragma once

#include <vector>

#include "core/broadphase.h"
#include "core/body.h"
#include "core/contact.h"

namespace bitstep {

// Last step's narrowphase results, for exact reuse. collide() is a pure
// function of the two shapes, their world poses and the margin: a shape pair
// whose bodies' poses and margin are bit-identical to last step's gets last
// step's manifold as collide() returned it (impulses are then inherited as
// always), so a step computes the same bits with or without the cache. A
// standing structure (no pose moves by a bit) skips its collision tests.
// Not state: the owner clears it whenever a body is created or removed (a
// reused slot may hold other shapes), and a restored world starts without it.
struct NarrowphaseCache {
  struct Entry {
    ContactKey key;
    Pose pose_a, pose_b;
    Fixed margin;
    Manifold found;  // point_count 0: the shapes were apart
  };
  std::vector<Entry> entries;  // last step's, sorted by key
  std::vector<Entry> next;     // this step's, while they are found
  bool enabled = true;         // off: every pair is tested (the reuse tests compare both)
  uint64_t reused = 0, tested = 0;  // shape pairs over the world's life (bench figures, not state)
};

// `contacts` holds last step's contacts on entry and this step's on return,
// both sorted by key. `previous` is workspace (last step's contacts are moved
// there while this step's are found), kept by the caller so that a settled
// step allocates nothing.
void update_contacts(const std::vector<Body>& bodies, const std::vector<BodyPair>& pairs, const Settings& settings,
                     std::vector<Contact>& contacts, std::vector<Contact>& previous, NarrowphaseCache& cache);

}  // namespace bitstep
