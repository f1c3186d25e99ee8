// The validation record (validation/convergence_series.hpp): orders and Richardson extrapolation
// of a synthetic series, and the JSON fields the plots and docs read.
#include <gtest/gtest.h>

#include <cmath>

#include "mgelastic/validation/validation_suite.hpp"

namespace mgelastic::validation {
namespace {

// value = 1 + 0.5 h^2 with h = 1 / n: second order towards 1.
ConvergenceSeries second_order_series() {
  ConvergenceSeries s{"synthetic", "grid", "q", "m", 0.3};
  for (int n : {8, 16, 32}) {
    const double h = 1.0 / n;
    s.rows.push_back({n, h, 1 + 0.5 * h * h, 1.0});
  }
  s.finish();
  return s;
}

TEST(ConvergenceSeries, ObservedOrderOfASecondOrderSeries) {
  const ConvergenceSeries s = second_order_series();
  EXPECT_TRUE(std::isnan(s.rows[0].order));
  EXPECT_NEAR(s.rows[1].order, 2.0, 1e-9);
  EXPECT_NEAR(s.observed_order, 2.0, 1e-9);
  EXPECT_NEAR(s.fitted_order, 2.0, 1e-9);
}

TEST(ConvergenceSeries, RichardsonRecoversTheLimitWithoutTheReference) {
  const ConvergenceSeries s = second_order_series();
  EXPECT_NEAR(s.richardson_order, 2.0, 1e-9);
  EXPECT_NEAR(s.richardson_value, 1.0, 1e-12);
}

TEST(ConvergenceSeries, JsonRecordHoldsEveryField) {
  ValidationReport report;
  report.series.push_back(second_order_series());
  report.patch.push_back({"tet", 4, 1e-14, 375, true});
  const nlohmann::json j = to_json(report);
  EXPECT_EQ(j["benchmark"], "validation");
  const nlohmann::json& s = j["series"][0];
  for (const char* key :
       {"study", "engine", "quantity", "unit", "poisson_ratio", "rows", "observed_order",
        "fitted_order", "richardson_order", "richardson_value", "note"})
    EXPECT_TRUE(s.contains(key)) << key;
  for (const char* key : {"resolution", "h", "value", "reference", "relative_error", "order",
                          "unknowns", "seconds", "converged"})
    EXPECT_TRUE(s["rows"][0].contains(key)) << key;
  EXPECT_TRUE(s["rows"][0]["order"].is_null());  // NaN has no JSON form
  for (const char* key : {"study", "engine", "resolution", "max_relative_error", "converged"})
    EXPECT_TRUE(j["patch_test"][0].contains(key)) << key;
}

}  // namespace
}  // namespace mgelastic::validation
