#include "mgelastic/grid/convergence_rate.hpp"

#include <cmath>

namespace mgelastic::grid {

double convergence_rate(const std::vector<double>& residuals, double floor, int last) {
  std::vector<double> ratios;
  for (std::size_t k = 1; k < residuals.size(); ++k) {
    if (!(residuals[k] > floor * residuals.front())) break;
    ratios.push_back(residuals[k] / residuals[k - 1]);
  }
  if (ratios.empty()) return 0.0;
  const std::size_t count = std::min<std::size_t>(ratios.size(), last);
  double log_sum = 0.0;
  for (std::size_t k = ratios.size() - count; k < ratios.size(); ++k)
    log_sum += std::log(ratios[k]);
  return std::exp(log_sum / static_cast<double>(count));
}

}  // namespace mgelastic::grid
