// The narrowphase: contact points between two placed shapes.
#pragma once

#include "core/manifold.h"
#include "core/shape.h"

namespace bitstep {

// Fills `out` with up to 4 points where a and b touch or overlap by more than
// -speculative_distance (m), the normal pointing from a to b, and returns the
// point count (0: apart). Handles every pair of shape types, in either order;
// plane-plane gives nothing. Deterministic: the same inputs give the same
// points in the same order with the same feature ids.
int collide(const WorldShape& a, const WorldShape& b, Fixed speculative_distance, Manifold& out);

}  // namespace bitstep
