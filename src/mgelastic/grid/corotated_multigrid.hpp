#pragma once
// Multigrid for co-rotational linear elasticity (Zhu et al. 2010, Sec. 7): V cycles on the
// quasi-linear system (14) with the per-cell rotations frozen (corotated_operator.hpp), and the
// outer non-linear iteration that refreshes the rotations every k cycles (the paper: k = 5).
//
// Hierarchy: the linear engine's levels (Multigrid: coarsening, classification, transfers,
// Dirichlet values, right-hand sides) carry the fields; each level gets its own rows of (14)
// with rotations restricted from the finer level (restrict_rotations), rebuilt at each refresh
// together with the smoother's blocks and the coarsest LU factor. Smoother (CorotatedSmoother):
// BOX = multiplicative box (Vanka) Gauss-Seidel, one block per interior cell = its interior
// faces and its pressure, `sweeps` forward before and backward after the coarse correction;
// DISTRIBUTIVE = the paper's split: a band pass (CorotatedBand: SCHUR = Gauss-Seidel on the
// band's Schur complement with edge-averaged pressures, corotated_band_smoother.hpp, or BOX =
// box sweeps over the band's cells), the distributive sweep with the generalized distribution
// (15) over the interior (corotated_distributive_smoother.hpp), the band again; all of them
// multithreaded (box sweeps over colored zones). Both smoothers add `relocation_sweeps` box
// sweeps over the blocks of the Fig. 8 relocated-boundary sets and back-substitute the traction
// variables with the co-rotated stress after each smoothing step.
//
// Residuals: the quasi-linear one (rows of the current frozen rotations) and the true
// non-linear one (rotations of the current displacement), both in the norm of residual.hpp.
// Double precision only.
#include <Eigen/Core>
#include <array>
#include <deque>
#include <memory>
#include <vector>

#include "mgelastic/grid/corotated_operator.hpp"
#include "mgelastic/grid/multigrid.hpp"

namespace mgelastic::grid {

class AndersonMixing;

// BOX: box (Vanka) Gauss-Seidel over every interior cell. DISTRIBUTIVE: the paper's split,
// a pass over the boundary band (rows the linear level marks BAND; CorotatedBand), then the
// distributive sweep with the generalized distribution (corotated_distributive_smoother.hpp)
// over the interior, then the band again. BOX stays the default: the distributive sweep lost
// its rate on a 48x12x12 bar twisted by 90 degrees (docs/grid-engine.md).
enum class CorotatedSmoother { BOX, DISTRIBUTIVE };

// Outer (rotation refresh) iteration. PICARD: k frozen-rotation V-cycles per refresh (solve()
// may mix them with Anderson acceleration). NEWTON_KRYLOV: Newton steps on the true non-linear
// residual, each direction one frozen V-cycle (the preconditioner; its rotations refreshed
// every k cycles), plus the last steps' corrections, combined by minimal residual with
// finite-difference Jacobian products (corotated_newton_krylov.hpp). The recycled corrections
// are part of CorotatedMultigrid::CarriedState, so a checkpointed run resumes bit for bit.
enum class CorotatedOuter { PICARD, NEWTON_KRYLOV };

// Band of the DISTRIBUTIVE smoother. SCHUR: Gauss-Seidel on the band's Schur complement with
// edge-averaged pressures (Sec. 5.3 / 7, corotated_band_smoother.hpp), multithreaded, as many
// sweeps per pass as the linear engine (MultigridOptions::boundary_sweeps: 2 / 3 / 4 by nu).
// BOX: `band_sweeps` box (Vanka) sweeps over the band's cells.
enum class CorotatedBand { SCHUR, BOX };

struct CorotatedOptions {
  int rotation_update_every = 5;  // V-cycles between rotation refreshes (k >= 1)
  CorotatedSmoother smoother = CorotatedSmoother::BOX;
  double block_weight = 1.0;  // relaxation weight of the box smoother
  int sweeps = 2;             // smoothing steps before and after each coarse correction
  CorotatedBand band = CorotatedBand::SCHUR;  // DISTRIBUTIVE only
  int band_sweeps = 1;  // DISTRIBUTIVE with BOX band: box sweeps before and after the interior one
  int relocation_sweeps = 2;  // extra sweeps over Fig. 8 relocated-boundary blocks
  CorotatedStress stress = CorotatedStress::SYMMETRIZED;
  // Anderson history of solve()'s outer iteration (corotated_acceleration.hpp); 0 = plain
  // frozen-rotation (Picard) cycles.
  int acceleration_depth = 3;
  CorotatedOuter outer = CorotatedOuter::PICARD;  // solve() and solve_with_load_steps()
  // run_cycles() (backward-Euler steps): one cycle per step reduces the step's residual by
  // ~0.11 against 0.38 with Picard (docs/grid-engine.md).
  CorotatedOuter step_outer = CorotatedOuter::NEWTON_KRYLOV;
  // NEWTON_KRYLOV: corrections of the last Newton steps added as extra directions (each costs a
  // residual evaluation, no V-cycle).
  int recycled_directions = 2;
};

struct CorotatedReport {
  std::vector<double> nonlinear;     // true non-linear residual before, then after each cycle
  std::vector<double> quasi_linear;  // residual of the frozen system the cycle worked on
  double seconds = 0;
  bool converged = false;
  int load_increments = 1;  // solve_with_load_steps: increments of the accepted attempt
  int cycles() const { return static_cast<int>(nonlinear.size()) - 1; }
};

// What later cycles read besides the finest unknowns (checkpoints, sim/grid_stepper.cpp): the
// frozen rows are a function of the rotations they were built from, which lag the displacement by
// up to k cycles, so those rotations, the cycles since their refresh and the Newton step's recycled
// corrections decide the next cycles. The rest (coarse levels' rotations, rows, smoother blocks,
// coarsest factor) is rebuilt from them; the load-stepping start is the current load.
template <int Dim>
struct CorotatedCarriedState {
  std::vector<double> rotations;  // finest cells' R, Dim x Dim each, column-major
  int cycles_since_refresh = 0;
  std::vector<Eigen::VectorXd> recycled;  // oldest first
};

template <int Dim>
class CorotatedMultigrid {
 public:
  explicit CorotatedMultigrid(const ElasticityProblem<Dim>& problem,
                              MultigridOptions multigrid = {}, CorotatedOptions options = {});
  ~CorotatedMultigrid();

  void set_dirichlet_displacement(const std::function<Vec<Dim>(const Vec<Dim>&)>& displacement);
  // Replaces the loads (boundary_stress, variable_loads, body_force) by those of `problem`
  // without a hierarchy build: the finest right-hand side, the linear level's traction rules and
  // band constants (load_update.hpp), and the finest co-rotated rows' constants (their
  // coefficients and the coarse levels' homogeneous rows do not depend on the loads). The rest of
  // `problem` must be that of the build (throws Error otherwise). Afterwards the solver is what a
  // build from `problem` with this one's state restored (carried_state, the finest x) is, bit for
  // bit: x is kept as it is (traction values included; cycles back-substitute them), and load
  // stepping starts from the new load.
  void set_loads(const ElasticityProblem<Dim>& problem);
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
  // NEWTON_KRYLOV: Newton steps of k cycles (directions) each.
  CorotatedReport solve(double relative_tolerance, int max_cycles, bool accelerate = true) {
    return solve(relative_tolerance, max_cycles, accelerate, m_options.outer,
                 m_options.rotation_update_every);
  }
  // A fixed number of cycles (a backward-Euler step) with options' step_outer: PICARD = plain
  // cycles (from a warm start two plain refreshes reduce the step's residual more than two
  // mixed ones), NEWTON_KRYLOV = one Newton step with `cycles` directions (docs/grid-engine.md).
  CorotatedReport run_cycles(int cycles) {
    return solve(0.0, cycles, false, m_options.step_outer, cycles);
  }
  // Quasistatic solve with load stepping (continuation, corotated_load_stepping.cpp): first as
  // solve(); when an increment fails (non-linear residual above kIncrementGrowth times its
  // start or not finite; or, for the last one, not converged in max_cycles), its start is
  // restored and the increment halved. The load (finest right-hand side, Dirichlet values,
  // boundary tractions) runs from that of the last call (zero at construction) to the current
  // one; an accepted increment doubles the next. Increments before the last are solved to
  // max(tolerance, 0.1) of their own start, the last as solve() (relative to the full load's
  // initial residual). `nonlinear` holds the full-load residual first, then each cycle's
  // residual for its increment's load. Throws Error when an increment of
  // 1/kMaxLoadIncrements of the load diverges.
  CorotatedReport solve_with_load_steps(double relative_tolerance, int max_cycles);
  static constexpr int kMaxLoadIncrements = 64;
  static constexpr double kIncrementGrowth = 100.0;

  CorotatedCarriedState<Dim> carried_state() const;
  // After the finest unknowns were restored (solution_level().x, Dirichlet and traction values
  // included): rebuilds every level's system from the carried rotations and the full boundary
  // tractions, exactly as the run that saved it had them between solves, and takes the current
  // load as the equilibrium load stepping starts from.
  // Throws Error when the arrays do not fit this hierarchy.
  void restore_carried_state(const CorotatedCarriedState<Dim>& state);

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
  struct Interior;
  // A quasistatic load: finest right-hand side, Dirichlet values (at m_dirichlet), traction scale.
  struct Load {
    std::array<FieldArray<double>, Dim + 1> b;
    std::vector<double> dirichlet;
    double traction = 0;
  };
  CorotatedReport solve(double relative_tolerance, int max_cycles, bool accelerate,
                        CorotatedOuter outer, int newton_directions);
  Load current_load() const;
  void apply_load(const Load& from, const Load& to, double s);
  void set_traction_scale(double scale);
  enum class Attempt { CONVERGED, STALLED, DIVERGED };
  Attempt solve_increment(double initial, double target, int max_cycles, CorotatedReport& report);
  void build_level_system(int l);
  void build_block_structure(int l);
  void refresh_levels();
  void refresh_rotations_when_due();
  // One cycle of solve(): refreshes with the rows of the last non-linear residual when due.
  double solve_cycle();
  double accelerated_cycle(AndersonMixing& anderson, double previous, double& quasi_linear);
  int newton_krylov_step(int directions, double target, CorotatedReport& report);
  bool rest_rotations() const;
  Eigen::VectorXd residual_vector() const;
  Eigen::VectorXd frozen_cycle_direction(const Eigen::VectorXd& x, const Eigen::VectorXd& r0,
                                         const Eigen::VectorXd* v);
  double matrix_free_nonlinear_residual();
  Eigen::VectorXd gather_unknowns() const;
  void scatter_unknowns(const Eigen::VectorXd& values);
  enum class BlockSet { ALL, BAND, RELOCATED };
  void box_sweep(int l, bool forward, BlockSet set);
  void band_pass(int l, bool forward);
  void smooth(int l, bool forward);
  void correct(int l);
  void back_substitute(int l);

  Multigrid<Dim, double> m_multigrid;
  CorotatedOptions m_options;
  BoundaryStress<Dim> m_sigma;             // boundary tractions times the load scale
  BoundaryStress<Dim> m_sigma_full;        // the problem's boundary tractions
  std::vector<std::uint32_t> m_dirichlet;  // finest Dirichlet variables (global indices)
  Load m_equilibrium;                      // load of the last accepted solve_with_load_steps
  double m_traction_scale = 1.0;
  std::vector<std::vector<Matrix<Dim>>> m_rotations;
  std::vector<CorotatedRows> m_rows;
  std::vector<std::unique_ptr<Blocks>> m_blocks;
  std::vector<std::unique_ptr<Interior>> m_interior;  // DISTRIBUTIVE only
  std::unique_ptr<CoarseFactor> m_coarse;
  // Rotations of the last non-linear residual's x (storage kept between calls); when the next
  // cycle refreshes they are fresh (m_fresh_rotations) and the refresh takes them over (dropped
  // by whatever moves x in between).
  std::vector<Matrix<Dim>> m_scratch_rotations;
  bool m_fresh_rotations = false;
  CorotatedResidualScratch<Dim> m_residual_scratch;  // of the finest level
  int m_cycles_since_refresh = 0;
  std::deque<Eigen::VectorXd> m_recycled;  // last Newton corrections (NEWTON_KRYLOV)
  Eigen::VectorXd m_trial_unknowns;        // the Newton step's evaluation points
  std::vector<double> m_saved_loads;       // frozen_cycle_direction's finest b
};

}  // namespace mgelastic::grid
