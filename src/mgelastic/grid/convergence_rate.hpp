#pragma once
// The convergence rate reported by the benchmarks: the geometric mean of the last five
// cycle-to-cycle residual ratios, counting only cycles whose residual stays above `floor` times
// the initial one (1e-11 in double; round-off would otherwise pollute the ratios).
#include <vector>

namespace mgelastic::grid {

double convergence_rate(const std::vector<double>& residuals, double floor = 1e-11, int last = 5);

}  // namespace mgelastic::grid
