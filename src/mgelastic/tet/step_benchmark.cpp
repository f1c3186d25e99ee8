#include "mgelastic/tet/step_benchmark.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <random>

#include "mgelastic/core/timer.hpp"
#include "mgelastic/geometry/tet_mesh_grid.hpp"
#include "mgelastic/tet/corotated_solver.hpp"
#include "mgelastic/tet/tet_multigrid.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace mgelastic::tet {

TetStepBenchmark run_tet_step_benchmark(int cells_across, int steps, double tolerance,
                                        int max_coarsest_vertices) {
  TetStepBenchmark r;
  r.cells_across = cells_across;
#ifdef _OPENMP
  r.threads = omp_get_max_threads();
#endif
  const double h = 0.25 / cells_across, dt = 1.0 / 60.0;
  const geometry::TetMesh mesh =
      geometry::regular_tet_grid(
          [](const Eigen::Vector3d&) { return true; },
          Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 0.25, 0.25)), h)
          .mesh;
  r.tets = mesh.tet_count();
  r.vertices = mesh.vertex_count();
  CorotatedSolverSettings settings;
  settings.time_step = dt;
  settings.gravity = Eigen::Vector3d(0, -9.81, 0);
  settings.pcg.tolerance = tolerance;
  CorotatedSolver solver(mesh, ElementMaterials::uniform(mesh.tet_count(), {1e6, 0.3, 1000.0}),
                         settings);
  std::vector<int> dirichlet;
  std::vector<char> fixed(mesh.vertex_count(), 0);
  for (int v = 0; v < mesh.vertex_count(); ++v)
    if (mesh.vertices(v, 0) < 1e-9 || mesh.vertices(v, 0) > 1.0 - 1e-9) {
      dirichlet.push_back(v);
      fixed[v] = 1;
    }
  solver.set_dirichlet(dirichlet, [](int, const Eigen::Vector3d& rest, double time) {
    if (rest[0] < 0.5) return Eigen::Vector3d(rest);
    const Eigen::Vector3d axis(0.0, 0.125, 0.125);
    const Eigen::Vector3d d(rest[0], rest[1] - axis[1], rest[2] - axis[2]);
    return Eigen::Vector3d(Eigen::AngleAxisd(6.0 * time, Eigen::Vector3d::UnitX()) * d + axis);
  });
  Timer setup;
  TetMultigridSettings mg_settings;
  mg_settings.hierarchy.max_coarsest_vertices = max_coarsest_vertices;
  TetMultigrid mg(mesh, fixed, solver.stiffness(), mg_settings);
  r.setup_seconds = setup.seconds();
  r.levels = mg.level_count();
  for (int l = 0; l < mg.level_count(); ++l)
    r.level_vertices.push_back(mg.hierarchy().vertex_count(l));
  r.stream_bytes = mg.stream_memory_bytes();

  std::mt19937 rng(1);
  std::normal_distribution<double> normal;
  Eigen::VectorXd b(3 * mesh.vertex_count());
  for (int i = 0; i < b.size(); ++i) b[i] = fixed[i / 3] != 0 ? 0.0 : normal(rng);
  PcgSettings pcg;
  pcg.tolerance = tolerance;
  for (int s = -1; s < steps; ++s) {  // step -1 warms up
    const StepStats& stats = solver.step();
    mg.update(solver.stiffness(), solver.body().vertex_mass(), 1.0, dt * dt);
    const MultigridUpdateTimes stream_times = mg.update_times();
    Timer timer;
    mg.update_coarse(GalerkinMethod::NAIVE);
    const double naive = mg.update_times().galerkin_seconds;
    timer.restart();
    Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size());
    mg.cycle(b, x);
    const double vcycle = timer.seconds();
    x.setZero();
    timer.restart();
    const PcgResult result = mg.solve_pcg(b, x, pcg);
    const double mg_pcg = timer.seconds();
    if (s < 0) continue;
    r.rotate_seconds += stats.rotate_seconds / steps;
    r.assemble_seconds += stats.assemble_seconds / steps;
    r.baseline_pcg_seconds += stats.solve_seconds / steps;
    r.baseline_pcg_iterations += static_cast<double>(stats.solve.iterations) / steps;
    r.fine_operator_seconds += stream_times.fine_seconds / steps;
    r.galerkin_stream_seconds += stream_times.galerkin_seconds / steps;
    r.factor_seconds += stream_times.factor_seconds / steps;
    r.galerkin_naive_seconds += naive / steps;
    r.vcycle_seconds += vcycle / steps;
    r.mg_pcg_seconds += mg_pcg / steps;
    r.mg_pcg_iterations += static_cast<double>(result.iterations) / steps;
  }
  // Rate on the last step's matrix.
  Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size()), res;
  double r3 = 1.0;
  for (int c = 1; c <= 10; ++c) {
    mg.cycle(b, x);
    mg.residual(b, x, res);
    if (c == 3) r3 = res.norm();
  }
  r.vcycle_rate = std::pow(res.norm() / r3, 1.0 / 7.0);
  const double common = r.rotate_seconds + r.assemble_seconds;
  r.mg_steps_per_second = 1.0 / (common + r.fine_operator_seconds + r.galerkin_stream_seconds +
                                 r.factor_seconds + r.mg_pcg_seconds);
  r.baseline_steps_per_second = 1.0 / (common + r.baseline_pcg_seconds);
  return r;
}

}  // namespace mgelastic::tet
