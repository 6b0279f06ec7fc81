// SplitMix64 (Steele, Lea, Flood 2014): a tiny, well-mixed, fully specified
// integer generator. Every seeded random operand in bitstep (the throw
// generator, the tools, the tests) comes from it, so a seed means the same
// numbers on every platform. Here in fixed/, the lowest layer that uses it.
#pragma once

#include <cstdint>

namespace bitstep {

struct SplitMix64 {
  uint64_t state;

  uint64_t next() {
    uint64_t z = (state += 0x9E3779B97F4A7C15u);
    z = (z ^ (z >> 30)) * 0xBF58476D1CE4E5B9u;
    z = (z ^ (z >> 27)) * 0x94D049BB133111EBu;
    return z ^ (z >> 31);
  }
  // Uniform in [0, n) for n > 0 (modulo bias below 2^-40 for the n used here).
  int below(int n) { return static_cast<int>(next() % static_cast<uint64_t>(n)); }
};

}  // namespace bitstep
