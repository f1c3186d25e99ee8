#include "mgelastic/grid/convergence_rate.hpp"

#include <algorithm>
#include <cmath>

namespace mgelastic::grid {

namespace {

// Cycle-to-cycle ratios while the residual stays above floor times the initial one.
std::vector<double> counted_ratios(const std::vector<double>& residuals, double floor) {
  std::vector<double> ratios;
  for (std::size_t k = 1; k < residuals.size(); ++k) {
    if (!(residuals[k] > floor * residuals.front())) break;
    ratios.push_back(residuals[k] / residuals[k - 1]);
  }
  return ratios;
}

}  // namespace

double convergence_rate(const std::vector<double>& residuals, double floor, int last) {
  const std::vector<double> ratios = counted_ratios(residuals, floor);
  if (ratios.empty()) return 0.0;
  const std::size_t count = std::min<std::size_t>(ratios.size(), last);
  double log_sum = 0.0;
  for (std::size_t k = ratios.size() - count; k < ratios.size(); ++k)
    log_sum += std::log(ratios[k]);
  return std::exp(log_sum / static_cast<double>(count));
}

bool rate_settled(const std::vector<double>& residuals, double floor, double tolerance) {
  const std::vector<double> ratios = counted_ratios(residuals, floor);
  if (ratios.size() < 3) return false;
  const auto last = ratios.end() - 3;
  const auto [low, high] = std::minmax_element(last, ratios.end());
  return *high - *low <= tolerance;
}

double last_ratio(const std::vector<double>& residuals, double floor) {
  const std::vector<double> ratios = counted_ratios(residuals, floor);
  return ratios.empty() ? 0.0 : ratios.back();
}

}  // namespace mgelastic::grid
