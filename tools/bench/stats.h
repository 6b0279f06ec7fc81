// The statistics the benchmark reports: the Pareto front of a
// work-precision diagram and the exponent of a power-law fit.
#pragma once

#include <vector>

namespace bitstep::bench {

struct CostError {
  double cost = 0;   // ms per simulated second
  double error = 0;  // the experiment's error metric
};

// front[i]: no other point is at most as costly and at most as wrong while
// strictly better in one of the two (ties: the first of equal points stays).
std::vector<bool> pareto_front(const std::vector<CostError>& points);

// y = c x^k by least squares on (log x, log y); needs two distinct positive x.
struct PowerLaw {
  double exponent = 0;
  double coefficient = 0;
  bool ok = false;
};
PowerLaw fit_power_law(const std::vector<double>& x, const std::vector<double>& y);

}  // namespace bitstep::bench
