#pragma once
// `mgelastic bench validation`: the analytic and reference cases of issue 22, run with both
// engines, as records for a table or JSON (docs/validation.md):
//   lame_sphere.hpp   hollow sphere under internal pressure, nu 0.3 and 0.49, grid and tet;
//   cantilever.hpp    tip force and gravity against Timoshenko, grid and tet, Richardson;
//   patch_test.hpp    homogeneous strain reproduced exactly, grid and tet;
//   the paper's disc  (grid/disc_study.hpp, Sec. 9.2, 2D), nu 0.2 and 0.49.
#include <functional>
#include <string>
#include <vector>

#include <nlohmann/json.hpp>

#include "mgelastic/validation/convergence_series.hpp"
#include "mgelastic/validation/patch_test.hpp"

namespace mgelastic::validation {

struct ValidationOptions {
  // Resolutions: cells (cubes) across the sphere's diameter / along the cantilever / across the
  // disc's unit square. Empty leaves a case out.
  std::vector<int> sphere_grid{16, 32, 64, 128}, sphere_tet{8, 16, 32, 64};
  std::vector<int> cantilever_grid{20, 40, 80, 160}, cantilever_tet{10, 20, 40, 80};
  std::vector<int> patch{8, 16};
  std::vector<int> disc{64, 128, 256};
  std::vector<double> sphere_poisson{0.3, 0.49};
  std::vector<double> disc_poisson{0.2, 0.49};

  // Small sizes: seconds instead of minutes, orders from coarse meshes.
  static ValidationOptions quick();
};

struct ValidationReport {
  std::vector<ConvergenceSeries> series;
  std::vector<PatchTestResult> patch;
};

// `progress(line)` (optional) is called before each case starts.
ValidationReport run_validation(const ValidationOptions& options,
                                const std::function<void(const std::string&)>& progress = {});

// The paper's disc (grid/disc_study.hpp) as a series: value = max |u - u_exact| at the interior
// variables (reference 0, so relative_error is that absolute error).
ConvergenceSeries disc_series(double poisson_ratio, const std::vector<int>& resolutions);

nlohmann::json to_json(const PatchTestResult& result);
nlohmann::json to_json(const ValidationReport& report);

}  // namespace mgelastic::validation
