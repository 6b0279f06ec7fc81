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

// Up to this many proxies, every pair is tested: fewer than 500 overlap
// tests cost less than the grid's set-up (a pendulum's 2 proxies took ~3,000
// instructions a step through the grid).
constexpr size_t all_pairs_up_to = 32;

Fixed widest_side(const Aabb& b) {
  const Vec3 size = b.max - b.min;
  return max(size.x, max(size.y, size.z));
}

using CellEntry = BroadphaseScratch::CellEntry;

bool can_collide(const BroadphaseProxy& p, const BroadphaseProxy& q) { return p.movable || q.movable; }

BodyPair ordered(uint32_t a, uint32_t b) { return a < b ? BodyPair{a, b} : BodyPair{b, a}; }

// Sorts the entries by (x, y, z, proxy). Where each coordinate's range
// from its lowest cell and the proxy number fit side by side in 64 bits
// (any scene of a few kilometres), the sort runs over those packed keys,
// whose order is the entries' order: the same result, without comparing
// four fields a time (which showed in a small scene's step).
void sort_entries(std::vector<CellEntry>& entries, std::vector<uint64_t>& keys, size_t proxy_count) {
  if (entries.empty()) return;
  int64_t low[3] = {entries[0].x, entries[0].y, entries[0].z}, high[3] = {low[0], low[1], low[2]};
  for (const CellEntry& e : entries) {
    const int64_t c[3] = {e.x, e.y, e.z};
    for (int k = 0; k < 3; ++k) {
      low[k] = std::min(low[k], c[k]);
      high[k] = std::max(high[k], c[k]);
    }
  }
  // Cells are raw coordinates shifted right at least once: |c| < 2^62, so
  // a range fits in 63 bits.
  int bits[3];
  for (int k = 0; k < 3; ++k) bits[k] = static_cast<int>(std::bit_width(static_cast<uint64_t>(high[k] - low[k])));
  const int proxy_bits = static_cast<int>(std::bit_width(static_cast<uint64_t>(proxy_count)));
  if (bits[0] + bits[1] + bits[2] + proxy_bits > 64) {
    std::sort(entries.begin(), entries.end());
    return;
  }
  const int shift_z = proxy_bits, shift_y = shift_z + bits[2], shift_x = shift_y + bits[1];
  // A field of width 0 holds nothing: it is neither shifted in nor out (its
  // shift may be 64).
  const auto place = [](int64_t offset, int shift, int width) {
    return width == 0 ? uint64_t{0} : static_cast<uint64_t>(offset) << shift;
  };
  const auto field = [](uint64_t key, int shift, int width) {
    return static_cast<int64_t>(width == 0 ? 0 : (key >> shift) & (~uint64_t{0} >> (64 - width)));
  };
  keys.clear();
  for (const CellEntry& e : entries) {
    keys.push_back(place(e.x - low[0], shift_x, bits[0]) | place(e.y - low[1], shift_y, bits[1]) |
                   place(e.z - low[2], shift_z, bits[2]) | e.proxy);
  }
  std::sort(keys.begin(), keys.end());
  for (size_t i = 0; i < keys.size(); ++i) {
    const uint64_t key = keys[i];
    entries[i] = {low[0] + field(key, shift_x, bits[0]), low[1] + field(key, shift_y, bits[1]),
                  low[2] + field(key, shift_z, bits[2]), static_cast<uint32_t>(field(key, 0, proxy_bits))};
  }
}

// Every pair, when there are few proxies.
void all_pairs(const std::vector<BroadphaseProxy>& proxies, std::vector<BodyPair>& pairs) {
  for (uint32_t i = 0; i < proxies.size(); ++i) {
    const BroadphaseProxy& p = proxies[i];
    for (uint32_t j = i + 1; j < proxies.size(); ++j) {
      const BroadphaseProxy& q = proxies[j];
      if (can_collide(p, q) && p.bounds.overlaps(q.bounds)) pairs.push_back(ordered(p.body, q.body));
    }
  }
}

// Whether fewer than one proxy in few_movers_ratio moves; `movers` gets
// their indices.
bool few_movers(const std::vector<BroadphaseProxy>& proxies, std::vector<uint32_t>& movers) {
  movers.clear();
  for (uint32_t i = 0; i < proxies.size(); ++i) {
    if (proxies[i].movable) movers.push_back(i);
  }
  return movers.size() * few_movers_ratio <= proxies.size();
}

// Each mover against every proxy (two movers once), when few move among many
// resting proxies (a world mostly asleep): m n tests, less than the grid's
// n log n. Exactly the overlapping pairs with a mover, as the grid finds.
void mover_pairs(const std::vector<BroadphaseProxy>& proxies, const std::vector<uint32_t>& movers,
                 std::vector<BodyPair>& pairs) {
  for (const uint32_t m : movers) {
    const BroadphaseProxy& p = proxies[m];
    for (uint32_t i = 0; i < proxies.size(); ++i) {
      const BroadphaseProxy& q = proxies[i];
      if (i == m || (q.movable && i < m) || !p.bounds.overlaps(q.bounds)) continue;
      pairs.push_back(ordered(p.body, q.body));
    }
  }
}

// The grid's cell width, 2^shift raw units: at least the widest small
// proxy's. `large` gets the large proxies' indices.
int grid_shift(const std::vector<BroadphaseProxy>& proxies, std::vector<uint32_t>& large) {
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
  return std::max(1, static_cast<int>(std::bit_width(static_cast<uint64_t>(widest_small.raw()))));
}

// The pairs within each cell of a grid whose cells are as wide as the
// widest small proxy (2^shift raw units), so each small proxy covers at
// most 2 x 2 x 2 cells; a pair is reported only in the cell holding the
// lower corner of its overlap.
void grid_pairs(const std::vector<BroadphaseProxy>& proxies, int shift, BroadphaseScratch& scratch,
                std::vector<BodyPair>& pairs) {
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
  sort_entries(entries, scratch.keys, proxies.size());
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
}

// The large proxies (past large_extent: grounds, walls), kept out of the
// grid, each against every proxy (two large ones once).
void large_pairs(const std::vector<BroadphaseProxy>& proxies, const std::vector<uint32_t>& large,
                 std::vector<BodyPair>& pairs) {
  for (const uint32_t l : large) {
    const BroadphaseProxy& big = proxies[l];
    for (uint32_t i = 0; i < proxies.size(); ++i) {
      const BroadphaseProxy& p = proxies[i];
      if (i == l || !can_collide(big, p) || !big.bounds.overlaps(p.bounds)) continue;
      const bool p_is_large = widest_side(p.bounds) > large_extent;
      if (p_is_large && i < l) continue;
      pairs.push_back(ordered(big.body, p.body));
    }
  }
}

}  // namespace

void find_pairs(const std::vector<BroadphaseProxy>& proxies, std::vector<BodyPair>& pairs, BroadphaseScratch& scratch) {
  if (scratch.reuse) {
    if (proxies == scratch.last_proxies) return;
    scratch.last_proxies = proxies;
  }
  pairs.clear();
  if (proxies.size() <= all_pairs_up_to) {
    all_pairs(proxies, pairs);
  } else if (few_movers(proxies, scratch.movers)) {
    mover_pairs(proxies, scratch.movers, pairs);
  } else {
    const int shift = grid_shift(proxies, scratch.large);
    grid_pairs(proxies, shift, scratch, pairs);
    large_pairs(proxies, scratch.large, pairs);
  }
  // Each way reports every overlapping pair once: sorted, the same list.
  std::sort(pairs.begin(), pairs.end());
}

}  // namespace bitstep
