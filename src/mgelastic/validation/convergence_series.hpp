#pragma once
// The record of one validation study (validation_suite.hpp): a measured quantity at several
// resolutions next to its analytic or theoretical reference, with observed orders.
//
// Orders. For rows i-1, i with refinement ratio r = resolution_i / resolution_{i-1}:
//   order_i = log(error_{i-1} / error_i) / log(r)      (error = |value - reference| / |reference|)
// and, on the last three rows (constant ratio r assumed), Richardson extrapolation from the values
// alone, without the reference:
//   p = log((v1 - v2) / (v2 - v3)) / log(r),   v_inf = v3 + (v3 - v2) / (r^p - 1).
// Quantities that are not defined (fewer rows, non-monotone differences, a Richardson order below
// 0.5, an error norm as the value) are NaN, written to JSON
// as null.
#include <cstddef>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

namespace mgelastic::validation {

struct ConvergenceRow {
  int resolution = 0;  // cells (or cubes) across the body's longest axis
  double h = 0.0;      // cell / cube edge (m)
  double value = 0.0;  // the measured quantity
  double reference = 0.0;
  // |value - reference| / |reference|; |value| when the reference is 0 (value is an error norm).
  double relative_error = 0.0;
  double order = 0.0;  // observed order against the previous row (NaN for the first)
  std::size_t unknowns = 0;
  double seconds = 0.0;  // setup + solve + measurement
  bool converged = true;
};

struct ConvergenceSeries {
  std::string study;     // lame_sphere, cantilever_tip_force, cantilever_gravity, patch_test, disc
  std::string engine;    // grid | tet
  std::string quantity;  // what `value` is, e.g. "u_r(a) mean"
  std::string unit;      // of value and reference
  double poisson_ratio = 0.0;
  std::vector<ConvergenceRow> rows;
  double observed_order = 0.0;  // order of the last row (NaN with fewer than two rows)
  // Least-squares slope of -log(error) against log(resolution) over all rows: steadier than
  // observed_order where the error scatters with how the lattice cuts a curved surface.
  double fitted_order = 0.0;
  double richardson_order = 0.0, richardson_value = 0.0;
  std::string note;  // reference used, known effects, the choices made

  // Fills relative_error and order of every row, observed_order and the Richardson fields.
  void finish();
};

nlohmann::json to_json(const ConvergenceSeries& series);

}  // namespace mgelastic::validation
