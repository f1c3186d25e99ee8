// V-cycle and MG-preconditioned CG on the implicit step system (M + h^2 K~) (tet_multigrid.hpp).
#include <gtest/gtest.h>

#include <Eigen/Eigenvalues>
#include <algorithm>
#include <cmath>
#include <cstdlib>
#include <ctime>
#include <filesystem>
#include <fstream>
#include <iomanip>
#include <iostream>
#include <random>

#include "mgelastic/core/threads.hpp"
#include "mgelastic/geometry/surface_mesh_readers.hpp"
#include "mgelastic/geometry/tet_mesh_boundary.hpp"
#include "mgelastic/geometry/tet_mesh_readers.hpp"
#include "mgelastic/tet/corotated_solver.hpp"
#include "mgelastic/tet/mesh_refinement.hpp"
#include "mgelastic/tet/tet_multigrid.hpp"
#include "tet/tet_test_support.hpp"

namespace mgelastic::tet {
namespace {

// The issue asks for a residual reduction <= 0.3 per V-cycle. Measured with the multicolour
// cluster smoother (docs/tet-engine.md, Multigrid): the paper's V(1,1) (one sweep each side)
// gives 0.59-0.62 on the stiff twisted bars, 0.48 on the bunny, 0.37 on the armadillo; with
// symmetric sweeps (forward + backward each side, SSOR factor 1.2) 0.35-0.37 on the bars, 0.22
// on the bunny, 0.05 on the armadillo. Bounds are the measured rates plus a margin of ~0.04, so a
// regression shows; 0.3 itself is asserted where it is reached (symmetric sweeps on bunny and
// armadillo).
constexpr double kBarVCycleRate = 0.65;
constexpr double kBarSymmetricRate = 0.41;
constexpr double kBunnyVCycleRate = 0.52;
constexpr double kIssueRate = 0.3;
constexpr double kBunnyPcgRate = 0.22;
constexpr double kArmadilloVCycleRate = 0.41;
// Resolution independence over three refinements: the issue's +0.05.
constexpr double kRateSpread = 0.05;
// A_0 assembled by the multigrid vs StepSystem: same sums, round-off only.
constexpr double kAssemblyRoundoff = 1e-12;

constexpr double kStep = 1.0 / 60.0;

// A step system after a few corotated steps: the bar's left end fixed, the right end turned about
// the bar axis (so K~ holds rotated element stiffnesses), E = 1e6 Pa so that h^2 K~ dominates M.
struct StepProblem {
  geometry::TetMesh mesh;
  std::vector<char> fixed;
  std::unique_ptr<CorotatedSolver> solver;
};

StepProblem twisted_bar(double h, double poisson = 0.3) {
  StepProblem problem;
  problem.mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.25, 0.25), h);
  CorotatedSolverSettings settings;
  settings.time_step = kStep;
  settings.gravity = Eigen::Vector3d(0, -9.81, 0);
  settings.pcg.tolerance = 1e-6;
  problem.solver = std::make_unique<CorotatedSolver>(
      problem.mesh, ElementMaterials::uniform(problem.mesh.tet_count(), {1e6, poisson, 1000.0}),
      settings);
  std::vector<int> dirichlet;
  problem.fixed.assign(problem.mesh.vertex_count(), 0);
  for (int v = 0; v < problem.mesh.vertex_count(); ++v)
    if (problem.mesh.vertices(v, 0) < 1e-9 || problem.mesh.vertices(v, 0) > 1.0 - 1e-9) {
      dirichlet.push_back(v);
      problem.fixed[v] = 1;
    }
  problem.solver->set_dirichlet(dirichlet, [](int, const Eigen::Vector3d& rest, double time) {
    if (rest[0] < 0.5) return Eigen::Vector3d(rest);
    const Eigen::Vector3d axis(0.0, 0.125, 0.125);
    const Eigen::Vector3d r(rest[0], rest[1] - axis[1], rest[2] - axis[2]);
    return Eigen::Vector3d(Eigen::AngleAxisd(6.0 * time, Eigen::Vector3d::UnitX()) * r + axis);
  });
  for (int i = 0; i < 6; ++i) problem.solver->step();
  return problem;
}

// Geometric mean of the residual ratio over cycles 4..10 from x = 0 and a seeded random b
// (zero on the constrained vertices).
double vcycle_rate(const TetMultigrid& mg, const std::vector<char>& fixed, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  Eigen::VectorXd b(3 * static_cast<int>(fixed.size())), x = Eigen::VectorXd::Zero(b.size()), r;
  for (int i = 0; i < b.size(); ++i) b[i] = fixed[i / 3] != 0 ? 0.0 : normal(rng);
  double r3 = 0.0;
  for (int c = 1; c <= 10; ++c) {
    mg.cycle(b, x);
    mg.residual(b, x, r);
    if (c == 3) r3 = r.norm();
  }
  return std::pow(r.norm() / r3, 1.0 / 7.0);
}

// Mean residual reduction per iteration of MG-PCG to 1e-8 from x = 0 (same right-hand side).
double mg_pcg_rate(const TetMultigrid& mg, const std::vector<char>& fixed, unsigned seed) {
  std::mt19937 rng(seed);
  std::normal_distribution<double> normal;
  Eigen::VectorXd b(3 * static_cast<int>(fixed.size())), x = Eigen::VectorXd::Zero(b.size());
  for (int i = 0; i < b.size(); ++i) b[i] = fixed[i / 3] != 0 ? 0.0 : normal(rng);
  PcgSettings settings;
  settings.tolerance = 1e-8;
  const PcgResult result = mg.solve_pcg(b, x, settings);
  EXPECT_TRUE(result.converged);
  return std::pow(result.relative_residual, 1.0 / std::max(1, result.iterations));
}

TetMultigrid step_multigrid(const StepProblem& problem, const TetMultigridSettings& settings = {}) {
  const CorotatedSolver& solver = *problem.solver;
  TetMultigrid mg(problem.mesh, problem.fixed, solver.stiffness(), settings);
  mg.update(solver.stiffness(), solver.body().vertex_mass(), 1.0, kStep * kStep);
  return mg;
}

TEST(TetMultigrid, FineOperatorEqualsTheStepSystem) {
  const StepProblem problem = twisted_bar(0.25 / 4);
  const TetMultigrid mg = step_multigrid(problem);
  const StepSystem system(problem.solver->stiffness(), problem.solver->body().vertex_mass(), 1.0,
                          kStep * kStep, problem.fixed);
  const Eigen::MatrixXd expected(system.to_sparse());
  const Eigen::MatrixXd actual(mg.level_matrix(0).to_sparse());
  EXPECT_LE((actual - expected).cwiseAbs().maxCoeff(),
            kAssemblyRoundoff * expected.cwiseAbs().maxCoeff());
}

TEST(TetMultigrid, VCycleRateOnTwistedBar) {
  const StepProblem problem = twisted_bar(0.25 / 8);
  const TetMultigrid mg = step_multigrid(problem);
  const double rate = vcycle_rate(mg, problem.fixed, 1);
  const double pcg_rate = mg_pcg_rate(mg, problem.fixed, 1);
  std::cout << "[ rate ] twisted bar " << problem.mesh.tet_count() << " tets, " << mg.level_count()
            << " levels: " << rate << " per V-cycle, " << pcg_rate << " per MG-PCG iteration\n";
  EXPECT_GE(mg.level_count(), 2);
  EXPECT_LE(rate, kBarVCycleRate);
  EXPECT_LE(pcg_rate, kIssueRate);
}

TEST(TetMultigrid, NaiveAndStreamHierarchiesGiveTheSameCycle) {
  const StepProblem problem = twisted_bar(0.25 / 6);
  TetMultigridSettings naive;
  naive.galerkin = GalerkinMethod::NAIVE;
  naive.hierarchy.max_coarsest_vertices = 100;
  TetMultigridSettings stream = naive;
  stream.galerkin = GalerkinMethod::STREAM;
  const TetMultigrid a = step_multigrid(problem, naive), b = step_multigrid(problem, stream);
  ASSERT_GE(a.level_count(), 3);
  EXPECT_NEAR(vcycle_rate(a, problem.fixed, 2), vcycle_rate(b, problem.fixed, 2), 1e-6);
}

// One symmetric-form cycle from z = 0 is the preconditioner B r; CG needs B symmetric and
// positive: r2 . B r1 = r1 . B r2, for the paper's sweeps and for symmetric sweeps (3 levels).
TEST(TetMultigrid, CycleFromZeroIsASymmetricOperator) {
  const StepProblem problem = twisted_bar(0.25 / 6);
  // V(1,1), symmetric sweeps, symmetric sweeps with feature patches (0 / 1 / 2).
  for (const int symmetric : {0, 1, 2}) {
    TetMultigridSettings settings;
    settings.hierarchy.max_coarsest_vertices = 100;
    settings.symmetric_sweeps = symmetric > 0;
    settings.patches.max_valence = symmetric == 2 ? 7 : 0;
    const TetMultigrid mg = step_multigrid(problem, settings);
    ASSERT_GE(mg.level_count(), 3);
    EXPECT_EQ(mg.patches().patch_count() > 0, symmetric == 2);
    std::mt19937 rng(9);
    std::normal_distribution<double> normal;
    Eigen::VectorXd r1(3 * problem.mesh.vertex_count()), r2(r1.size());
    for (int i = 0; i < r1.size(); ++i) {
      r1[i] = problem.fixed[i / 3] != 0 ? 0.0 : normal(rng);
      r2[i] = problem.fixed[i / 3] != 0 ? 0.0 : normal(rng);
    }
    Eigen::VectorXd b1 = Eigen::VectorXd::Zero(r1.size()), b2 = b1;
    mg.precondition(r1, b1);
    mg.precondition(r2, b2);
    EXPECT_NEAR(r2.dot(b1), r1.dot(b2), 1e-10 * r1.norm() * b2.norm()) << symmetric;
    EXPECT_GT(r1.dot(b1), 0.0) << symmetric;
  }
}

// Feature patches go parallel from 256 patches; coloured, the cycle is the same for 1 and 2
// threads (smoother and patch passes; 12 288-tet bar, patches around vertices in <= 12 tets).
TEST(TetMultigrid, CycleWithFeaturePatchesDoesNotDependOnTheThreadCount) {
  const StepProblem problem = twisted_bar(0.25 / 8);
  TetMultigridSettings settings;
  settings.symmetric_sweeps = true;
  settings.patches.max_valence = 12;
  const int threads = thread_count();
  set_thread_count(2);
  const TetMultigrid mg = step_multigrid(problem, settings);
  ASSERT_GE(mg.patches().patch_count(), 256);
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  Eigen::VectorXd b(3 * problem.mesh.vertex_count());
  for (int i = 0; i < b.size(); ++i) b[i] = problem.fixed[i / 3] != 0 ? 0.0 : normal(rng);
  Eigen::VectorXd one = Eigen::VectorXd::Zero(b.size()), two = one;
  set_thread_count(1);
  mg.cycle(b, one);
  set_thread_count(2);
  mg.cycle(b, two);
  set_thread_count(threads);
  EXPECT_GT(one.norm(), 0.0);
  EXPECT_EQ((one - two).cwiseAbs().maxCoeff(), 0.0);
}

// The bars of `mgelastic bench tet-step` (12 288 / 31 944 / 65 856 tets, 3 levels each).
TEST(TetMultigrid, RateIsIndependentOfResolution) {
  std::vector<double> single, symmetric;
  TetMultigridSettings symmetric_settings;
  symmetric_settings.symmetric_sweeps = true;
  for (const int cells : {8, 11, 14}) {
    const StepProblem problem = twisted_bar(0.25 / cells);
    const TetMultigrid mg = step_multigrid(problem),
                       mg_symmetric = step_multigrid(problem, symmetric_settings);
    single.push_back(vcycle_rate(mg, problem.fixed, 3));
    symmetric.push_back(vcycle_rate(mg_symmetric, problem.fixed, 3));
    std::cout << "[ rate ] " << problem.mesh.tet_count() << " tets, " << mg.level_count()
              << " levels: V(1,1) " << single.back() << ", symmetric sweeps " << symmetric.back()
              << "\n";
    EXPECT_GE(mg.level_count(), 3);
    EXPECT_LE(single.back(), kBarVCycleRate);
    EXPECT_LE(symmetric.back(), kBarSymmetricRate);
  }
  for (const std::vector<double>* rates : {&single, &symmetric})
    EXPECT_LE(*std::max_element(rates->begin(), rates->end()) -
                  *std::min_element(rates->begin(), rates->end()),
              kRateSpread);
}

// Adaptive feature patches (patch_seeds.hpp) on a bar large enough for the parallel sweeps
// (level 0 has > 4096 clusters): seeded where the cycle's power iteration leaves its error, they
// speed the symmetric cycle up, and seeds, patches and cycle are the same for 1 and 2 threads.
TEST(TetMultigrid, AdaptivePatchesSpeedUpTheCycleAndDoNotDependOnTheThreadCount) {
  const StepProblem problem = twisted_bar(0.25 / 12);
  TetMultigridSettings symmetric;
  symmetric.symmetric_sweeps = true;
  TetMultigridSettings adaptive = symmetric;
  adaptive.adaptive_patches.rounds = 2;
  adaptive.adaptive_patches.target_contraction = 0.0;  // both rounds
  const int threads = thread_count();
  set_thread_count(1);
  const TetMultigrid one = step_multigrid(problem, adaptive);
  set_thread_count(2);
  const TetMultigrid two = step_multigrid(problem, adaptive),
                     plain = step_multigrid(problem, symmetric);
  ASSERT_GT(one.smoother(0).cluster_count(), 4096);
  ASSERT_EQ(one.adaptive_contractions().size(), 2U);
  EXPECT_LT(one.adaptive_contractions()[1], one.adaptive_contractions()[0]);
  ASSERT_GT(one.patches().patch_count(), 0);
  ASSERT_EQ(one.patches().patch_count(), two.patches().patch_count());
  for (int p = 0; p < one.patches().patch_count(); ++p)
    EXPECT_EQ(one.patches().patch(p), two.patches().patch(p)) << "patch " << p;
  const double rate = vcycle_rate(two, problem.fixed, 3),
               plain_rate = vcycle_rate(plain, problem.fixed, 3);
  std::cout << "[ rate ] bar " << problem.mesh.tet_count() << " tets: symmetric " << plain_rate
            << ", + " << two.patches().patch_count() << " adaptive patches " << rate
            << " (contractions " << one.adaptive_contractions()[0] << ", "
            << one.adaptive_contractions()[1] << ")\n";
  EXPECT_LT(rate, plain_rate);
  Eigen::VectorXd b = Eigen::VectorXd::Zero(3 * problem.mesh.vertex_count());
  for (int v = 0; v < problem.mesh.vertex_count(); ++v)
    if (problem.fixed[v] == 0) b.segment<3>(3 * v) = Eigen::Vector3d(1.0, -0.5, 0.25 * (v % 7));
  Eigen::VectorXd x1 = Eigen::VectorXd::Zero(b.size()), x2 = x1;
  set_thread_count(1);
  one.cycle(b, x1);
  set_thread_count(2);
  one.cycle(b, x2);
  set_thread_count(threads);
  EXPECT_EQ((x1 - x2).cwiseAbs().maxCoeff(), 0.0);
}

TEST(TetMultigrid, SolvesToToleranceAndPreconditionsCg) {
  const StepProblem problem = twisted_bar(0.25 / 8);
  const TetMultigrid mg = step_multigrid(problem);
  std::mt19937 rng(4);
  std::normal_distribution<double> normal;
  Eigen::VectorXd b(3 * problem.mesh.vertex_count());
  for (int i = 0; i < b.size(); ++i) b[i] = problem.fixed[i / 3] != 0 ? 0.0 : normal(rng);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size());
  const MultigridResult cycles = mg.solve(b, x, 1e-8, 40);
  EXPECT_TRUE(cycles.converged);
  PcgSettings settings;
  settings.tolerance = 1e-8;
  Eigen::VectorXd y = Eigen::VectorXd::Zero(b.size());
  const PcgResult pcg = mg.solve_pcg(b, y, settings);
  EXPECT_TRUE(pcg.converged);
  EXPECT_LT(pcg.iterations, cycles.cycles);
  // Block-Jacobi PCG on the same system needs many more iterations.
  const StepSystem system(problem.solver->stiffness(), problem.solver->body().vertex_mass(), 1.0,
                          kStep * kStep, problem.fixed);
  Eigen::VectorXd z = Eigen::VectorXd::Zero(b.size());
  const PcgResult jacobi = solve_pcg(system, b, z, settings);
  std::cout << "[ solve ] V-cycles " << cycles.cycles << ", MG-PCG " << pcg.iterations
            << ", block-Jacobi PCG " << jacobi.iterations << " iterations to 1e-8\n";
  EXPECT_LT(pcg.iterations, jacobi.iterations);
  EXPECT_LE((x - z).norm(), 1e-6 * z.norm());
}

// A real mesh sagging under gravity: lowest 10 % of its height fixed, E = 1e4 Pa x height (how
// much h^2 K~ dominates M depends on the model's units, see stiffness_to_mass), three implicit
// Euler steps taken with MG-PCG (tolerance 1e-6; fewer cycles than plain V-cycles).
StepProblem sagging_problem(geometry::TetMesh mesh) {
  StepProblem problem;
  problem.mesh = std::move(mesh);
  const double low = problem.mesh.vertices.col(1).minCoeff();
  const double extent = problem.mesh.vertices.col(1).maxCoeff() - low;
  std::vector<int> dirichlet;
  problem.fixed.assign(problem.mesh.vertex_count(), 0);
  for (int v = 0; v < problem.mesh.vertex_count(); ++v)
    if (problem.mesh.vertices(v, 1) < low + 0.1 * extent) {
      dirichlet.push_back(v);
      problem.fixed[v] = 1;
    }
  CorotatedSolverSettings settings;
  settings.time_step = kStep;
  settings.gravity = Eigen::Vector3d(0, -9.81, 0);
  settings.linear_solver = LinearSolver::MG_PCG;
  settings.pcg.tolerance = 1e-6;
  problem.solver = std::make_unique<CorotatedSolver>(
      problem.mesh,
      ElementMaterials::uniform(problem.mesh.tet_count(), {1e4 * extent, 0.3, 1000.0}), settings);
  problem.solver->set_dirichlet(dirichlet);
  for (int i = 0; i < 3; ++i) EXPECT_TRUE(problem.solver->step().solve.converged);
  return problem;
}

StepProblem sagging_mesh(const std::string& file, int refinements = 0) {
  const char* dir = std::getenv("MGELASTIC_DATA_DIR");
  if (dir == nullptr || std::string(dir).empty()) return {};
  const std::filesystem::path path = std::filesystem::path(dir) / file;
  EXPECT_TRUE(std::filesystem::exists(path))
      << "MGELASTIC_DATA_DIR is set but " << path << " is missing";
  geometry::TetMesh mesh = geometry::read_tet_mesh(path);
  for (int r = 0; r < refinements; ++r) mesh = refine_uniform(mesh);
  return sagging_problem(std::move(mesh));
}

// Stiffness over mass at the element scale, dt^2 E / (rho l^2) with l the mean edge: the step
// matrix is mass-dominated when it is small (every smoother converges fast there) and
// stiffness-dominated when it is large (the multigrid's own rate). E = 1e4 x height makes it
// scale like 1 / (model size) at a fixed element count, so meshes in different units are not
// comparable by their rate alone.
double stiffness_to_mass(const geometry::TetMesh& mesh) {
  const double extent = mesh.vertices.col(1).maxCoeff() - mesh.vertices.col(1).minCoeff();
  const double edge = mean_edge_length(mesh);
  return kStep * kStep * 1e4 * extent / (1000.0 * edge * edge);
}

// The issue's <= 0.3 per V-cycle on the armadillo (54 985 tets, 4 levels down to ~300 vertices):
// reached with symmetric sweeps (measured 0.05); the paper's single sweeps give 0.37.
TEST(TetMultigrid, VCycleRateOnArmadillo) {
  const StepProblem problem = sagging_mesh("armadillo_13k.msh");
  if (problem.mesh.tet_count() == 0) GTEST_SKIP() << "MGELASTIC_DATA_DIR not set";
  TetMultigridSettings symmetric;
  symmetric.symmetric_sweeps = true;
  const TetMultigrid single_mg = step_multigrid(problem),
                     symmetric_mg = step_multigrid(problem, symmetric);
  const double single = vcycle_rate(single_mg, problem.fixed, 6);
  const double both = vcycle_rate(symmetric_mg, problem.fixed, 6);
  std::cout << "[ rate ] armadillo " << problem.mesh.tet_count() << " tets, "
            << single_mg.level_count() << " levels: V(1,1) " << single << ", symmetric sweeps "
            << both << " per V-cycle\n";
  EXPECT_GE(single_mg.level_count(), 3);
  EXPECT_LE(single, kArmadilloVCycleRate);
  EXPECT_LE(both, kIssueRate);
}

// Mesh size on real meshes (measured, docs/tet-engine.md "Convergence"): the armadillo at 3.7k
// tets (armadillo_4k), the same refined once (30k) and the independently meshed armadillo_13k
// (55k); the bunny refined once (155k). Symmetric sweeps: 0.13 / 0.37 / 0.04 and 0.51; V(1,1):
// 0.43 / 0.65 / 0.33 and 0.67. armadillo_4k and armadillo_13k differ in stiffness/mass (0.28 vs
// 0.038), so "the finer is not slower" between them (asserted, +0.05) says little; the refined
// meshes are stiffness-dominated (1.1-1.8) and slower, bounded at the measured rates plus a
// margin so that a regression shows. The same-body size comparison is the tetgen test below.
constexpr double kRefinedVCycleRate = 0.71;
constexpr double kRefinedSymmetricRate = 0.56;

TEST(TetMultigrid, RateOnRealMeshesOfSeveralSizes) {
  if (std::getenv("MGELASTIC_DATA_DIR") == nullptr) GTEST_SKIP() << "MGELASTIC_DATA_DIR not set";
  TetMultigridSettings symmetric;
  symmetric.symmetric_sweeps = true;
  struct Rates {
    double single = 0.0, both = 0.0;
  };
  const auto measure = [&](const std::string& file, int refinements) {
    const StepProblem problem = sagging_mesh(file, refinements);
    Rates rates;
    if (problem.mesh.tet_count() == 0) return rates;
    const TetMultigrid mg = step_multigrid(problem),
                       mg_symmetric = step_multigrid(problem, symmetric);
    rates.single = vcycle_rate(mg, problem.fixed, 8);
    rates.both = vcycle_rate(mg_symmetric, problem.fixed, 8);
    std::cout << "[ rate ] " << file << " x" << (1 << (3 * refinements)) << ": "
              << problem.mesh.tet_count() << " tets, stiffness/mass "
              << stiffness_to_mass(problem.mesh) << ", " << mg.level_count() << " levels: V(1,1) "
              << rates.single << ", symmetric sweeps " << rates.both << "\n";
    return rates;
  };
  const Rates coarse = measure("armadillo_4k.node", 0);
  const Rates fine = measure("armadillo_13k.msh", 0);
  EXPECT_LE(fine.single, coarse.single + kRateSpread);
  EXPECT_LE(fine.both, coarse.both + kRateSpread);
  EXPECT_LE(coarse.both, kIssueRate);
  EXPECT_LE(fine.both, kIssueRate);
  for (const auto& [file, refinements] :
       std::vector<std::pair<std::string, int>>{{"armadillo_4k.node", 1}, {"bunny.msh", 1}}) {
    const Rates refined = measure(file, refinements);
    EXPECT_LE(refined.single, kRefinedVCycleRate) << file;
    EXPECT_LE(refined.both, kRefinedSymmetricRate) << file;
  }
}

// Independently meshed sizes (what the paper did: bunny, horse, dragon at 11k / 34k / 67k tets):
// TetGen (the Debian `tetgen` executable; AGPL, so it is run, never linked) tetrahedralizes one
// surface at three maximum tet volumes with radius-edge ratio <= 1.5. Surfaces: the boundary of
// armadillo_4k (2 102 triangles; armadillo.obj's 86k triangles give >= 150k tets) and bunny_10k.obj
// with -Y (its 10k scanned triangles kept unsplit; quality refinement of them alone gives 148k
// tets), hence 18k / 29k / 68k and 33k / 46k / 76k tets. Same body, same E: the finer mesh is more
// stiffness-dominated (stiffness_to_mass ~ 1 / l^2), so this is the honest size comparison.
// Measured (docs/tet-engine.md, Convergence): bunny V(1,1) 0.54 / 0.54 / 0.50, symmetric sweeps
// 0.27 / 0.26 / 0.24: the issue's <= 0.3 with the finest within +0.05 of the coarsest holds and
// is asserted. Armadillo V(1,1) 0.56 / 0.62 / 0.72, symmetric 0.29 / 0.43 / 0.55: not met; the
// slowest mode is two thin claw tips moving against each other inside one coarse cube, too smooth
// for the smoother and not representable by the coarse space; it weighs more as the step matrix
// gets stiffness-dominated. Composite coarse cubes (coarse DOFs per connected piece of a cube)
// leave these rates unchanged (0.29 / 0.43 / 0.55): the slow tips are connected inside their
// cube. Its rates (and the bunny's V(1,1)) are bounded at the measured value plus a margin so
// that a regression shows.
// Feature patches (feature_patches.hpp: block solves around vertices in <= 7 tets, 12 vertices
// each) on top of the symmetric sweeps bring every size of both models to <= 0.3 (asserted); the
// armadillo's finest is still slower than its coarsest by more than 0.05 (0.07 / 0.09 / 0.24).
constexpr int kFeaturePatchValence = 7;
// Adaptive patches (patch_seeds.hpp) on top of those: up to 10 rounds of seeding where the cycle's
// own slow error concentrates, until its power-iteration contraction is <= 0.1. Same settings for
// both models: every size <= 0.3 and, for both, all three sizes within 0.05 of each other (the
// issue's size independence), asserted: armadillo 0.073 / 0.088 / 0.084, bunny 0.100 / 0.081 /
// 0.099 (0 / 0 / 4 and 2 / 3 / 5 rounds of patches before the contraction met 0.1).
constexpr int kAdaptivePatchRounds = 10;
constexpr double kTetGenVCycleRate = 0.76;
constexpr double kTetGenSymmetricRate = 0.60;

geometry::TriangleMesh surface_of(const std::filesystem::path& path) {
  if (path.extension() == ".obj") return geometry::read_surface_mesh(path);
  const geometry::TetMesh mesh = geometry::read_tet_mesh(path);
  const geometry::TetMeshBoundary boundary = geometry::tet_mesh_boundary(mesh);
  geometry::TriangleMesh surface;
  surface.vertices.resize(static_cast<Eigen::Index>(boundary.mesh_vertex.size()), 3);
  for (std::size_t i = 0; i < boundary.mesh_vertex.size(); ++i)
    surface.vertices.row(static_cast<Eigen::Index>(i)) = mesh.vertices.row(boundary.mesh_vertex[i]);
  surface.triangles = boundary.triangles;
  return surface;
}

void write_off(const geometry::TriangleMesh& surface, const std::filesystem::path& path) {
  std::ofstream out(path);
  out << std::setprecision(17) << "OFF\n"
      << surface.vertex_count() << " " << surface.triangle_count() << " 0\n";
  for (Eigen::Index v = 0; v < surface.vertex_count(); ++v)
    out << surface.vertices(v, 0) << " " << surface.vertices(v, 1) << " " << surface.vertices(v, 2)
        << "\n";
  for (Eigen::Index t = 0; t < surface.triangle_count(); ++t)
    out << "3 " << surface.triangles(t, 0) << " " << surface.triangles(t, 1) << " "
        << surface.triangles(t, 2) << "\n";
  ASSERT_TRUE(out.good()) << "cannot write " << path;
}

// Runs `tetgen -<switches>Q surface.off`; empty mesh (and a test failure) when it fails.
geometry::TetMesh tetgen_mesh(const std::filesystem::path& off, const std::string& switches) {
  const std::string command =
      "tetgen -" + switches + "Q " + off.string() + " > " + off.string() + ".log 2>&1";
  const int status = std::system(command.c_str());
  const std::filesystem::path node = off.parent_path() / (off.stem().string() + ".1.node");
  if (status != 0 || !std::filesystem::exists(node)) {
    ADD_FAILURE() << "'" << command << "' failed (status " << status
                  << "); is tetgen installed? scripts/install-deps.sh installs it";
    return {};
  }
  geometry::TetMesh mesh = geometry::read_tet_mesh(node);
  // MG_TETGEN_KEEP=dir keeps the meshes (as <surface>-<switches>.node/.ele) for the diagnostics
  // and `mgelastic bench tet-step --mesh`.
  if (const char* keep = std::getenv("MG_TETGEN_KEEP"); keep != nullptr && *keep != 0)
    for (const char* extension : {".node", ".ele"})
      std::filesystem::copy_file(
          off.parent_path() / (off.stem().string() + ".1" + extension),
          std::filesystem::path(keep) / (off.stem().string() + "-" + switches + extension),
          std::filesystem::copy_options::overwrite_existing);
  std::filesystem::remove(node);
  std::filesystem::remove(off.parent_path() / (off.stem().string() + ".1.ele"));
  std::filesystem::remove(off.parent_path() / (off.stem().string() + ".1.face"));
  std::filesystem::remove(off.parent_path() / (off.stem().string() + ".1.edge"));
  return mesh;
}

TEST(TetMultigrid, RateOnTetGenMeshesOfSeveralSizes) {
  const char* dir = std::getenv("MGELASTIC_DATA_DIR");
  if (dir == nullptr || std::string(dir).empty()) GTEST_SKIP() << "MGELASTIC_DATA_DIR not set";
  const std::filesystem::path work = std::filesystem::temp_directory_path() /
                                     ("mgelastic_tetgen_" + std::to_string(std::random_device()()));
  std::filesystem::create_directories(work);
  TetMultigridSettings symmetric;
  symmetric.symmetric_sweeps = true;
  TetMultigridSettings patched = symmetric;
  patched.patches.max_valence = kFeaturePatchValence;
  TetMultigridSettings adaptive = patched;
  adaptive.adaptive_patches.rounds = kAdaptivePatchRounds;
  struct Model {
    std::string file;
    std::vector<std::string> switches;
    bool meets_issue;  // symmetric <= 0.3 at every size, finest <= coarsest + 0.05 asserted
  };
  const std::vector<Model> models{
      {"armadillo_4k.node", {"pq1.5", "pq1.5a0.0012", "pq1.5a0.00016"}, false},
      {"bunny_10k.obj", {"pq1.5Y", "pq1.5Ya0.000015", "pq1.5Ya0.000006"}, true}};
  for (const Model& model : models) {
    const std::filesystem::path path = std::filesystem::path(dir) / model.file;
    ASSERT_TRUE(std::filesystem::exists(path))
        << "MGELASTIC_DATA_DIR is set but " << path << " is missing";
    const std::filesystem::path off = work / (path.stem().string() + ".off");
    write_off(surface_of(path), off);
    std::vector<double> single, both, with_patches, with_adaptive;
    for (const std::string& switches : model.switches) {
      geometry::TetMesh mesh = tetgen_mesh(off, switches);
      ASSERT_GT(mesh.tet_count(), 0) << model.file << " -" << switches;
      const double ratio = stiffness_to_mass(mesh);
      const StepProblem problem = sagging_problem(std::move(mesh));
      const TetMultigrid mg = step_multigrid(problem),
                         mg_symmetric = step_multigrid(problem, symmetric),
                         mg_patched = step_multigrid(problem, patched),
                         mg_adaptive = step_multigrid(problem, adaptive);
      single.push_back(vcycle_rate(mg, problem.fixed, 8));
      both.push_back(vcycle_rate(mg_symmetric, problem.fixed, 8));
      with_patches.push_back(vcycle_rate(mg_patched, problem.fixed, 8));
      with_adaptive.push_back(vcycle_rate(mg_adaptive, problem.fixed, 8));
      std::cout << "[ rate ] " << model.file << " tetgen -" << switches << ": "
                << problem.mesh.tet_count() << " tets, stiffness/mass " << ratio << ", "
                << mg.level_count() << " levels: V(1,1) " << single.back() << ", symmetric sweeps "
                << both.back() << ", symmetric + " << mg_patched.patches().patch_count()
                << " feature patches " << with_patches.back() << ", + adaptive ("
                << mg_adaptive.patches().patch_count() << " patches after "
                << mg_adaptive.adaptive_contractions().size() << " power iterations) "
                << with_adaptive.back() << "\n";
      EXPECT_LE(with_patches.back(), kIssueRate) << model.file << " -" << switches;
      EXPECT_LE(with_adaptive.back(), kIssueRate) << model.file << " -" << switches;
      EXPECT_LE(single.back(), kTetGenVCycleRate) << model.file << " -" << switches;
      EXPECT_LE(both.back(), kTetGenSymmetricRate) << model.file << " -" << switches;
    }
    if (model.meets_issue) {
      EXPECT_LE(*std::max_element(both.begin(), both.end()), kIssueRate) << model.file;
      EXPECT_LE(single.back(), single.front() + kRateSpread) << model.file;
      EXPECT_LE(both.back(), both.front() + kRateSpread) << model.file;
      EXPECT_LE(with_patches.back(), with_patches.front() + kRateSpread) << model.file;
    }
    EXPECT_LE(*std::max_element(with_adaptive.begin(), with_adaptive.end()) -
                  *std::min_element(with_adaptive.begin(), with_adaptive.end()),
              kRateSpread)
        << model.file;
  }
  std::filesystem::remove_all(work);
}

TEST(TetMultigrid, VCycleRateOnBunny) {
  const char* dir = std::getenv("MGELASTIC_DATA_DIR");
  if (dir == nullptr || std::string(dir).empty()) GTEST_SKIP() << "MGELASTIC_DATA_DIR not set";
  const std::filesystem::path path = std::filesystem::path(dir) / "bunny.msh";
  ASSERT_TRUE(std::filesystem::exists(path))
      << "MGELASTIC_DATA_DIR is set but " << path << " is missing";
  StepProblem problem;
  problem.mesh = geometry::read_tet_mesh(path);
  const double low = problem.mesh.vertices.col(1).minCoeff();
  const double extent = problem.mesh.vertices.col(1).maxCoeff() - low;
  std::vector<int> dirichlet;
  problem.fixed.assign(problem.mesh.vertex_count(), 0);
  for (int v = 0; v < problem.mesh.vertex_count(); ++v)
    if (problem.mesh.vertices(v, 1) < low + 0.1 * extent) {
      dirichlet.push_back(v);
      problem.fixed[v] = 1;
    }
  CorotatedSolverSettings settings;
  settings.time_step = kStep;
  settings.gravity = Eigen::Vector3d(0, -9.81, 0);
  settings.pcg.tolerance = 1e-6;
  // Stiff relative to the model's size (h^2 K~ dominates M); a few sagging steps rotate K~.
  problem.solver = std::make_unique<CorotatedSolver>(
      problem.mesh,
      ElementMaterials::uniform(problem.mesh.tet_count(), {1e4 * extent, 0.3, 1000.0}), settings);
  problem.solver->set_dirichlet(dirichlet);
  for (int i = 0; i < 3; ++i) problem.solver->step();
  const TetMultigrid mg = step_multigrid(problem);
  TetMultigridSettings symmetric;
  symmetric.symmetric_sweeps = true;
  const TetMultigrid symmetric_mg = step_multigrid(problem, symmetric);
  const double rate = vcycle_rate(mg, problem.fixed, 5);
  const double symmetric_rate = vcycle_rate(symmetric_mg, problem.fixed, 5);
  const double pcg_rate = mg_pcg_rate(mg, problem.fixed, 5);
  std::cout << "[ rate ] bunny " << problem.mesh.tet_count() << " tets, " << mg.level_count()
            << " levels: V(1,1) " << rate << ", symmetric sweeps " << symmetric_rate
            << " per V-cycle, " << pcg_rate << " per MG-PCG iteration\n";
  EXPECT_GE(mg.level_count(), 3);
  EXPECT_LE(rate, kBunnyVCycleRate);
  EXPECT_LE(symmetric_rate, kIssueRate);
  EXPECT_LE(pcg_rate, kBunnyPcgRate);
}

}  // namespace
}  // namespace mgelastic::tet

namespace mgelastic::tet {
namespace {

// Diagnostics (not run by default): MG_MESH=bar:N | file, MG_REFINE, MG_FACTOR, MG_SWEEPS,
// MG_SYM, MG_COARSEST, MG_NU, MG_E, MG_VALENCE / MG_PATCH (feature patches).
double env_or(const char* name, double fallback) {
  const char* v = std::getenv(name);
  return v != nullptr && *v != 0 ? std::atof(v) : fallback;
}

// MG_VALENCE / MG_PATCH: valence-seeded feature patches; MG_ADAPT (rounds), MG_ADAPT_CYCLES,
// MG_ADAPT_TAU, MG_ADAPT_FRACTION, MG_ADAPT_SIZE, MG_ADAPT_TARGET: adaptive patches
// (patch_seeds.hpp).
void env_patch_settings(TetMultigridSettings& settings) {
  settings.patches.max_valence = static_cast<int>(env_or("MG_VALENCE", 0));
  settings.patches.max_size = static_cast<int>(env_or("MG_PATCH", 12));
  settings.adaptive_patches.rounds = static_cast<int>(env_or("MG_ADAPT", 0));
  settings.adaptive_patches.cycles = static_cast<int>(env_or("MG_ADAPT_CYCLES", 6));
  settings.adaptive_patches.threshold = env_or("MG_ADAPT_TAU", 0.01);
  settings.adaptive_patches.target_contraction = env_or("MG_ADAPT_TARGET", 0.1);
  settings.adaptive_patches.max_seed_fraction = env_or("MG_ADAPT_FRACTION", 0.01);
  settings.adaptive_patches.max_size = static_cast<int>(env_or("MG_ADAPT_SIZE", 30));
}

TEST(TetMultigridDiagnostics, DISABLED_Explore) {
  const std::string spec = std::getenv("MG_MESH") ? std::getenv("MG_MESH") : "bar:8";
  StepProblem problem;
  const double nu = env_or("MG_NU", 0.3);
  if (spec.rfind("bar:", 0) == 0) {
    problem = twisted_bar(0.25 / std::atoi(spec.c_str() + 4), nu);
  } else {
    problem.mesh = geometry::read_tet_mesh(spec);
    for (int r = 0; r < static_cast<int>(env_or("MG_REFINE", 0)); ++r)
      problem.mesh = refine_uniform(problem.mesh);
    const double low = problem.mesh.vertices.col(1).minCoeff();
    const double extent = problem.mesh.vertices.col(1).maxCoeff() - low;
    std::vector<int> dirichlet;
    problem.fixed.assign(problem.mesh.vertex_count(), 0);
    for (int v = 0; v < problem.mesh.vertex_count(); ++v)
      if (problem.mesh.vertices(v, 1) < low + env_or("MG_FIX", 0.1) * extent) {
        dirichlet.push_back(v);
        problem.fixed[v] = 1;
      }
    CorotatedSolverSettings settings;
    settings.time_step = kStep;
    settings.gravity = Eigen::Vector3d(0, -9.81, 0);
    settings.linear_solver = LinearSolver::CHOLESKY;
    problem.solver = std::make_unique<CorotatedSolver>(
        problem.mesh,
        ElementMaterials::uniform(problem.mesh.tet_count(),
                                  {env_or("MG_E", 1e4) * extent, nu, 1000.0}),
        settings);
    problem.solver->set_dirichlet(dirichlet);
    for (int i = 0; i < 3; ++i) problem.solver->step();
  }
  TetMultigridSettings settings;
  settings.hierarchy.first_cell_factor = env_or("MG_FACTOR", 1.587);
  settings.hierarchy.max_coarsest_vertices = static_cast<int>(env_or("MG_COARSEST", 400));
  settings.pre_smoothing = settings.post_smoothing = static_cast<int>(env_or("MG_SWEEPS", 1));
  settings.symmetric_sweeps = env_or("MG_SYM", 0) != 0;
  settings.relaxation = env_or("MG_OMEGA", 1.0);
  settings.symmetric_relaxation = env_or("MG_OMEGA", 1.2);
  settings.lexicographic = env_or("MG_LEX", 0) != 0;
  settings.smoother.strong_coupling = env_or("MG_STRONG", 0.3);
  settings.smoother.max_cluster_size = static_cast<int>(env_or("MG_CLUSTER", 4));
  env_patch_settings(settings);
  std::vector<double> edges;
  for (int t = 0; t < problem.mesh.tet_count(); ++t) {
    const Eigen::Matrix<double, 3, 4> c = problem.mesh.corners(t);
    for (int i = 0; i < 4; ++i)
      for (int j = i + 1; j < 4; ++j) edges.push_back((c.col(i) - c.col(j)).norm());
  }
  std::sort(edges.begin(), edges.end());
  std::cout << "edge percentiles 1/10/50/90/99: " << edges[edges.size() / 100] << " "
            << edges[edges.size() / 10] << " " << edges[edges.size() / 2] << " "
            << edges[edges.size() * 9 / 10] << " " << edges[edges.size() * 99 / 100] << "\n";
  const std::clock_t setup_start = std::clock();
  const TetMultigrid mg = step_multigrid(problem, settings);
  std::cout << mg.patches().patch_count() << " feature patches in " << mg.patches().color_count()
            << " colours; update: coarsest + smoother + patch factors "
            << 1e3 * mg.update_times().factor_seconds << " ms (wall)\n";
  std::cout << "cpu ms setup + first update "
            << 1000.0 * static_cast<double>(std::clock() - setup_start) / CLOCKS_PER_SEC << "\n";
  std::cout << "adaptive rounds' contractions:";
  for (const double c : mg.adaptive_contractions()) std::cout << " " << c;
  std::cout << "\n";
  std::cout << problem.mesh.tet_count() << " tets, levels:";
  for (int l = 0; l < mg.level_count(); ++l) std::cout << " " << mg.hierarchy().vertex_count(l);
  std::cout << "\n";
  if (!settings.lexicographic)
    for (int l = 0; l + 1 < mg.level_count(); ++l)
      std::cout << "smoother level " << l << ": " << mg.smoother(l).color_count() << " colours, "
                << mg.smoother(l).clustered_vertices() << " vertices in clusters (largest "
                << mg.smoother(l).largest_cluster() << ")\n";
  std::mt19937 rng(7);
  std::normal_distribution<double> normal;
  Eigen::VectorXd b(3 * problem.mesh.vertex_count()), x = Eigen::VectorXd::Zero(b.size());
  for (int i = 0; i < b.size(); ++i) b[i] = problem.fixed[i / 3] != 0 ? 0.0 : normal(rng);
  for (int c = 0; c < 8; ++c) mg.cycle(b, x);
  const std::vector<LevelResiduals> trace = mg.cycle_traced(b, x);
  for (int l = 0; l < mg.level_count(); ++l)
    std::cout << "level " << l << ": entry " << trace[l].entry << " pre " << trace[l].pre_smoothed
              << " corrected " << trace[l].corrected << " post " << trace[l].post_smoothed << "\n";
  std::cout << "rate " << vcycle_rate(mg, problem.fixed, 1) << " pcg "
            << mg_pcg_rate(mg, problem.fixed, 1) << "\n";
  // Cost of one V-cycle (process CPU time over 20 cycles, all threads; a loaded machine inflates
  // wall time, CPU time less).
  const std::clock_t start = std::clock();
  for (int c = 0; c < 20; ++c) mg.cycle(b, x);
  std::cout << "cpu ms per V-cycle "
            << 1000.0 * static_cast<double>(std::clock() - start) / CLOCKS_PER_SEC / 20.0 << "\n";
  if (mg.patches().patch_count() == 0) return;
  // Cost of the feature-patch passes alone: least CPU time of 5 rounds of 10 forward + backward.
  double least = 1e300;
  for (int round = 0; round < 5; ++round) {
    const std::clock_t t0 = std::clock();
    for (int c = 0; c < 10; ++c) {
      mg.patches().pass(mg.level_matrix(0), b, x, true);
      mg.patches().pass(mg.level_matrix(0), b, x, false);
    }
    least = std::min(least, static_cast<double>(std::clock() - t0) / CLOCKS_PER_SEC / 20.0);
  }
  std::cout << "cpu ms per patch pass " << 1000.0 * least << "\n";
}

}  // namespace
}  // namespace mgelastic::tet

namespace mgelastic::tet {
namespace {

// Diagnostics: the slowest error mode of the V-cycle (power iteration on e <- (I - B A) e, b = 0)
// and where it lives. MG_MESH as in Explore (file only).
TEST(TetMultigridDiagnostics, DISABLED_SlowMode) {
  StepProblem problem;
  problem.mesh = geometry::read_tet_mesh(std::getenv("MG_MESH"));
  const int parent_vertices = problem.mesh.vertex_count();
  for (int r = 0; r < static_cast<int>(env_or("MG_REFINE", 0)); ++r)
    problem.mesh = refine_uniform(problem.mesh);
  const double low = problem.mesh.vertices.col(1).minCoeff();
  const double extent = problem.mesh.vertices.col(1).maxCoeff() - low;
  std::vector<int> dirichlet;
  problem.fixed.assign(problem.mesh.vertex_count(), 0);
  for (int v = 0; v < problem.mesh.vertex_count(); ++v)
    if (problem.mesh.vertices(v, 1) < low + 0.1 * extent) {
      dirichlet.push_back(v);
      problem.fixed[v] = 1;
    }
  CorotatedSolverSettings cs;
  cs.time_step = kStep;
  cs.gravity = Eigen::Vector3d(0, -9.81, 0);
  cs.linear_solver = LinearSolver::CHOLESKY;
  problem.solver = std::make_unique<CorotatedSolver>(
      problem.mesh,
      ElementMaterials::uniform(problem.mesh.tet_count(),
                                {env_or("MG_E", 1e4) * extent, 0.3, 1000.0}),
      cs);
  problem.solver->set_dirichlet(dirichlet);
  for (int i = 0; i < 3; ++i) problem.solver->step();
  TetMultigridSettings settings;
  settings.hierarchy.first_cell_factor = env_or("MG_FACTOR", 1.587);
  settings.hierarchy.max_coarsest_vertices = static_cast<int>(env_or("MG_COARSEST", 400));
  settings.pre_smoothing = settings.post_smoothing = static_cast<int>(env_or("MG_SWEEPS", 1));
  settings.symmetric_sweeps = env_or("MG_SYM", 0) != 0;
  settings.lexicographic = env_or("MG_LEX", 0) != 0;
  settings.smoother.strong_coupling = env_or("MG_STRONG", 0.3);
  settings.smoother.max_cluster_size = static_cast<int>(env_or("MG_CLUSTER", 4));
  env_patch_settings(settings);
  const TetMultigrid mg = step_multigrid(problem, settings);
  std::mt19937 rng(3);
  std::normal_distribution<double> normal;
  const int n = problem.mesh.vertex_count();
  Eigen::VectorXd e(3 * n), zero = Eigen::VectorXd::Zero(3 * n), ae;
  for (int i = 0; i < e.size(); ++i) e[i] = problem.fixed[i / 3] != 0 ? 0.0 : normal(rng);
  const auto energy = [&](const Eigen::VectorXd& v) {
    mg.level_matrix(0).multiply(v, ae);
    return std::sqrt(v.dot(ae));
  };
  double ratio = 0.0;
  for (int it = 0; it < 40; ++it) {
    const double before = energy(e);
    mg.cycle(zero, e);
    ratio = energy(e) / before;
    e /= energy(e);
  }
  std::cout << "energy-norm contraction of the slowest mode " << ratio << "\n";
  // Where it lives: share of |e|^2 per height decile, and the top vertices.
  std::vector<double> share(10, 0.0);
  std::vector<std::pair<double, int>> top;
  for (int v = 0; v < n; ++v) {
    const double m = e.segment<3>(3 * v).squaredNorm();
    const int d = std::min(9, static_cast<int>(10 * (problem.mesh.vertices(v, 1) - low) / extent));
    share[d] += m;
    top.emplace_back(m, v);
  }
  const double total = e.squaredNorm();
  std::cout << "height decile share:";
  for (double s : share) std::cout << " " << s / total;
  // Distance above the Dirichlet plane in fine mean edges, surface vs interior, parent vertices
  // vs refinement midpoints.
  const double edge = mean_edge_length(problem.mesh);
  const double plane = low + 0.1 * extent;
  std::vector<double> band(6, 0.0);
  std::vector<char> on_surface(n, 0);
  const geometry::TetMeshBoundary boundary = geometry::tet_mesh_boundary(problem.mesh);
  for (const int v : boundary.mesh_vertex) on_surface[v] = 1;
  double surface_share = 0.0, parent_share = 0.0;
  int surface_count = 0;
  for (int v = 0; v < n; ++v) {
    const double m = e.segment<3>(3 * v).squaredNorm();
    const double d = (problem.mesh.vertices(v, 1) - plane) / edge;
    band[d < 0 ? 0 : d < 1 ? 1 : d < 2 ? 2 : d < 4 ? 3 : d < 8 ? 4 : 5] += m;
    surface_share += on_surface[v] != 0 ? m : 0.0;
    surface_count += on_surface[v];
    parent_share += v < parent_vertices ? m : 0.0;
  }
  std::cout << "\nshare by distance above the Dirichlet plane (fine edges) <0 / 0-1 / 1-2 / 2-4 / "
               "4-8 / >8:";
  for (double s : band) std::cout << " " << s / total;
  std::cout << "\nsurface vertices " << surface_count << " of " << n << " hold "
            << surface_share / total << "; parent vertices " << parent_vertices << " hold "
            << parent_share / total;
  std::cout << "\nbbox min " << problem.mesh.vertices.colwise().minCoeff() << " max "
            << problem.mesh.vertices.colwise().maxCoeff() << "\n";
  std::sort(top.rbegin(), top.rend());
  double acc = 0.0;
  int count = 0;
  while (acc < 0.5 * total) acc += top[count++].first;
  std::cout << count << " of " << n << " vertices hold half of |e|^2; top 8:\n";
  // Valence, graph distance to the nearest patch vertex (-1: none) and patch seeds nearby.
  std::vector<int> valence(n, 0);
  for (int t = 0; t < problem.mesh.tet_count(); ++t)
    for (int c = 0; c < 4; ++c) ++valence[problem.mesh.tets(t, c)];
  std::vector<int> hops(n, -1), queue;
  for (int p = 0; p < mg.patches().patch_count(); ++p)
    for (const int v : mg.patches().patch(p))
      if (hops[v] < 0) {
        hops[v] = 0;
        queue.push_back(v);
      }
  const BlockRowMatrix<double>& graph = mg.level_matrix(0);
  for (std::size_t head = 0; head < queue.size(); ++head)
    for (int k = graph.row_offsets()[queue[head]]; k < graph.row_offsets()[queue[head] + 1]; ++k)
      if (hops[graph.block_columns()[k]] < 0) {
        hops[graph.block_columns()[k]] = hops[queue[head]] + 1;
        queue.push_back(graph.block_columns()[k]);
      }
  std::cout << mg.patches().patch_count() << " patches; level-1 cube "
            << settings.hierarchy.first_cell_factor * edge << "\n";
  for (int k = 0; k < 8; ++k)
    std::cout << "  v" << top[k].second << " " << problem.mesh.vertices.row(top[k].second) << " e "
              << e.segment<3>(3 * top[k].second).transpose() << " valence "
              << valence[top[k].second] << " surface " << int(on_surface[top[k].second])
              << " hops to a patch " << hops[top[k].second] << "\n";
  // Neighbourhood of the top vertex: incident tets (quality 6V / l_max^3), fixed neighbours,
  // diagonal block eigenvalues and couplings, prolongation row.
  const int v0 = top[0].second;
  const BlockRowMatrix<double>& a0 = mg.level_matrix(0);
  for (int k = a0.row_offsets()[v0]; k < a0.row_offsets()[v0 + 1]; ++k) {
    const int j = a0.block_columns()[k];
    Eigen::SelfAdjointEigenSolver<Eigen::Matrix3d> eig(0.5 *
                                                       (a0.block(k) + a0.block(k).transpose()));
    std::cout << "  A(" << v0 << "," << j << ") fixed " << int(problem.fixed[j]) << " |A| "
              << a0.block(k).norm() << " sym eig " << eig.eigenvalues().transpose() << " |e_j| "
              << e.segment<3>(3 * j).norm() << "\n";
  }
  for (int t = 0; t < problem.mesh.tet_count(); ++t)
    for (int c = 0; c < 4; ++c)
      if (problem.mesh.tets(t, c) == v0) {
        const Eigen::Matrix<double, 3, 4> x = problem.mesh.corners(t);
        double lmax = 0;
        for (int i = 0; i < 4; ++i)
          for (int j = i + 1; j < 4; ++j) lmax = std::max(lmax, (x.col(i) - x.col(j)).norm());
        Eigen::Matrix3d ed;
        ed << x.col(1) - x.col(0), x.col(2) - x.col(0), x.col(3) - x.col(0);
        std::cout << "  tet " << t << " quality " << ed.determinant() / std::pow(lmax, 3) << "\n";
      }
  const Prolongation& p0 = mg.hierarchy().prolongation(0);
  for (int s2 = 0; s2 < 4; ++s2)
    std::cout << "  P row: coarse " << p0.vertices[v0][s2] << " w " << p0.weights[v0][s2] << " at "
              << mg.hierarchy().positions(1).row(p0.vertices[v0][s2]) << " constrained "
              << int(mg.hierarchy().constrained(1)[p0.vertices[v0][s2]]) << "\n";
  // Smoothed? Energy of e vs its (smoothing-sensitive) high-frequency part: one GS sweep.
  Eigen::VectorXd s = e;
  Eigen::VectorXd r;
  mg.residual(zero, s, r);
  std::cout << "|A e| / |e|_A = " << r.norm() << "\n";
}

}  // namespace
}  // namespace mgelastic::tet
