// The broadphase: which bodies may touch, in canonical order.
#pragma once

#include <cstdint>
#include <vector>

#include "core/aabb.h"

namespace bitstep {

struct BodyPair {
  uint32_t a, b;  // body slot indices, a < b
  friend auto operator<=>(const BodyPair&, const BodyPair&) = default;
};

// One entry per live body: its bounds and whether it moves.
struct BroadphaseProxy {
  uint32_t body;
  Aabb bounds;
  bool movable;  // its contacts are found this step (core/body.h needs_contacts()); pairs of two unmovable bodies are skipped
  friend bool operator==(const BroadphaseProxy&, const BroadphaseProxy&) = default;
};

// The broadphase's workspace, kept by the world from step to step so that a
// settled step allocates nothing. Not state: the pairs are a function of
// the proxies alone, found again whenever one proxy differs by a bit.
struct BroadphaseScratch {
  struct CellEntry {
    int64_t x, y, z;  // cell coordinates: raw coordinate >> cell_shift (floor division by the cell size)
    uint32_t proxy;
    friend auto operator<=>(const CellEntry&, const CellEntry&) = default;
  };
  std::vector<uint32_t> movers, large;
  std::vector<CellEntry> entries;
  std::vector<uint64_t> keys;  // the entries packed for sorting
  // The proxies of the last call, while `reuse` is on: a call with the same
  // proxies, bit for bit (a standing wall's), keeps the pairs that call left.
  bool reuse = true;
  std::vector<BroadphaseProxy> last_proxies;
};

// All pairs whose bounds overlap and of which at least one is movable,
// sorted by (a, b). A uniform grid over the small proxies (cell = the largest
// small proxy, a power of two) finds neighbours in n log n; the few large
// ones (ground, planes) are tested against everything. `pairs` must hold
// what the last call with this scratch left in it (the world passes the same
// two every step).
void find_pairs(const std::vector<BroadphaseProxy>& proxies, std::vector<BodyPair>& pairs,
                BroadphaseScratch& scratch);

}  // namespace bitstep
