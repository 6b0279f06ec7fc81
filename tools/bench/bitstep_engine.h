// bitstep behind the benchmark's Engine interface (tools/bench/engine.h), in
// its five variants: pipeline standard or guendelman, shock step off or on,
// and the soft step.
#pragma once

#include <vector>

#include "core/pose.h"
#include "tools/bench/engine.h"

namespace bitstep::bench {

// standard, standard+shock, guendelman, guendelman+shock, soft.
const std::vector<Variant>& bitstep_variants();

// Doubles to Q32.32 by rounding to the nearest ulp (exact for every value a
// Fixed converted to double gives back, so scene files round-trip).
int64_t to_raw(double value);
// Q32.32 to double: exact while the value has at most 53 significant bits.
double to_double(Fixed value);
V3 to_double(Vec3 v);
Q4 to_double(Quat q);

}  // namespace bitstep::bench
