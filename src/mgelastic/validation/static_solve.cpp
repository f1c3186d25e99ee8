#include "mgelastic/validation/static_solve.hpp"

#include "mgelastic/core/timer.hpp"
#include "mgelastic/grid/multigrid.hpp"
#include "mgelastic/grid/surface_interpolation.hpp"
#include "mgelastic/tet/corotated_solver.hpp"

namespace mgelastic::validation {

GridStatic solve_grid_static(const nlohmann::json& document, const DisplacementField& dirichlet,
                             double tolerance) {
  Timer timer;
  GridStatic run{scene::build_grid_setup(scene::parse_scene(document, "validation.json", "."))};
  if (dirichlet) run.setup.problem.dirichlet_displacement = dirichlet;
  grid::Multigrid<3, double> mg(run.setup.problem, {});
  const grid::SolveReport report = mg.solve_accelerated(tolerance, 400);
  run.converged = report.converged;
  run.unknowns = mg.unknowns();
  const auto value = [&](int field, std::ptrdiff_t k) { return mg.solution(field, k); };
  run.u = grid::node_displacement<double>(mg.finest(), value);
  run.seconds = timer.seconds();
  return run;
}

Eigen::Vector3d grid_displacement(const GridStatic& run, const Eigen::Vector3d& x) {
  return grid::interpolate_displacement(run.u, x, grid::SurfaceInterpolation::TRILINEAR);
}

TetStatic solve_tet_static(const nlohmann::json& document, const DisplacementField& dirichlet,
                           double tolerance) {
  Timer timer;
  TetStatic run{scene::build_tet_setup(scene::parse_scene(document, "validation.json", "."))};
  const scene::TetSetup& setup = run.setup;
  tet::CorotatedSolver solver(setup.mesh, setup.materials, setup.settings);
  if (dirichlet) {
    solver.set_dirichlet(setup.dirichlet_vertices,
                         [dirichlet](int, const Eigen::Vector3d& rest, double) -> Eigen::Vector3d {
                           return rest + dirichlet(rest);
                         });
  } else {
    solver.set_dirichlet(setup.dirichlet_vertices, setup.motion);
  }
  if (setup.surface_forces.size() > 0) solver.set_surface_forces(setup.surface_forces);
  run.converged = solver.solve_static(30, tolerance).static_converged;
  run.displacement = solver.positions_matrix() - setup.mesh.vertices;
  run.unknowns = 3 * static_cast<std::size_t>(setup.mesh.vertex_count());
  run.seconds = timer.seconds();
  return run;
}

void tet_surface_displacement(const TetStatic& run, Eigen::MatrixX3d& rest,
                              Eigen::MatrixX3d& displacement) {
  const geometry::TetMesh& mesh = run.setup.mesh;
  rest = tet::embedded_positions(run.setup.surface, mesh.vertices, mesh.tets);
  displacement =
      tet::embedded_positions(run.setup.surface, mesh.vertices + run.displacement, mesh.tets) -
      rest;
}

}  // namespace mgelastic::validation
