#pragma once
// Multigrid for co-rotational linear elasticity (Zhu et al. 2010, Sec. 7): V cycles on the
// quasi-linear system (14) with the per-cell rotations frozen (corotated_operator.hpp), and the
// outer non-linear iteration that refreshes the rotations every k cycles (the paper: k = 5).
//
// Hierarchy: the linear engine's levels (Multigrid: coarsening, classification, transfers,
// Dirichlet values, right-hand sides) carry the fields; each level gets its own rows of (14)
// with rotations restricted from the finer level (restrict_rotations), rebuilt at each refresh
// together with the smoother's blocks and the coarsest LU factor. Smoother: multiplicative box
// (Vanka) Gauss-Seidel, one block per interior cell = its interior faces and its pressure,
// `sweeps` forward before and backward after the coarse correction (plus `relocation_sweeps`
// over the blocks of the Fig. 8 relocated-boundary sets), traction variables back-substituted
// with the co-rotated stress after each sweep. This replaces the paper's distributive smoother
// with the generalized distribution (15) and its band rows (not built, see docs/grid-engine.md).
//
// Residuals: the quasi-linear one (rows of the current frozen rotations) and the true
// non-linear one (rotations of the current displacement), both in the norm of residual.hpp.
// Double precision only.
#include <Eigen/Core>
#include <memory>
#include <vector>

#include "mgelastic/grid/corotated_operator.hpp"
#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::grid {

class AndersonMixing;

struct CorotatedOptions {
  int rotation_update_every = 5;  // V-cycles between rotation refreshes (k >= 1)
  double block_weight = 1.0;      // relaxation weight of the box smoother
  int sweeps = 2;                 // box sweeps before and after each coarse correction
  int relocation_sweeps = 2;      // extra sweeps over Fig. 8 relocated-boundary blocks
  CorotatedStress stress = CorotatedStress::SYMMETRIZED;
  // Anderson history of solve()'s outer iteration (corotated_acceleration.hpp); 0 = plain
  // frozen-rotation (Picard) cycles.
  int acceleration_depth = 3;
};

struct CorotatedReport {
  std::vector<double> nonlinear;     // true non-linear residual before, then after each cycle
  std::vector<double> quasi_linear;  // residual of the frozen system the cycle worked on
  double seconds = 0;
  bool converged = false;
  int cycles() const { return static_cast<int>(nonlinear.size()) - 1; }
};

template <int Dim>
class CorotatedMultigrid {
 public:
  explicit CorotatedMultigrid(const ElasticityProblem<Dim>& problem,
                              MultigridOptions multigrid = {}, CorotatedOptions options = {});
  ~CorotatedMultigrid();

  void set_dirichlet_displacement(const std::function<Vec<Dim>(const Vec<Dim>&)>& displacement);
  // Rotations from the current displacement on the finest level, restricted to every level;
  // rebuilds rows, smoother blocks and the coarsest factor. Resets the cycle counter.
  void refresh_rotations();
  double quasi_linear_residual();
  double nonlinear_residual();
  // One V(1,1) cycle on the frozen system (refreshing first when k cycles have passed);
  // returns the quasi-linear residual after it.
  double vcycle();
  // Cycles until the non-linear residual <= tolerance * initial or max_cycles. Throws Error when
  // the residual stops being finite. `accelerate`: Anderson-mixed cycles (options'
  // acceleration_depth), otherwise plain frozen-rotation cycles.
  CorotatedReport solve(double relative_tolerance, int max_cycles, bool accelerate = true);
  // A fixed number of plain cycles (a backward-Euler step): from a warm start two plain
  // refreshes reduce the step's residual more than two mixed ones (docs/grid-engine.md).
  CorotatedReport run_cycles(int cycles) { return solve(0.0, cycles, false); }

  int levels() const { return m_multigrid.levels(); }
  std::size_t unknowns() const { return m_multigrid.unknowns(); }
  Level<Dim, double>& solution_level() { return m_multigrid.level(0); }
  const Level<Dim, double>& solution_level() const { return m_multigrid.level(0); }
  const std::vector<Matrix<Dim>>& rotations() const { return m_rotations.front(); }
  const CorotatedOptions& options() const { return m_options; }
  Multigrid<Dim, double>& linear_hierarchy() { return m_multigrid; }

 private:
  struct Blocks;
  struct CoarseFactor;
  struct FreshRows;
  void build_level_system(int l);
  void build_level_system(int l, CorotatedRows rows);
  void refresh_rotations(FreshRows fresh);
  // One cycle of solve(): refreshes with the rows of the last non-linear residual when due.
  double solve_cycle();
  double accelerated_cycle(AndersonMixing& anderson, double previous, double& quasi_linear);
  Eigen::VectorXd gather_unknowns() const;
  void scatter_unknowns(const Eigen::VectorXd& values);
  void smooth(int l, bool forward, bool relocated_only);
  void correct(int l);
  void back_substitute(int l);

  Multigrid<Dim, double> m_multigrid;
  CorotatedOptions m_options;
  BoundaryStress<Dim> m_sigma;
  std::vector<std::vector<Matrix<Dim>>> m_rotations;
  std::vector<CorotatedRows> m_rows;
  std::vector<std::unique_ptr<Blocks>> m_blocks;
  std::unique_ptr<CoarseFactor> m_coarse;
  // Rotations and finest rows of the displacement at the last non-linear residual of solve();
  // a due refresh reuses them instead of rebuilding the same rows.
  std::unique_ptr<FreshRows> m_fresh;
  int m_cycles_since_refresh = 0;
};

}  // namespace mgelastic::grid
