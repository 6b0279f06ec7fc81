// Support levels for shock propagation (the second seed, after Guendelman,
// Bridson and Fedkiw): which body rests on which, counted upward from the
// static and kinematic bodies along the direction opposite gravity.
#pragma once

#include <cstdint>
#include <vector>

#include "core/body.h"
#include "core/contact.h"

namespace bitstep {

inline constexpr uint32_t not_supported = UINT32_MAX;

// Whether a contact normal, pointing from one body to the other, makes the
// first hold the second up: within 60 degrees of up = -gravity.
bool is_support(Vec3 normal, Vec3 gravity);

// Level per body slot: 0 for static, kinematic and sleeping bodies; an awake body
// resting on a body of level k is at most k + 1, where "resting on" means a
// contact whose normal, from the supporter to it, lies within 60 degrees of
// up = -gravity. Breadth-first from level 0 (ties by slot order), so a
// body's level is the fewest supports between it and the ground. Dynamic
// bodies with no such path (falling, or only leaning sideways on others),
// dead slots, and every body when gravity is zero are not_supported. Only
// contacts that touch count: a point within `touch_distance` (m); a
// speculative contact further apart holds nothing up yet.
void support_levels(const std::vector<Body>& bodies, const std::vector<Contact>& contacts, Vec3 gravity,
                    Fixed touch_distance, std::vector<uint32_t>& level);

}  // namespace bitstep
