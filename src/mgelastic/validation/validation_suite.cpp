#include "mgelastic/validation/validation_suite.hpp"

#include "mgelastic/core/timer.hpp"
#include "mgelastic/grid/disc_study.hpp"
#include "mgelastic/validation/cantilever.hpp"
#include "mgelastic/validation/lame_sphere.hpp"

namespace mgelastic::validation {

ValidationOptions ValidationOptions::quick() {
  ValidationOptions o;
  o.sphere_grid = {16, 24, 32};
  o.sphere_tet = {8, 12, 16};
  o.cantilever_grid = {10, 20, 40};
  o.cantilever_tet = {5, 10, 20};
  o.patch = {8};
  o.disc = {16, 32, 64};
  return o;
}

ConvergenceSeries disc_series(double poisson_ratio, const std::vector<int>& resolutions) {
  ConvergenceSeries series{"disc", "grid", "max |u - u_exact| at interior variables (2D)", "m",
                           poisson_ratio};
  Timer timer;
  const grid::DiscStudy study = grid::run_disc_study(poisson_ratio, resolutions);
  for (const grid::DiscStudyRow& r : study.rows) {
    ConvergenceRow row{r.cells, 1.0 / r.cells, r.max_error, 0.0};
    row.unknowns = r.unknowns;
    series.rows.push_back(row);
  }
  if (!series.rows.empty()) series.rows.back().seconds = timer.seconds();  // the whole study
  series.note =
      "Zhu et al. 2010 Sec. 9.2: disc of radius 1/4 in the unit square, Eq. 17 deformation, "
      "Dirichlet left half, embedded traction right half; seconds: whole study on the last row";
  series.finish();
  return series;
}

ValidationReport run_validation(const ValidationOptions& o,
                                const std::function<void(const std::string&)>& progress) {
  const auto say = [&](const std::string& line) {
    if (progress) progress(line);
  };
  ValidationReport report;
  const auto append = [&](std::vector<ConvergenceSeries> more) {
    for (ConvergenceSeries& s : more) report.series.push_back(std::move(s));
  };
  for (const std::string engine : {"grid", "tet"}) {
    const std::vector<int>& sizes = engine == "grid" ? o.sphere_grid : o.sphere_tet;
    if (sizes.empty()) continue;
    for (double nu : o.sphere_poisson) {
      say("lame_sphere " + engine + " nu " + std::to_string(nu));
      LameSphere sphere;
      sphere.poisson_ratio = nu;
      append(lame_sphere_study(engine, sphere, sizes));
    }
  }
  for (const std::string engine : {"grid", "tet"}) {
    const std::vector<int>& sizes = engine == "grid" ? o.cantilever_grid : o.cantilever_tet;
    if (sizes.empty()) continue;
    for (CantileverLoad load : {CantileverLoad::TIP_FORCE, CantileverLoad::GRAVITY}) {
      say("cantilever " + engine);
      report.series.push_back(cantilever_study(engine, Cantilever{}, load, sizes));
    }
  }
  for (int n : o.patch)
    for (const std::string engine : {"grid", "tet"}) {
      say("patch_test " + engine);
      report.patch.push_back(patch_test(engine, n));
    }
  if (!o.disc.empty())
    for (double nu : o.disc_poisson) {
      say("disc nu " + std::to_string(nu));
      report.series.push_back(disc_series(nu, o.disc));
    }
  return report;
}

nlohmann::json to_json(const PatchTestResult& r) {
  return {{"study", "patch_test"},      {"engine", r.engine},
          {"resolution", r.resolution}, {"max_relative_error", r.max_relative_error},
          {"unknowns", r.unknowns},     {"converged", r.converged}};
}

nlohmann::json to_json(const ValidationReport& report) {
  nlohmann::json series = nlohmann::json::array(), patch = nlohmann::json::array();
  for (const ConvergenceSeries& s : report.series) series.push_back(to_json(s));
  for (const PatchTestResult& p : report.patch) patch.push_back(to_json(p));
  return {{"benchmark", "validation"}, {"series", series}, {"patch_test", patch}};
}

}  // namespace mgelastic::validation
