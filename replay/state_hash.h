// state_hash: XXH3-64 of a canonical little-endian serialisation of the
// world's state, in slot order, no padding. Hashing does not change the world.
#pragma once

#include <cstdint>
#include <vector>

#include "core/world.h"

namespace bitstep {

// Appends the canonical bytes of everything that influences the future
// (describe_state in state_description.h: the step counter, the settings,
// every body slot, the free-slot list, every contact).
void serialize_state(const World& world, std::vector<uint8_t>& out);

uint64_t state_hash(const World& world);

}  // namespace bitstep
