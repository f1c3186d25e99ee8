#include "mgelastic/tet/step_benchmark.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <ctime>
#include <random>

#include "mgelastic/core/error.hpp"
#include "mgelastic/core/timer.hpp"
#include "mgelastic/geometry/tet_mesh_grid.hpp"
#include "mgelastic/geometry/tet_mesh_readers.hpp"
#include "mgelastic/tet/block_jacobi_pcg.hpp"
#include "mgelastic/tet/corotated_solver.hpp"
#include "mgelastic/tet/mesh_refinement.hpp"

#ifdef _OPENMP
#include <omp.h>
#endif

namespace mgelastic::tet {
namespace {

constexpr double kStep = 1.0 / 60.0;

struct Problem {
  geometry::TetMesh mesh;
  std::string name;
  double youngs_modulus = 1e6;
  std::vector<int> dirichlet;
  DirichletMotion motion;
};

Problem bar(int cells) {
  Problem p;
  p.mesh = geometry::regular_tet_grid(
               [](const Eigen::Vector3d&) { return true; },
               Eigen::AlignedBox3d(Eigen::Vector3d::Zero(), Eigen::Vector3d(1.0, 0.25, 0.25)),
               0.25 / cells)
               .mesh;
  p.name = "bar " + std::to_string(cells);
  for (int v = 0; v < p.mesh.vertex_count(); ++v)
    if (p.mesh.vertices(v, 0) < 1e-9 || p.mesh.vertices(v, 0) > 1.0 - 1e-9)
      p.dirichlet.push_back(v);
  p.motion = [](int, const Eigen::Vector3d& rest, double time) {
    if (rest[0] < 0.5) return Eigen::Vector3d(rest);
    const Eigen::Vector3d axis(0.0, 0.125, 0.125);
    const Eigen::Vector3d d(rest[0], rest[1] - axis[1], rest[2] - axis[2]);
    return Eigen::Vector3d(Eigen::AngleAxisd(6.0 * time, Eigen::Vector3d::UnitX()) * d + axis);
  };
  return p;
}

Problem mesh_file(const std::string& file, int refinements) {
  Problem p;
  p.mesh = geometry::read_tet_mesh(file);
  for (int r = 0; r < refinements; ++r) p.mesh = refine_uniform(p.mesh);
  p.name = file + (refinements > 0 ? " x" + std::to_string(1 << (3 * refinements)) : "");
  const double low = p.mesh.vertices.col(1).minCoeff();
  const double height = p.mesh.vertices.col(1).maxCoeff() - low;
  p.youngs_modulus = 1e4 * height;
  for (int v = 0; v < p.mesh.vertex_count(); ++v)
    if (p.mesh.vertices(v, 1) < low + 0.1 * height) p.dirichlet.push_back(v);
  return p;
}

Eigen::VectorXd random_rhs(const std::vector<char>& fixed) {
  std::mt19937 rng(1);
  std::normal_distribution<double> normal;
  Eigen::VectorXd b(3 * static_cast<Eigen::Index>(fixed.size()));
  for (Eigen::Index i = 0; i < b.size(); ++i) b[i] = fixed[i / 3] != 0 ? 0.0 : normal(rng);
  return b;
}

}  // namespace

TetStepBenchmark run_tet_step_benchmark(const TetStepBenchmarkOptions& options) {
  if (options.steps < 1 || options.vcycles < 1 || !(options.tolerance > 0.0))
    throw Error("steps and vcycles >= 1 and a positive tolerance required",
                ErrorContext{std::string(), -1, "tet-step benchmark"});
  const Problem problem = options.mesh_file.empty()
                              ? bar(options.cells_across)
                              : mesh_file(options.mesh_file, options.refinements);
  TetStepBenchmark r;
  r.mesh = problem.name;
#ifdef _OPENMP
  r.threads = omp_get_max_threads();
#endif
  r.tets = problem.mesh.tet_count();
  r.vertices = problem.mesh.vertex_count();
  CorotatedSolverSettings settings;
  settings.time_step = kStep;
  settings.gravity = Eigen::Vector3d(0, -9.81, 0);
  settings.rotation_method = options.rotation;
  settings.linear_solver = LinearSolver::MULTIGRID;
  settings.vcycles = options.vcycles;
  settings.multigrid = options.multigrid;
  settings.pcg.tolerance = options.tolerance;
  CorotatedSolver solver(
      problem.mesh,
      ElementMaterials::uniform(problem.mesh.tet_count(), {problem.youngs_modulus, 0.3, 1000.0}),
      settings);
  solver.set_dirichlet(problem.dirichlet, problem.motion);
  std::vector<char> fixed(problem.mesh.vertex_count(), 0);
  for (const int v : problem.dirichlet) fixed[v] = 1;
  const Eigen::VectorXd b = random_rhs(fixed);
  PcgSettings pcg;
  pcg.tolerance = options.tolerance;
  pcg.max_iterations = 20000;
  const double n = options.steps;
  for (int s = -1; s < options.steps; ++s) {  // step -1 warms up (and builds the hierarchy)
    Timer timer;
    const std::clock_t cpu_start = std::clock();
    const StepStats stats = solver.step();
    const double step_seconds = timer.seconds();
    const double step_cpu = static_cast<double>(std::clock() - cpu_start) / CLOCKS_PER_SEC;
    TetMultigrid& mg = *solver.multigrid();
    if (s < 0) {
      r.setup_seconds = stats.galerkin_seconds - mg.update_times().galerkin_seconds -
                        mg.update_times().factor_seconds - mg.update_times().fine_seconds;
      continue;
    }
    const MultigridUpdateTimes stream = mg.update_times();
    r.rotate_seconds += stats.rotate_seconds / n;
    r.assemble_seconds += stats.assemble_seconds / n;
    r.fine_operator_seconds += stream.fine_seconds / n;
    r.galerkin_stream_seconds += stream.galerkin_seconds / n;
    r.factor_seconds += stream.factor_seconds / n;
    r.solve_seconds += stats.solve_seconds / n;
    r.step_seconds += step_seconds / n;
    r.step_cpu_seconds += step_cpu / n;
    r.step_residual += stats.solve.relative_residual / n;
    r.newton_iterations += stats.rotation.mean_newton_iterations / n;
    if (options.steps_only) continue;
    mg.update_coarse(GalerkinMethod::NAIVE);
    const double naive = mg.update_times().galerkin_seconds;
    mg.update_coarse(GalerkinMethod::STREAM);
    const StepSystem system(solver.stiffness(), solver.body().vertex_mass(), 1.0, kStep * kStep,
                            fixed);
    Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size());
    timer.restart();
    const PcgResult baseline = solve_pcg(system, b, x, pcg);
    r.baseline_pcg_seconds += timer.seconds() / n;
    r.baseline_pcg_iterations += baseline.iterations / n;
    x.setZero();
    timer.restart();
    const PcgResult preconditioned = mg.solve_pcg(b, x, pcg);
    r.mg_pcg_seconds += timer.seconds() / n;
    r.mg_pcg_iterations += preconditioned.iterations / n;
    x.setZero();
    timer.restart();
    const MultigridResult cycles = mg.solve(b, x, options.tolerance, 500);
    r.vcycles_to_tolerance_seconds += timer.seconds() / n;
    r.vcycles_to_tolerance += cycles.cycles / n;
    r.galerkin_naive_seconds += naive / n;
  }
  const TetMultigrid& mg = *solver.multigrid();
  r.levels = mg.level_count();
  for (int l = 0; l < mg.level_count(); ++l)
    r.level_vertices.push_back(mg.hierarchy().vertex_count(l));
  r.stream_bytes = mg.stream_memory_bytes();
  if (mg.level_count() > 1 && !options.multigrid.lexicographic) {
    r.smoother_colors = mg.smoother(0).color_count();
    r.smoother_clustered_vertices = mg.smoother(0).clustered_vertices();
  }
  r.feature_patches = mg.patches().patch_count();
  r.feature_patch_colors = mg.patches().color_count();
  r.steps_per_second = 1.0 / r.step_seconds;
  if (options.steps_only) return r;
  if (options.external_solver) {
    const StepSystem system(solver.stiffness(), solver.body().vertex_mass(), 1.0, kStep * kStep,
                            fixed);
    const Eigen::SparseMatrix<double, Eigen::RowMajor> a = system.to_sparse();
    r.external = options.external_solver(a, b, options.tolerance);
  }
  Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size()), res;
  double r3 = 1.0;
  for (int c = 1; c <= 10; ++c) {
    mg.cycle(b, x);
    mg.residual(b, x, res);
    if (c == 3) r3 = res.norm();
  }
  r.vcycle_rate = std::pow(res.norm() / r3, 1.0 / 7.0);
  const double multigrid_part =
      r.fine_operator_seconds + r.galerkin_stream_seconds + r.factor_seconds + r.solve_seconds;
  r.baseline_steps_per_second = 1.0 / (r.step_seconds - multigrid_part + r.baseline_pcg_seconds);
  return r;
}

}  // namespace mgelastic::tet
