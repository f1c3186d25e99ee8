#pragma once
// Multigrid correction scheme with V(1,1) cycles (Algorithm 1) for the augmented system.
// One smoothing (Sec. 5.2-5.3) = band Gauss-Seidel sweeps, one distributive sweep, band sweeps
// again, then back-substitution of traction variables, so boundary conditions hold exactly and
// coarse boundary conditions are homogeneous (Sec. 6).
#include <array>
#include <memory>
#include <string>
#include <type_traits>
#include <vector>

#include "mgelastic/grid/boundary_smoother.hpp"
#include "mgelastic/grid/coarse_solver.hpp"
#include "mgelastic/grid/coarsening.hpp"
#include "mgelastic/grid/galerkin_band_rows.hpp"
#include "mgelastic/grid/galerkin_coarsest.hpp"
#include "mgelastic/grid/krylov_workspace.hpp"
#include "mgelastic/grid/level.hpp"
#include "mgelastic/grid/local_corrections.hpp"
#include "mgelastic/grid/problem.hpp"
#include "mgelastic/grid/residual_restriction.hpp"
#include "mgelastic/grid/solver_health.hpp"

namespace mgelastic::grid {

// V: the coarse problem is visited once per level visit (Algorithm 1); W: twice.
enum class CycleType { V, W };

struct MultigridOptions {
  CycleType cycle = CycleType::V;
  // Gauss-Seidel sweeps of the boundary band before and after each distributive sweep;
  // 0 = as the paper: 2 for nu <= 0.45, 3 up to 0.49, 4 above.
  int boundary_sweeps = 0;
  // Extra band sweeps over relocated-boundary equations before restriction / after
  // prolongation (Sec. 6, Fig. 8).
  int relocation_sweeps = 2;
  // Order of each pass's band sweeps (boundary_smoother.hpp): BLOCK_LOCAL, each colored block
  // takes all sweeps of a pass while in cache (128^3 box: boundary smoothing -24 %, rate
  // 0.2596 -> 0.2594); BAND_WIDE, sweep after sweep over the whole band (the paper's order);
  // AUTOMATIC: BLOCK_LOCAL in 3D, BAND_WIDE in 2D (Multigrid resolves it: options() never
  // reports AUTOMATIC).
  BandSweepOrder band_sweep_order = BandSweepOrder::AUTOMATIC;
  // Coarsen while a level has more interior unknowns than this, the next level keeps at least
  // `coarsest_min_cells` cells along its longest axis and at most
  // `coarsest_max_boundary_fraction` of its body cells have an exterior face neighbor; the
  // coarsest level is solved directly. At least two levels are always built.
  std::size_t coarsest_max_unknowns = 4096;
  int coarsest_min_cells = 16;
  double coarsest_max_boundary_fraction = 0.5;
  // Coarse cell typings are repaired so that they have no strain-free modes the fine level does
  // not have (repair_coarse_cells in coarsening.hpp).
  bool repair_coarse_cells = true;
  // Extra cell layers of eliminated pressures around the boundary band (0 = the paper's narrow
  // band). One layer makes the band sweeps reach shallow wedges of embedded bodies (real scans
  // converge much faster) at ~30% more boundary-smoothing time on boxes.
  int band_layers = 0;
  // Coarse cells' stresses scaled by their fill weights (fill_weights.hpp), so that thin parts
  // keep their stiffness on coarse levels. false = the paper's unweighted coarse operator.
  bool coarse_fill_weights = true;
  // Coarse levels clamp tangential corrections at the finest level's Dirichlet depth (h / 2
  // inside the Dirichlet region) instead of their own (H / 2), in their operator and in the
  // prolongation; false = the paper's rediscretization, whose clamp recedes with depth.
  bool consistent_dirichlet_depth = true;
  // With consistent_dirichlet_depth: also where a clamp top lies between a coarse level's faces
  // (inside its Dirichlet cells), clamp at the finest wall, up to 2^l - 1 finest cells deeper
  // than the coarse wall (finest_dirichlet_wall_layers). false = only coarse walls that are
  // finest walls. Embedded V(1,1) at 128 cells: armadillo 0.584 -> 0.532, bunny 0.642 -> 0.658
  // (docs/notes/2026-12-04-coarse-clamp.md).
  bool misaligned_dirichlet_depth = true;
  int max_levels = 0;  // 0 = no limit
  // Which coarse cells are Dirichlet (coarsening.hpp). EVERY_CHILD pays only with a Galerkin
  // coarse operator.
  CoarseDirichletRule coarse_dirichlet = CoarseDirichletRule::ANY_CHILD;
  // Diagnostics for two-level studies (galerkin_coarsest.hpp): the coarsest level solved with
  // the Galerkin product of the level above instead of its rediscretized rows. Builds by one
  // probe per coarse unknown: small problems only.
  CoarsestOperator coarsest_operator = CoarsestOperator::REDISCRETIZED;
  // Galerkin displacement terms in the coarse levels' band rows (galerkin_band_rows.hpp,
  // computed locally; a level with them is factored by LU when it is the coarsest).
  // docs/notes/2026-12-06-galerkin-band-rows.md: the embedded bodies and misaligned clamps gain,
  // the aligned box loses (0.26 -> 0.32 at nu 0.495), so not the default.
  CoarseBandRows coarse_band_rows = CoarseBandRows::REDISCRETIZED;
  // Float levels only. true: mixed precision, the solution and its residual in double on a
  // copy of the finest level (residuals far below float round-off). false: the paper's single
  // precision, the float finest level holds the solution itself: about half the memory
  // (no double copy of x and b) and no refinement traffic, but relative residuals stall near
  // eps (L/h)^2 (3.7e-3 at 128^3) and solution_level() (time integrators, FGMRES) is
  // unavailable.
  bool mixed_precision = true;
  // Mixed precision inside solve() and run_cycles(): iterative refinement with inner cycles.
  // The float cycles go on with one correction problem L e = r (as single precision does, each
  // followed by the float residual's norm only) until they have reduced its residual to this
  // fraction of r's norm; then e is added to the double solution and r recomputed there. A
  // cycle refines at once where the last ratio predicts the reduction (no float norm), after a
  // cycle that raised the residual above r's or stalled (kDeferredStall: float round-off of a
  // large correction), after kMaxDeferredCycles and on a solve's last allowed cycle. The
  // double phases (refinement and double residual, ~25 % of a cycle when every cycle refines)
  // then run on every third cycle of the box. >= 1: refine after every cycle (vcycle() always
  // does).
  double refinement_reduction = 0.02;
  // Hand the pages of the fields that hold no variable (most of an embedded body's bounding
  // box) back to the operating system and skip them in whole-array passes (live_chunks.hpp),
  // and the pages of the loads that hold only zeros (record_zero_loads).
  // The same results either way; false is for comparisons.
  bool release_dead_pages = true;
  // At most this many local corrections (local_correction.hpp) of the finest level where a
  // slow mode's residual sits (local_corrections.hpp: when, where, and when to remove them
  // again); plain and accelerated solves place them, and every later cycle (in later solves
  // too) applies them first. 0 = none: the library's default, so that rate studies see the
  // plain cycle; scenes and `bench vcycle --mesh` place up to 4. The armadillo at 256 cells:
  // settled ratio 0.77 -> 0.36, 1e-6 in 18 cycles instead of > 30 (docs/embedded-geometry.md).
  int local_corrections = 0;
};

int default_boundary_sweeps(double poisson_ratio);

// MultigridOptions::refinement_reduction: at most this many float cycles per refinement (slow
// embedded modes would otherwise defer it for dozens of cycles).
inline constexpr int kMaxDeferredCycles = 8;
// ... and a deferred cycle whose float residual ratio exceeds this refines (round-off reached).
inline constexpr double kDeferredStall = 0.9;

// Seconds spent per phase, accumulated over cycles (the rows of the paper's Fig. 22, and the
// cycle's own work around them, so that the phases add up to the solve time). The byte model
// of the same phases (cycle_roofline.hpp) uses this struct too.
struct PhaseSeconds {
  double boundary_smoothing = 0, interior_smoothing = 0, residual = 0, restriction = 0,
         prolongation = 0;
  // Direct solves: the coarsest level's and the local corrections' (local_correction.hpp).
  double coarse_solve = 0;
  // Mixed precision: the float correction problem loaded from the double residual, and the
  // correction added back to the double solution with its traction back-substitution.
  double refinement = 0;
  // The finest residual each cycle returns (double level in mixed precision).
  double cycle_residual = 0;
  // Once per solve(): the initial residual and the copy of the start state for the replay.
  double solve_setup = 0;
  static constexpr int count = 9;
  static constexpr const char* names[count] = {
      "boundary_smoothing", "interior_smoothing", "residual",       "restriction", "prolongation",
      "coarse_solve",       "refinement",         "cycle_residual", "solve_setup"};
  double operator[](int phase) const {
    const double values[count] = {boundary_smoothing, interior_smoothing, residual,
                                  restriction,        prolongation,       coarse_solve,
                                  refinement,         cycle_residual,     solve_setup};
    return values[phase];
  }
  double total() const {
    double sum = 0;
    for (int phase = 0; phase < count; ++phase) sum += (*this)[phase];
    return sum;
  }
};

struct SolveReport {
  std::vector<double> residuals;  // before the first cycle, then after each cycle
  double seconds = 0;
  bool converged = false;
  // Stopped before the tolerance because the residual stopped falling (Multigrid::solve's
  // stall_cycles, solve_accelerated's round-off floor): round-off reached, not a cycle limit.
  bool stalled = false;
  int cycles() const { return static_cast<int>(residuals.size()) - 1; }
};

template <int Dim, typename Scalar>
class Multigrid {
 public:
  // Validates the problem (throws mgelastic::Error) and builds the hierarchy.
  explicit Multigrid(const ElasticityProblem<Dim>& problem, MultigridOptions options = {});

  // Replaces the prescribed displacement of the Dirichlet variables (a keyframed region's next
  // frame), keeping the current solution elsewhere as the warm start of the next solve.
  void set_dirichlet_displacement(const std::function<Vec<Dim>(const Vec<Dim>&)>& displacement);
  // Replaces the loads (boundary_stress, variable_loads, body_force) by those of `problem`
  // without a hierarchy build (load_update.hpp): the level that holds them (solution_level() in
  // mixed precision, else the finest) gets the new traction values and b; the Dirichlet values
  // and the current solution stay as the warm start. Its other members must be those of the
  // built problem (throws Error otherwise). Time integrators rewrite b each step: they take the
  // new static b from here (BackwardEuler::set_loads).
  void set_loads(const ElasticityProblem<Dim>& problem);

  double residual();  // recomputes the finest residual norm
  // One V(1,1) cycle; returns the residual norm after it. Mixed precision: the correction is
  // added to the double solution and the residual recomputed there after every vcycle() call
  // (solve() defers that, MultigridOptions::refinement_reduction).
  double vcycle();
  // Cycles until residual <= tolerance * initial residual or max_cycles. In mixed precision the
  // residuals of cycles without a refinement are the float correction problem's (equal to the
  // double residual to float round-off of r); the last entry is always the double residual of
  // the returned solution, and convergence is judged on it. On divergence (a
  // non-finite residual, or growth beyond kResidualGrowthLimit, solver_health.hpp) throws Error
  // with the residual history and the level and phase found by a checked replay.
  // stall_cycles > 0: also stops (converged false, stalled true) after that many consecutive
  // cycles that do not lower the smallest residual after a cycle (StallWatch: the initial
  // residual does not count, a first cycle may raise it). A slow but converging solve sets a
  // new minimum every cycle; only a residual at round-off wanders above it (float round-off in
  // single precision, x's own rounding in double).
  SolveReport solve(double relative_tolerance, int max_cycles, int stall_cycles = 0);
  SolveReport run_cycles(int cycles);
  // Flexible GMRES(restart) on the augmented system, preconditioned by one cycle per iteration
  // (multigrid_fgmres.cpp): robust where a few error modes converge slowly (slender embedded
  // bodies). `residuals` holds the true residual before, the estimates during, and the true
  // residual after the solve; each entry after the first costs one cycle. Divergence: as solve,
  // the diagnosis from a checked replay of plain cycles from the same start. A tolerance below
  // the round-off floor of the solution's precision (the residual of x's own rounding, ~eps |A|
  // |x|: 1.6e-10 relative for a tip-loaded cantilever at 256 cells in double) stops with
  // converged false, stalled true, once two restarts in a row reached the target by their
  // estimate but not by the true residual and did not halve it.
  SolveReport solve_accelerated(double relative_tolerance, int max_cycles, int restart = 10);

  // All that one solve passes to the next (the warm start), for checkpoints: the finest level's
  // unknowns x in double, Dim + 1 arrays (u_0.., p) of the lattice size, Dirichlet and
  // back-substituted traction values included (single precision: a double copy of the float
  // values, rounded back by set_solution_state). set_solution_state throws Error on other sizes.
  using SolutionState = std::array<FieldArray<double>, Dim + 1>;
  const SolutionState& solution_state() const;
  void set_solution_state(const SolutionState& x);

  int levels() const { return static_cast<int>(m_levels.size()); }
  Level<Dim, Scalar>& level(int l) {
    m_solution_residual_current = false;  // the caller may change the finest level's b
    m_correction_zero = false;            // ... or its x
    // ... and write into its released zero load pages: count them again (conservative).
    m_levels[l].forget_zero_loads();
    return m_levels[l];
  }
  const Level<Dim, Scalar>& level(int l) const { return m_levels[l]; }
  const Level<Dim, Scalar>& finest() const { return m_levels.front(); }
  // The current solution at a variable of the finest level (double in every precision).
  double solution(int field, std::ptrdiff_t k) const;
  std::size_t unknowns() const { return m_levels.front().interior_unknowns(); }
  int boundary_sweeps() const { return m_boundary_sweeps; }
  // Whether the cycle passes level l's residual to level l + 1 fused with the restriction
  // (residual_restriction.hpp; false after a caller changed level l's band rows).
  bool fuses_restriction(int l) const {
    return l + 1 < levels() &&
           m_band_row_planes[static_cast<std::size_t>(l)].valid_for(m_levels[l]);
  }
  const MultigridOptions& options() const { return m_options; }
  // Bytes of the coarsest level's factor (a coarse solve streams it twice).
  std::size_t coarse_factor_bytes() const { return m_coarse->factor_bytes(); }
  // The local corrections placed so far (MultigridOptions::local_corrections) and their state
  // for checkpoints (LocalCorrections::State).
  int local_corrections() const { return m_local.size(); }
  const LocalCorrection<Dim, Scalar>& local_correction(int i) const { return m_local[i]; }
  using LocalCorrectionState = typename LocalCorrections<Dim, Scalar>::State;
  LocalCorrectionState local_correction_state() const { return m_local.state(); }
  void restore_local_correction_state(const LocalCorrectionState& state) {
    m_local.restore(m_levels.front(), state);
  }
  // Memory of all levels' arrays (the working set of a cycle, without the coarse factor).
  std::size_t bytes() const;
  // bytes() by Level::byte_breakdown group, summed over the levels; the double-precision
  // solution level of a mixed-precision solve (below) in groups of its own ("solution ...").
  std::vector<ByteShare> byte_breakdown() const;
  const PhaseSeconds& phase_seconds() const { return m_phases; }
  // Mixed precision, since construction: refinements (correction added, double residual) and
  // float residual norms of the correction problem (cycles that may defer the refinement;
  // cycle_roofline.hpp counts the bytes of both).
  int refinements() const { return m_refinements; }
  int float_norms() const { return m_float_norms; }
  // The finest level in double precision that holds the solution x and the right-hand side b
  // (the float finest level solves only corrections in mixed precision). Time integrators
  // (backward_euler.hpp) write b and the initial guess here between solves; do not keep the
  // reference across a cycle (each call marks the cached residual stale).
  // Single precision (MultigridOptions::mixed_precision false) has none: throws Error.
  Level<Dim, double>& solution_level();
  const Level<Dim, double>& solution_level() const;  // reading does not mark it stale
  bool single_precision() const {
    return !std::is_same_v<Scalar, double> && !m_options.mixed_precision;
  }

 private:
  void build_levels(const ElasticityProblem<Dim>& problem,
                    const std::vector<Lattice<Dim>>& lattices,
                    const std::vector<std::vector<CellType>>& cells,
                    const std::vector<std::vector<double>>& weights);
  void install_coarse_galerkin_rows();  // MultigridOptions::coarse_band_rows
  // Float levels with a double solution level (MultigridOptions::mixed_precision).
  bool mixed_precision() const { return !std::is_same_v<Scalar, double> && !single_precision(); }
  void smooth(int l, bool pre);
  void cycle_correction();
  // One cycle; mixed precision with may_defer: the refinement waits (refinement_reduction).
  double cycle(bool may_defer);
  // Mixed precision: adds the float level's correction to the double solution, recomputes the
  // residual there (the next correction problem) and returns its norm.
  double refine();
  // solve()'s watch after each cycle: places local corrections from the finest residual.
  void place_local_corrections(const std::vector<double>& residuals);
  // The finest level's band rows by plane (fresh_residual_norm's lines); null with one level.
  const BandRowPlanes* finest_band_planes() const {
    return m_band_row_planes.empty() ? nullptr : &m_band_row_planes.front();
  }
  // Checked replay only (m_monitor set): records level l's residual norm and finiteness.
  void observe(int l, CyclePhase phase);
  // A solve's start for the replay of a diverging solve: the double solution's x, or in single
  // precision the float finest level's x (half the bytes of a double copy).
  struct StartState {
    SolutionState solution;
    std::array<FieldArray<Scalar>, Dim + 1> single;
    bool packed = false;  // the arrays hold the live chunks only (live_chunks.hpp: pack_live)
    // Per field: x started at zero there, nothing stored (at 512^3 a copy is 4.4 GB; an
    // embedded body's gravity load leaves three of its four fields zero at the start).
    std::array<bool, Dim + 1> zero{};
  };
  // record_zero_loads on the level that holds the loads (the solution's); its pages released if
  // release_dead_pages.
  void record_zero_loads();
  // solution_level() for this class's own writes of x alone: keeps b's zero-page record.
  Level<Dim, double>& solution_storage();
  // Packs the start into m_start (its storage reused from solve to solve) and returns it.
  const StartState& capture_start();
  void restore_start(const StartState& start);
  [[noreturn]] void fail_diverged(const std::string& what, const std::string& reason,
                                  const std::vector<double>& residuals, const StartState& start);
  void correct(int level);
  // b_{l+1} = R r_l and x_{l+1} = 0: fused (no r_l) while level l's band rows are those grouped
  // at the build, else update_residual and restrict_residual.
  void restrict_to_next(int l);
  std::size_t fused_restriction_bytes() const;  // band rows by plane and plane windows

  std::vector<Level<Dim, Scalar>> m_levels;
  // Each level but the coarsest passes its residual to the next one fused with the restriction
  // (residual_restriction.hpp), so the levels keep no r: per level, its band rows by plane, and
  // the threads' plane windows.
  std::vector<BandRowPlanes> m_band_row_planes;
  ResidualWindows<Scalar> m_residual_windows;
  // Single precision runs as mixed-precision iterative refinement: the solution and its
  // residual live on a double copy of the finest level, and each float V-cycle solves for the
  // correction (homogeneous boundary conditions), so float V-cycles still reach residuals far
  // below float round-off of the displacements. Null in double precision.
  std::unique_ptr<Level<Dim, double>> m_solution;
  // The float finest level's b holds the residual of m_solution's current x and b (set by
  // vcycle() and residual(); cleared by every access that may change them, solution_level() and
  // level() included), so the next cycle need not recompute it.
  bool m_solution_residual_current = false;
  // Mixed precision: the float finest level's x is all zero (add_correction left it so and
  // nothing has written it since), so the next cycle needs no zero_correction.
  bool m_correction_zero = false;
  // Mixed precision inside solve(): the float finest level's x holds a correction not yet added
  // to m_solution (refinement_reduction), after m_deferred_cycles cycles on the correction
  // problem whose right-hand side had the norm m_refined_norm.
  bool m_correction_pending = false;
  int m_deferred_cycles = 0;
  double m_refined_norm = 0, m_last_float_norm = 0;
  // The last cycle's residual ratio (kUnknownRatio before a solve's first cycle).
  static constexpr double kUnknownRatio = 1e300;
  double m_last_ratio = kUnknownRatio;
  int m_refinements = 0, m_float_norms = 0;
  // Single precision only: solution_state()'s double copy of the float finest level's x, made
  // on request (checkpoints), not kept up to date.
  mutable SolutionState m_single_state;
  // The last solve's start (capture_start) and the accelerated solve's vectors: storage kept
  // for the next solve.
  StartState m_start;
  std::unique_ptr<KrylovWorkspace<Dim, Scalar>> m_krylov;
  std::unique_ptr<CoarseSolver<Dim, Scalar>> m_coarse;
  std::unique_ptr<GalerkinCoarseSolver<Dim, Scalar>>
      m_galerkin;  // coarsest_operator != REDISCRETIZED
  MultigridOptions m_options;
  int m_boundary_sweeps = 2;
  LocalCorrections<Dim, Scalar> m_local;  // of the finest level
  PhaseSeconds m_phases;
  CycleMonitor* m_monitor = nullptr;  // non-null only while a diverged solve is replayed
};

}  // namespace mgelastic::grid
