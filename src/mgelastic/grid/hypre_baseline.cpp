#include "mgelastic/grid/hypre_baseline.hpp"

#include "mgelastic/core/timer.hpp"

#ifdef MGELASTIC_HAVE_HYPRE
#include <mpi.h>

#include <cstdlib>

#include "HYPRE.h"
#include "HYPRE_IJ_mv.h"
#include "HYPRE_parcsr_ls.h"
#endif

namespace mgelastic::grid {

#ifdef MGELASTIC_HAVE_HYPRE
namespace {

// MPI and hypre are initialized once per process, as a single rank, and finalized at exit.
void ensure_initialized() {
  static const bool initialized = [] {
    int running = 0;
    MPI_Initialized(&running);
    if (!running) {
      MPI_Init(nullptr, nullptr);
      std::atexit([] {
        HYPRE_Finalize();
        MPI_Finalize();
      });
    }
    HYPRE_Init();
    return true;
  }();
  (void)initialized;
}

HYPRE_IJVector make_vector(const Eigen::VectorXd& values) {
  const HYPRE_BigInt last = static_cast<HYPRE_BigInt>(values.size()) - 1;
  HYPRE_IJVector v;
  HYPRE_IJVectorCreate(MPI_COMM_WORLD, 0, last, &v);
  HYPRE_IJVectorSetObjectType(v, HYPRE_PARCSR);
  HYPRE_IJVectorInitialize(v);
  std::vector<HYPRE_BigInt> rows(values.size());
  for (std::size_t i = 0; i < rows.size(); ++i) rows[i] = static_cast<HYPRE_BigInt>(i);
  HYPRE_IJVectorSetValues(v, static_cast<HYPRE_Int>(values.size()), rows.data(), values.data());
  HYPRE_IJVectorAssemble(v);
  return v;
}

HYPRE_IJMatrix make_matrix(const Eigen::SparseMatrix<double, Eigen::RowMajor>& a) {
  const HYPRE_BigInt last = static_cast<HYPRE_BigInt>(a.rows()) - 1;
  HYPRE_IJMatrix m;
  HYPRE_IJMatrixCreate(MPI_COMM_WORLD, 0, last, 0, last, &m);
  HYPRE_IJMatrixSetObjectType(m, HYPRE_PARCSR);
  HYPRE_IJMatrixInitialize(m);
  std::vector<HYPRE_BigInt> columns;
  std::vector<double> values;
  for (Eigen::Index row = 0; row < a.rows(); ++row) {
    columns.clear();
    values.clear();
    for (Eigen::SparseMatrix<double, Eigen::RowMajor>::InnerIterator it(a, row); it; ++it) {
      columns.push_back(static_cast<HYPRE_BigInt>(it.col()));
      values.push_back(it.value());
    }
    HYPRE_Int count = static_cast<HYPRE_Int>(columns.size());
    HYPRE_BigInt r = static_cast<HYPRE_BigInt>(row);
    HYPRE_IJMatrixSetValues(m, 1, &count, &r, columns.data(), values.data());
  }
  HYPRE_IJMatrixAssemble(m);
  return m;
}

}  // namespace

HypreReport boomeramg_pcg(const Eigen::SparseMatrix<double, Eigen::RowMajor>& a,
                          const Eigen::VectorXd& rhs, const std::vector<int>& component,
                          int dimension, double relative_tolerance, int max_iterations,
                          Eigen::VectorXd& solution) {
  ensure_initialized();
  HypreReport report;
  report.available = true;
  Timer timer;
  HYPRE_IJMatrix matrix = make_matrix(a);
  HYPRE_IJVector b = make_vector(rhs), x = make_vector(Eigen::VectorXd::Zero(rhs.size()));
  HYPRE_ParCSRMatrix pa;
  HYPRE_ParVector pb, px;
  HYPRE_IJMatrixGetObject(matrix, reinterpret_cast<void**>(&pa));
  HYPRE_IJVectorGetObject(b, reinterpret_cast<void**>(&pb));
  HYPRE_IJVectorGetObject(x, reinterpret_cast<void**>(&px));
  HYPRE_Solver pcg, amg;
  HYPRE_ParCSRPCGCreate(MPI_COMM_WORLD, &pcg);
  HYPRE_PCGSetTol(pcg, relative_tolerance);
  HYPRE_PCGSetMaxIter(pcg, max_iterations);
  HYPRE_PCGSetTwoNorm(pcg, 1);
  HYPRE_BoomerAMGCreate(&amg);
  HYPRE_BoomerAMGSetMaxIter(amg, 1);
  HYPRE_BoomerAMGSetTol(amg, 0.0);
  HYPRE_BoomerAMGSetCoarsenType(amg, 10);  // HMIS
  HYPRE_BoomerAMGSetInterpType(amg, 6);    // extended+i
  HYPRE_BoomerAMGSetPMaxElmts(amg, 4);
  HYPRE_BoomerAMGSetRelaxType(amg, 8);  // l1-symmetric Gauss-Seidel (SPD preconditioner)
  HYPRE_BoomerAMGSetStrongThreshold(amg, dimension == 3 ? 0.5 : 0.25);
  HYPRE_BoomerAMGSetNumFunctions(amg, dimension);
  // hypre takes ownership of the dof-function array and frees it.
  auto* dof = static_cast<HYPRE_Int*>(std::malloc(sizeof(HYPRE_Int) * component.size()));
  for (std::size_t i = 0; i < component.size(); ++i) dof[i] = component[i];
  HYPRE_BoomerAMGSetDofFunc(amg, dof);
  HYPRE_PCGSetPrecond(pcg, reinterpret_cast<HYPRE_PtrToSolverFcn>(HYPRE_BoomerAMGSolve),
                      reinterpret_cast<HYPRE_PtrToSolverFcn>(HYPRE_BoomerAMGSetup), amg);
  HYPRE_ParCSRPCGSetup(pcg, pa, pb, px);
  report.setup_seconds = timer.seconds();
  timer.restart();
  HYPRE_ParCSRPCGSolve(pcg, pa, pb, px);
  report.solve_seconds = timer.seconds();
  HYPRE_Int iterations = 0;
  HYPRE_PCGGetNumIterations(pcg, &iterations);
  HYPRE_PCGGetFinalRelativeResidualNorm(pcg, &report.relative_residual);
  report.iterations = static_cast<int>(iterations);
  report.converged = report.relative_residual <= relative_tolerance;
  solution.resize(rhs.size());
  std::vector<HYPRE_BigInt> rows(rhs.size());
  for (std::size_t i = 0; i < rows.size(); ++i) rows[i] = static_cast<HYPRE_BigInt>(i);
  HYPRE_IJVectorGetValues(x, static_cast<HYPRE_Int>(rows.size()), rows.data(), solution.data());
  HYPRE_BoomerAMGDestroy(amg);
  HYPRE_ParCSRPCGDestroy(pcg);
  HYPRE_IJVectorDestroy(x);
  HYPRE_IJVectorDestroy(b);
  HYPRE_IJMatrixDestroy(matrix);
  return report;
}
#else
HypreReport boomeramg_pcg(const Eigen::SparseMatrix<double, Eigen::RowMajor>&,
                          const Eigen::VectorXd&, const std::vector<int>&, int, double, int,
                          Eigen::VectorXd&) {
  return {};
}
#endif

}  // namespace mgelastic::grid
