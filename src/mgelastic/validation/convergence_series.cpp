#include "mgelastic/validation/convergence_series.hpp"

#include <cmath>
#include <limits>

#include <Eigen/Dense>

namespace mgelastic::validation {
namespace {

constexpr double kNaN = std::numeric_limits<double>::quiet_NaN();
constexpr double kMinRichardsonOrder = 0.5;

// JSON has no NaN: undefined figures are null.
nlohmann::json number(double x) {
  return std::isfinite(x) ? nlohmann::json(x) : nlohmann::json(nullptr);
}

}  // namespace

void ConvergenceSeries::finish() {
  for (std::size_t i = 0; i < rows.size(); ++i) {
    ConvergenceRow& row = rows[i];
    row.relative_error =
        std::abs(row.value - row.reference) / (row.reference != 0 ? std::abs(row.reference) : 1.0);
    row.order = kNaN;
    if (i == 0) continue;
    const ConvergenceRow& previous = rows[i - 1];
    const double ratio = static_cast<double>(row.resolution) / previous.resolution;
    if (row.relative_error > 0 && previous.relative_error > 0 && ratio > 1)
      row.order = std::log(previous.relative_error / row.relative_error) / std::log(ratio);
  }
  observed_order = rows.size() >= 2 ? rows.back().order : kNaN;
  fitted_order = kNaN;
  Eigen::MatrixX2d design(rows.size(), 2);
  Eigen::VectorXd log_error(rows.size());
  for (std::size_t i = 0; i < rows.size(); ++i) {
    design.row(i) << 1.0, std::log(static_cast<double>(rows[i].resolution));
    log_error[i] = std::log(rows[i].relative_error);
  }
  if (rows.size() >= 2 && log_error.allFinite())
    fitted_order = -design.colPivHouseholderQr().solve(log_error)[1];
  richardson_order = richardson_value = kNaN;
  // An error norm (reference 0) has no limit to extrapolate.
  if (rows.size() < 3 || rows.back().reference == 0) return;
  const ConvergenceRow &r1 = rows[rows.size() - 3], &r2 = rows[rows.size() - 2], &r3 = rows.back();
  const double ratio = static_cast<double>(r3.resolution) / r2.resolution;
  const double d12 = r1.value - r2.value, d23 = r2.value - r3.value;
  // Monotone convergence only: oscillating or stalled differences have no order.
  if (ratio <= 1 || d23 == 0 || d12 / d23 <= 0) return;
  const double order = std::log(d12 / d23) / std::log(ratio);
  // Below order 0.5 the differences hardly shrink: the rows are not in the asymptotic range and
  // 1 / (r^p - 1) would amplify them into nonsense.
  if (order < kMinRichardsonOrder) return;
  richardson_order = order;
  richardson_value = r3.value + (r3.value - r2.value) / (std::pow(ratio, order) - 1);
}

nlohmann::json to_json(const ConvergenceSeries& series) {
  nlohmann::json rows = nlohmann::json::array();
  for (const ConvergenceRow& r : series.rows)
    rows.push_back({{"resolution", r.resolution},
                    {"h", r.h},
                    {"value", r.value},
                    {"reference", r.reference},
                    {"relative_error", r.relative_error},
                    {"order", number(r.order)},
                    {"unknowns", r.unknowns},
                    {"seconds", r.seconds},
                    {"converged", r.converged}});
  return {{"study", series.study},
          {"engine", series.engine},
          {"quantity", series.quantity},
          {"unit", series.unit},
          {"poisson_ratio", series.poisson_ratio},
          {"rows", rows},
          {"observed_order", number(series.observed_order)},
          {"fitted_order", number(series.fitted_order)},
          {"richardson_order", number(series.richardson_order)},
          {"richardson_value", number(series.richardson_value)},
          {"note", series.note}};
}

}  // namespace mgelastic::validation
