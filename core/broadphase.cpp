#include "core/broadphase.h"

#include <algorithm>
#include <bit>
#include <tuple>

#include "core/settings.h"

namespace bitstep {

namespace {

// Proxies wider than this along any axis (grounds, planes, long walls) skip
// the grid and are tested against every proxy.
constexpr Fixed large_extent = 8.0_fx;  // m

// Below one mover per this many proxies, movers are tested against all.
constexpr size_t few_movers_ratio = 64;

Fixed widest_side(const Aabb& b) {
  const Vec3 size = b.max - b.min;
  return max(size.x, max(size.y, size.z));
}

using CellEntry = BroadphaseScratch::CellEntry;

bool can_collide(const BroadphaseProxy& p, const BroadphaseProxy& q) { return p.movable || q.movable; }

BodyPair ordered(uint32_t a, uint32_t b) { return a < b ? BodyPair{a, b} : BodyPair{b, a}; }

}  // namespace

void find_pairs(const std::vector<BroadphaseProxy>& proxies, std::vector<BodyPair>& pairs,
                BroadphaseScratch& scratch) {
  if (scratch.reuse) {
    if (proxies == scratch.last_proxies) return;
    scratch.last_proxies = proxies;
  }
  pairs.clear();
  // Few movers among many resting proxies (a world mostly asleep): each
  // mover against every proxy costs m n, less than the grid's n log n.
  // Both ways report exactly the overlapping pairs with a mover.
  std::vector<uint32_t>& movers = scratch.movers;
  movers.clear();
  for (uint32_t i = 0; i < proxies.size(); ++i) {
    if (proxies[i].movable) movers.push_back(i);
  }
  if (movers.size() * few_movers_ratio <= proxies.size()) {
    for (const uint32_t m : movers) {
      const BroadphaseProxy& p = proxies[m];
      for (uint32_t i = 0; i < proxies.size(); ++i) {
        const BroadphaseProxy& q = proxies[i];
        if (i == m || (q.movable && i < m) || !p.bounds.overlaps(q.bounds)) continue;  // two movers once
        pairs.push_back(ordered(p.body, q.body));
      }
    }
    std::sort(pairs.begin(), pairs.end());
    return;
  }
  std::vector<uint32_t>& large = scratch.large;
  large.clear();
  Fixed widest_small;
  for (uint32_t i = 0; i < proxies.size(); ++i) {
    const Fixed w = widest_side(proxies[i].bounds);
    if (w > large_extent) {
      large.push_back(i);
    } else {
      widest_small = max(widest_small, w);
    }
  }

  // A cell of 2^shift raw units is at least as wide as every small proxy,
  // so each proxy covers at most 2 x 2 x 2 cells.
  const int shift = std::max(1, static_cast<int>(std::bit_width(static_cast<uint64_t>(widest_small.raw()))));
  std::vector<CellEntry>& entries = scratch.entries;
  entries.clear();
  entries.reserve(proxies.size() * 2);
  for (uint32_t i = 0; i < proxies.size(); ++i) {
    const Aabb& b = proxies[i].bounds;
    if (widest_side(b) > large_extent) continue;
    for (int64_t x = b.min.x.raw() >> shift; x <= b.max.x.raw() >> shift; ++x) {
      for (int64_t y = b.min.y.raw() >> shift; y <= b.max.y.raw() >> shift; ++y) {
        for (int64_t z = b.min.z.raw() >> shift; z <= b.max.z.raw() >> shift; ++z) entries.push_back({x, y, z, i});
      }
    }
  }
  std::sort(entries.begin(), entries.end());

  for (size_t run = 0; run < entries.size();) {
    size_t end = run + 1;
    while (end < entries.size() && std::tie(entries[end].x, entries[end].y, entries[end].z) ==
                                       std::tie(entries[run].x, entries[run].y, entries[run].z)) {
      ++end;
    }
    for (size_t i = run; i < end; ++i) {
      const BroadphaseProxy& p = proxies[entries[i].proxy];
      for (size_t j = i + 1; j < end; ++j) {
        const BroadphaseProxy& q = proxies[entries[j].proxy];
        if (!can_collide(p, q) || !p.bounds.overlaps(q.bounds)) continue;
        // Two proxies may share several cells: report the pair only in the
        // cell holding the lower corner of their overlap.
        const Vec3 corner = max(p.bounds.min, q.bounds.min);
        if ((corner.x.raw() >> shift) != entries[run].x || (corner.y.raw() >> shift) != entries[run].y ||
            (corner.z.raw() >> shift) != entries[run].z) {
          continue;
        }
        pairs.push_back(ordered(p.body, q.body));
      }
    }
    run = end;
  }

  for (size_t li = 0; li < large.size(); ++li) {
    const BroadphaseProxy& l = proxies[large[li]];
    for (uint32_t i = 0; i < proxies.size(); ++i) {
      const BroadphaseProxy& p = proxies[i];
      if (i == large[li] || !can_collide(l, p) || !l.bounds.overlaps(p.bounds)) continue;
      const bool p_is_large = widest_side(p.bounds) > large_extent;
      if (p_is_large && i < large[li]) continue;  // a large-large pair once
      pairs.push_back(ordered(l.body, p.body));
    }
  }
  std::sort(pairs.begin(), pairs.end());
}

}  // namespace bitstep
