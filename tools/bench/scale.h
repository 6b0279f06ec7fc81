// `bitstep bench`'s scale experiment: ms/step against body count.
#pragma once

#include <string>
#include <vector>

namespace bitstep::bench {

struct ScaleRow {
  std::string structure;  // "pyramid" or "columns"
  bool asleep = false;    // every body created asleep (sleep on), or sleep off
  int bodies = 0;         // dynamic bodies
  int steps = 0;          // steps timed
  double ms_per_step = 0;
  bool stayed_asleep = true;  // asleep runs: no body woke while timed
};

// Body counts measured: 10 to 1,000 (quick) or 10,000.
std::vector<int> scale_sizes(bool quick);
// Builds the structure with about `bodies` dynamic bodies and times its steps.
ScaleRow measure_scale(const std::string& structure, int bodies, bool asleep);

}  // namespace bitstep::bench
