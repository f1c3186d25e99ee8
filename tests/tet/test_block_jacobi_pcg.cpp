// Step system and block-Jacobi PCG.
#include <gtest/gtest.h>

#include <Eigen/SparseCholesky>
#include <cmath>
#include <random>

#include "mgelastic/core/error.hpp"
#include "mgelastic/tet/block_jacobi_pcg.hpp"
#include "mgelastic/tet/corotated_assembly.hpp"
#include "tet/tet_test_support.hpp"

namespace mgelastic::tet {
namespace {

struct Problem {
  geometry::TetMesh mesh = test::box_mesh(Eigen::Vector3d(1.0, 0.5, 0.5), 0.125);
  TetBody body{mesh, ElementMaterials::uniform(mesh.tet_count(), {1e5, 0.3, 1000.0})};
  RotationField rotations{body, RotationMethod::ENERGY_MINIMIZATION};
  CorotatedAssembler assembler{body};
  std::vector<char> fixed;
  Eigen::VectorXd b;
  Problem() {
    std::mt19937 rng(31);
    rotations.update(body.rest_positions() * 1.0);
    assembler.assemble(rotations);
    fixed.assign(body.vertex_count(), 0);
    for (int v = 0; v < body.vertex_count(); ++v) fixed[v] = mesh.vertices(v, 0) < 1e-12;
    std::uniform_real_distribution<double> uniform(-1, 1);
    b.resize(3 * body.vertex_count());
    for (int i = 0; i < b.size(); ++i) b[i] = uniform(rng);
  }
};

TEST(BlockJacobiPcg, MatchesSparseCholeskyOnStepSystem) {
  Problem p;
  const double h = 1.0 / 60.0;
  const StepSystem system(p.assembler.stiffness(), p.body.vertex_mass(), 1.0, h * h, p.fixed);
  Eigen::VectorXd b = p.b;
  system.eliminate(Eigen::VectorXd::Zero(b.size()), b);
  Eigen::VectorXd x = Eigen::VectorXd::Zero(b.size());
  const PcgResult result = solve_pcg(system, b, x, PcgSettings{1e-12, 5000});
  ASSERT_TRUE(result.converged);
  const Eigen::SimplicialLDLT<Eigen::SparseMatrix<double>> ldlt(system.to_sparse());
  const Eigen::VectorXd reference = ldlt.solve(b);
  // Residual 1e-12 times the condition number (~1e3 for this mass-dominated system).
  EXPECT_LE((x - reference).norm(), 1e-8 * reference.norm());
}

TEST(BlockJacobiPcg, ApplyIsSymmetric) {
  Problem p;
  const StepSystem system(p.assembler.stiffness(), p.body.vertex_mass(), 1.0, 1e-3, p.fixed);
  std::mt19937 rng(32);
  std::uniform_real_distribution<double> uniform(-1, 1);
  Eigen::VectorXd x(p.b.size()), y(p.b.size()), ax, ay;
  for (int i = 0; i < x.size(); ++i) x[i] = uniform(rng), y[i] = uniform(rng);
  system.apply(x, ax);
  system.apply(y, ay);
  EXPECT_LE(std::abs(x.dot(ay) - y.dot(ax)), 1e-12 * x.norm() * ay.norm());
}

TEST(BlockJacobiPcg, NanRightHandSideThrows) {
  Problem p;
  const StepSystem system(p.assembler.stiffness(), p.body.vertex_mass(), 1.0, 1e-3, p.fixed);
  Eigen::VectorXd b = p.b, x;
  b[7] = std::nan("");
  EXPECT_THROW(solve_pcg(system, b, x, PcgSettings{}), Error);
}

TEST(BlockJacobiPcg, IndefiniteSystemThrows) {
  Problem p;
  const StepSystem system(p.assembler.stiffness(), p.body.vertex_mass(), -1.0, 0.0, p.fixed);
  Eigen::VectorXd x;
  EXPECT_THROW(solve_pcg(system, p.b, x, PcgSettings{}), Error);
}

// The failure names the iteration and carries the relative residuals so far (1 at x = 0).
TEST(BlockJacobiPcg, FailureMessageCarriesTheResidualHistory) {
  Problem p;
  const StepSystem system(p.assembler.stiffness(), p.body.vertex_mass(), -1.0, 0.0, p.fixed);
  Eigen::VectorXd x;
  try {
    solve_pcg(system, p.b, x, PcgSettings{});
    FAIL() << "an indefinite system was solved";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("non-positive curvature p.Ap (matrix not SPD) at "
                                         "iteration 0; relative residual history: 1.000e+00"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace mgelastic::tet
