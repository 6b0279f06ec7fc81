// Measured accuracy of every fixed/ function: the worst error in ulps over
// edge values and random operands, against an exact integer/rational
// reference (mul, div, sqrt, length, decimal parsing, ...) or a long double
// one (transcendentals). tests/fixed/accuracy_tests.cpp prints the table and
// asserts every bound. Floating point, hence here and not in fixed/.
#pragma once

#include <cstdint>
#include <string>
#include <vector>

namespace bitstep {

struct AccuracyRow {
  std::string function;     // e.g. "mul", "sin"
  std::string reference;    // "exact" or "long double"
  double bound_ulps;        // the stated bound (docs/determinism.md, "Accuracy")
  double worst_ulps;        // measured
  std::string worst_input;  // the operand(s) of the worst case, in raw: text
  uint64_t samples;         // edge values + random operands
};

// random_samples: random operands per function, on top of the edge values.
std::vector<AccuracyRow> measure_accuracy(uint64_t random_samples);

}  // namespace bitstep
