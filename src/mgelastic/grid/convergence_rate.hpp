#pragma once
// The convergence rate reported by the benchmarks: the geometric mean of the last five
// cycle-to-cycle residual ratios, counting only cycles whose residual stays above `floor` times
// the initial one (1e-11 in double; round-off would otherwise pollute the ratios).
#include <vector>

namespace mgelastic::grid {

double convergence_rate(const std::vector<double>& residuals, double floor = 1e-11, int last = 5);

// Whether that rate has settled: the last three counted ratios lie within `tolerance` of each
// other. A slow mode that the load barely excites shows only after many cycles (the armadillo
// at 256 cells: ratios 0.35 for eight cycles, 0.78 from cycle 16 on), so an unsettled rate is a
// lower bound of the cycle's asymptotic rate, and the benchmarks say so.
bool rate_settled(const std::vector<double>& residuals, double floor = 1e-11,
                  double tolerance = 0.01);

// The last counted ratio (0 when none counts).
double last_ratio(const std::vector<double>& residuals, double floor = 1e-11);

}  // namespace mgelastic::grid
