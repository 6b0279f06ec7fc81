// Contact manifolds: what the narrowphase finds between two shapes, and the
// solver state that persists with it from step to step.
#pragma once

#include <array>
#include <cstddef>
#include <cstdint>

#include "fixed/decimal.h"
#include "fixed/vec3.h"

namespace bitstep {

using namespace bitstep::literals;

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
  // Rolling resistance (N m s, about the same tangent basis): an angular
  // impulse opposing the relative rotation in the contact plane.
  Fixed rolling_impulse[2];
};

// How far apart (m) two surfaces may be and still touch: rounding, not
// physics. A speculative contact lands a falling body exactly (its row lets
// the gap close by depth / dt, no more), so a body at rest on a support sits
// at a depth of 0 to the penetration slop (default 0), never above it by more
// than a few ulps. This is NOT the penetration slop: counting gaps up to a
// slop of millimetres as touching lets the shock step hold bodies up in the
// air (a box released a few mm above the ground would stay there for ever).
inline constexpr Fixed touch_tolerance = 0.00001_fx;

// A point of the manifold touches: depth >= -touch_tolerance. Islands, sleep
// and the shock step count such a contact as touching; one further apart is
// only speculative (the iterations close it, exactly, when the bodies meet).
inline bool touches(const Manifold& m) {
  for (int i = 0; i < m.point_count; ++i) {
    if (m.points[static_cast<size_t>(i)].depth >= -touch_tolerance) return true;
  }
  return false;
}

}  // namespace bitstep
