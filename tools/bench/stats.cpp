#include "tools/bench/stats.h"

#include <cmath>
#include <cstddef>

namespace bitstep::bench {

std::vector<bool> pareto_front(const std::vector<CostError>& points) {
  std::vector<bool> front(points.size(), true);
  for (size_t i = 0; i < points.size(); ++i) {
    for (size_t j = 0; j < points.size() && front[i]; ++j) {
      if (j == i) continue;
      const CostError& a = points[j];
      const CostError& b = points[i];
      const bool no_worse = a.cost <= b.cost && a.error <= b.error;
      const bool better = a.cost < b.cost || a.error < b.error;
      // An exact duplicate keeps only its first copy on the front.
      if (no_worse && (better || j < i)) front[i] = false;
    }
  }
  return front;
}

PowerLaw fit_power_law(const std::vector<double>& x, const std::vector<double>& y) {
  // Ordinary least squares of log y = log c + k log x.
  double n = 0, sx = 0, sy = 0, sxx = 0, sxy = 0;
  for (size_t i = 0; i < x.size() && i < y.size(); ++i) {
    if (!(x[i] > 0) || !(y[i] > 0)) continue;
    const double lx = std::log(x[i]), ly = std::log(y[i]);
    n += 1;
    sx += lx;
    sy += ly;
    sxx += lx * lx;
    sxy += lx * ly;
  }
  const double denominator = n * sxx - sx * sx;
  if (n < 2 || denominator <= 1e-12) return {};
  const double k = (n * sxy - sx * sy) / denominator;
  return {k, std::exp((sy - k * sx) / n), true};
}

}  // namespace bitstep::bench
