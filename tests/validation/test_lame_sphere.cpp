// The Lamé hollow sphere (validation/lame_sphere.hpp): the analytic solution meets its boundary
// conditions, and the grid engine's error decreases with resolution.
#include <gtest/gtest.h>

#include "mgelastic/validation/lame_sphere.hpp"

namespace mgelastic::validation {
namespace {

// sigma_rr = (lambda + 2 mu) du/dr + 2 lambda u / r for the radial field.
double radial_stress(const LameSphere& s, double r) {
  const double nu = s.poisson_ratio, e = s.youngs_modulus;
  const double lambda = e * nu / ((1 + nu) * (1 - 2 * nu)), mu = e / (2 * (1 + nu));
  const double d = 1e-6 * r;
  const double dudr = (s.radial_displacement(r + d) - s.radial_displacement(r - d)) / (2 * d);
  return (lambda + 2 * mu) * dudr + 2 * lambda * s.radial_displacement(r) / r;
}

TEST(LameSphere, AnalyticSolutionMeetsPressureAndFreeSurface) {
  for (double nu : {0.3, 0.49}) {
    LameSphere s;
    s.poisson_ratio = nu;
    // Central differences of a smooth field: ~1e-10 relative.
    EXPECT_NEAR(radial_stress(s, s.inner_radius), -s.pressure, 1e-6 * s.pressure) << nu;
    EXPECT_NEAR(radial_stress(s, s.outer_radius), 0.0, 1e-6 * s.pressure) << nu;
  }
}

TEST(LameSphere, GridErrorDecreasesWithResolution) {
  const std::vector<ConvergenceSeries> series = lame_sphere_study("grid", LameSphere{}, {12, 24});
  ASSERT_EQ(series.size(), 2U);
  for (const ConvergenceSeries& s : series) {
    ASSERT_EQ(s.rows.size(), 2U);
    EXPECT_TRUE(s.rows[0].converged && s.rows[1].converged);
    EXPECT_GT(s.observed_order, 0.5) << s.quantity << ": errors " << s.rows[0].relative_error
                                     << ", " << s.rows[1].relative_error;
  }
}

}  // namespace
}  // namespace mgelastic::validation
