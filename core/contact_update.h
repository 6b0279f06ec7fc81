// The narrowphase pass of the step: this step's contacts from the broadphase
// pairs, each matched with last step's contact of the same key so that its
// points inherit their accumulated impulses by feature id.
#pragma once

#include <array>
#include <cstdint>
#include <vector>

#include "core/broadphase.h"
#include "core/body.h"
#include "core/contact.h"
#include "core/executor.h"

namespace bitstep {

// Last step's narrowphase results, for exact reuse. collide() is a pure
// function of the two shapes, their world poses and the margin: a shape pair
// whose bodies' poses and margin are bit-identical to last step's gets last
// step's result as collide() wrote it (impulses are then inherited as
// always), so a step computes the same bits with or without the cache. A
// standing structure (no pose moves by a bit) skips its collision tests,
// and when its shape pairs are last step's, in order, the entries are
// rewritten where they lie (one buffer, not two).
// Not state: the owner drops a slot's entries when its body is removed (the
// slot may be reused at the same pose by other shapes), and a restored world
// starts without any.
struct NarrowphaseCache {
  // What collide() writes into a fresh manifold (it never touches the
  // impulses): the normal, the count and the points' geometry, all four.
  struct Found {
    Vec3 normal;
    int point_count = 0;  // 0: the shapes were apart
    struct Point {
      Vec3 position;
      Fixed depth;
      FeatureId feature = 0;
    };
    std::array<Point, max_manifold_points> points{};
  };
  struct Entry {
    ContactKey key;
    Fixed margin;
    Found found;
  };
  std::vector<Entry> entries;  // last step's, sorted by key
  std::vector<Entry> next;     // this step's, while they are found
  std::vector<Pose> poses;     // per slot: the pose at last step's narrowphase
  std::vector<uint8_t> still;  // per slot: this step's pose is that one, bit for bit
  // This step's shape pairs to test, in key order (workspace of
  // update_contacts): each one's key, margin, and the entry it is restored
  // from, or none: then collide() writes its fresh manifold into
  // collided[slot].
  struct Test {
    static constexpr size_t none = SIZE_MAX;
    ContactKey key;
    Fixed margin;
    size_t cached = none;
    size_t slot = 0;
  };
  std::vector<Test> tests;
  std::vector<Manifold> collided;
  // The shapes of the bodies in a test to run, placed in the world once
  // each (a body is in several pairs), a box with its rotation matrix:
  // per slot, where its shapes begin in `placed` (none: not placed).
  std::vector<size_t> first_placed;
  std::vector<WorldShape> placed;
  std::vector<Mat33> placed_axes;
  bool enabled = true;         // off: every pair is tested (the reuse tests compare both)
  uint64_t reused = 0, tested = 0;  // shape pairs over the world's life (bench figures, not state)
};

// `contacts` holds last step's contacts on entry and this step's on return,
// both sorted by key. `previous` is workspace (last step's contacts are moved
// there while this step's are found), kept by the caller so that a settled
// step allocates nothing. `turn_speed` holds, per slot, how fast the body's
// farthest point moves by its rotation alone (|w| r, m/s).
void update_contacts(const std::vector<Body>& bodies, const std::vector<BodyPair>& pairs, const Settings& settings,
                     const std::vector<Fixed>& turn_speed, std::vector<Contact>& contacts,
                     std::vector<Contact>& previous, NarrowphaseCache& cache, Executor* executor = nullptr);

}  // namespace bitstep
