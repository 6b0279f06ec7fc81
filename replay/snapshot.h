// Snapshots: the whole world as a versioned, endian-neutral byte image that
// restores into a fresh world which continues bit-identically.
//
// Image: "BITSTEPS" (8 bytes), format version (u32, little-endian), payload
// size (u64), the payload (serialize_state's canonical bytes: the state hash
// is XXH3-64 of exactly these), then XXH3-64 of everything before it (u64).
#pragma once

#include <cstdint>
#include <span>
#include <string>
#include <vector>

#include "core/world.h"

namespace bitstep {

inline constexpr uint32_t snapshot_version = 6;  // 2: rolling resistance (material, contact impulses); 3: joints' solver passes; 4: cars' tyre impulses; 5: sliders, joint motors (a joint's flags byte); 6: the suspension's impulse, held islands' velocity passes (a setting)

std::vector<uint8_t> snapshot(const World& world);

// Restores an image into `world`, replacing it, or returns why it cannot (a
// wrong magic or version, a checksum mismatch, a truncated image, a value
// no world can hold; the error's reason says it all, its place is empty)
// and leaves `world` untouched.
Result<void> restore(std::span<const uint8_t> image, World& world);

}  // namespace bitstep
