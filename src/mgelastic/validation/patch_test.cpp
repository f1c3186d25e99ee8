#include "mgelastic/validation/patch_test.hpp"

#include <cmath>

#include "mgelastic/grid/box_problem.hpp"
#include "mgelastic/grid/multigrid.hpp"
#include "mgelastic/validation/static_solve.hpp"

namespace mgelastic::validation {
namespace {

// A symmetric constant displacement gradient (a pure strain, no rotation).
Eigen::Matrix3d strain() {
  Eigen::Matrix3d g;
  g << 1.0, 0.3, -0.2, 0.3, -0.5, 0.4, -0.2, 0.4, 0.7;
  return 1e-3 * g;
}

PatchTestResult grid_patch_test(int n, double nu) {
  grid::BoxSpec spec;
  spec.cells = n;
  spec.poisson_ratio = nu;
  spec.body_force = 0;
  spec.boundary = grid::BoxBoundary::DIRICHLET;
  grid::ElasticityProblem<3> problem = grid::make_box_problem<3>(spec);
  const Eigen::Matrix3d g = strain();
  problem.body_force = {};
  problem.dirichlet_displacement = [g](const grid::Vec<3>& x) { return grid::Vec<3>(g * x); };
  grid::Multigrid<3, double> mg(problem, {});
  const grid::SolveReport report = mg.solve_accelerated(1e-13, 200);
  PatchTestResult result{"grid", n, 0.0, mg.unknowns(), report.converged};
  const auto& level = mg.finest();
  double scale = 0;
  for (int i = 0; i < 3; ++i)
    for (std::size_t k = 0; k < level.size(); ++k) {
      if (level.kind(i, k) != grid::VarKind::INTERIOR) continue;
      const grid::Vec<3> x = level.lattice.face_center(i, k);
      const double exact = (g * x)[i];
      scale = std::max(scale, std::abs(exact));
      result.max_relative_error =
          std::max(result.max_relative_error, std::abs(mg.solution(i, k) - exact));
    }
  result.max_relative_error /= scale;
  return result;
}

PatchTestResult tet_patch_test(int n, double nu) {
  // The unit cube; one constraint region so that the scene is valid, replaced below by all
  // boundary vertices.
  const nlohmann::json document = {
      {"engine", "tet"},
      {"geometry", {{"box", {{"center", {0.5, 0.5, 0.5}}, {"size", {1, 1, 1}}}}}},
      {"tet", {{"resolution", n}, {"tolerance", 1e-13}}},
      {"material", {{"youngs_modulus", 1e6}, {"poisson_ratio", nu}, {"density", 1000}}},
      {"constraints",
       {{{"region", {{"box", {{"center", {0, 0.5, 0.5}}, {"size", {0.02, 2, 2}}}}}}}}},
      {"loads", {{"gravity", {0, 0, 0}}}}};
  scene::TetSetup setup =
      scene::build_tet_setup(scene::parse_scene(document, "validation.json", "."));
  const Eigen::MatrixX3d& rest = setup.mesh.vertices;
  const auto on_boundary = [](const Eigen::Vector3d& x) {
    return (x.array().abs() < 1e-9).any() || ((x.array() - 1).abs() < 1e-9).any();
  };
  std::vector<int> boundary;
  for (Eigen::Index v = 0; v < rest.rows(); ++v)
    if (on_boundary(rest.row(v).transpose())) boundary.push_back(static_cast<int>(v));
  const Eigen::Matrix3d g = strain();
  tet::CorotatedSolver solver(setup.mesh, setup.materials, setup.settings);
  solver.set_dirichlet(boundary, [g](int, const Eigen::Vector3d& x, double) -> Eigen::Vector3d {
    return x + g * x;
  });
  PatchTestResult result{"tet", n, 0.0, 3 * static_cast<std::size_t>(rest.rows())};
  result.converged = solver.solve_static(30, 1e-13).static_converged;
  const Eigen::MatrixX3d u = solver.positions_matrix() - rest;
  double scale = 0;
  for (Eigen::Index v = 0; v < rest.rows(); ++v) {
    const Eigen::Vector3d exact = g * rest.row(v).transpose();
    scale = std::max(scale, exact.cwiseAbs().maxCoeff());
    if (!on_boundary(rest.row(v).transpose()))
      result.max_relative_error =
          std::max(result.max_relative_error, (u.row(v).transpose() - exact).cwiseAbs().maxCoeff());
  }
  result.max_relative_error /= scale;
  return result;
}

}  // namespace

PatchTestResult patch_test(const std::string& engine, int resolution, double poisson_ratio) {
  return engine == "grid" ? grid_patch_test(resolution, poisson_ratio)
                          : tet_patch_test(resolution, poisson_ratio);
}

}  // namespace mgelastic::validation
