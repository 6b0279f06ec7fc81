// Contact manifolds: what the narrowphase finds between two shapes, and the
// solver state that persists with it from step to step.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "fixed/vec3.h"

namespace bitstep {

// A feature id names the pair of features (faces, edges, vertices) that made
// a contact point, so next step's point with the same id inherits the
// accumulated impulses (warm starting, qu3e's q3FeaturePair).
using FeatureId = uint32_t;

struct ContactPoint {
  Vec3 position;       // world, m: midway between the two surfaces
  Fixed depth;         // m, > 0 when the shapes overlap
  FeatureId feature = 0;
  // Accumulated impulses (N s), kept across steps for warm starting.
  Fixed normal_impulse;
  Fixed split_impulse;  // the penetration-recovery (pseudo-velocity) impulse, not warm started
};

inline constexpr int max_manifold_points = 4;

struct Manifold {
  Vec3 normal;  // unit, world, from shape A to shape B
  int point_count = 0;
  std::array<ContactPoint, max_manifold_points> points{};
  // Friction acts at the centroid of the points (N s, along the solver's
  // tangent basis of the normal) with a twist about the normal (N m s),
  // accumulated and warm-started like the normal impulses.
  Fixed friction_impulse[2];
  Fixed twist_impulse;
};

// A point of the manifold lies within touch_distance (m): depth >= -touch_distance.
// Islands, sleep and the shock step count such a contact as touching; one
// further apart is only speculative.
inline bool touches(const Manifold& m, Fixed touch_distance) {
  for (int i = 0; i < m.point_count; ++i) {
    if (m.points[static_cast<size_t>(i)].depth >= -touch_distance) return true;
  }
  return false;
}

}  // namespace bitstep
