#include <catch2/catch.hpp>
#include <cstdint>
#include <cstdio>
#include <set>
#include <string>
#include <vector>

#include "tests/fixed/fixed_accuracy.h"
#include "tests/test_support.h"

// The accuracy bounds docs/determinism.md states ("Accuracy"), measured over edge values plus 10^6 random
// operands per function (10^5 in unoptimised builds: test_support.h)
// against exact integer or long double references (tests/fixed/fixed_accuracy.cpp).
// The table goes to stdout, i.e. the ctest log.
TEST_CASE("every fixed-point function is within its documented ulp bound over 10^6 random operands and the edges",
          "[fixed][accuracy]") {
  constexpr uint64_t random_samples = bitstep::test::samples(1000000);
  const std::vector<bitstep::AccuracyRow> rows = bitstep::measure_accuracy(random_samples);

  std::printf("\n%-10s %-12s %6s %13s %9s  %s\n", "function", "reference", "bound", "worst (ulp)", "samples",
              "worst input");
  std::set<std::string> functions;
  for (const bitstep::AccuracyRow& row : rows) {
    std::printf("%-10s %-12s %6.1f %13.10f %9llu  %s\n", row.function.c_str(), row.reference.c_str(), row.bound_ulps,
                row.worst_ulps, static_cast<unsigned long long>(row.samples), row.worst_input.c_str());
    functions.insert(row.function);
    INFO(row.function << ": worst " << row.worst_ulps << " ulp (bound " << row.bound_ulps << ") at "
                      << row.worst_input);
    CHECK(row.worst_ulps <= row.bound_ulps);
    CHECK(row.samples >= random_samples);
  }
  std::fflush(stdout);
  const std::set<std::string> expected = {"mul",       "div",  "mul_add", "mul_div", "dot",       "cross",
                                          "length_sq", "sqrt", "length",  "rsqrt",   "normalize", "sin",
                                          "cos",       "tan",  "atan2",   "asin",    "acos",      "parse"};
  CHECK(functions == expected);
}
