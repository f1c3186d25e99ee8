#include "mgelastic/grid/multigrid.hpp"

#include <algorithm>
#include <cmath>
#include <future>
#include <map>
#include <optional>
#include <type_traits>
#include <utility>

#include <omp.h>

#include "mgelastic/core/cancellation.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/core/threads.hpp"
#include "mgelastic/core/timer.hpp"
#include "mgelastic/grid/boundary_smoother.hpp"
#include "mgelastic/grid/coarsening.hpp"
#include "mgelastic/grid/distributive_smoother.hpp"
#include "mgelastic/grid/fill_weights.hpp"
#include "mgelastic/grid/galerkin_band_rows.hpp"
#include "mgelastic/grid/load_update.hpp"
#include "mgelastic/grid/problem_validation.hpp"
#include "mgelastic/grid/residual.hpp"
#include "mgelastic/grid/transfer.hpp"

namespace mgelastic::grid {
namespace {

template <int Dim>
bool can_coarsen(const Lattice<Dim>& lattice) {
  for (int a = 0; a < Dim; ++a)
    if (lattice.cells[a] < 4) return false;
  return true;
}

template <int Dim>
std::size_t count_interior(const std::vector<CellType>& cells) {
  return static_cast<std::size_t>(std::count(cells.begin(), cells.end(), CellType::INTERIOR));
}

// Fraction of the body's (non-exterior) cells that have an exterior face neighbor.
template <int Dim>
double boundary_fraction(const Lattice<Dim>& lattice, const std::vector<CellType>& cells) {
  std::size_t body = 0, boundary = 0;
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(lattice.size()); ++k) {
    if (cells[k] == CellType::EXTERIOR || !lattice.is_real(lattice.coords(k))) continue;
    ++body;
    bool exposed = false;
    for (int a = 0; a < Dim && !exposed; ++a)
      exposed = cells[k - lattice.stride(a)] == CellType::EXTERIOR ||
                cells[k + lattice.stride(a)] == CellType::EXTERIOR;
    boundary += exposed;
  }
  return body == 0 ? 1.0 : static_cast<double>(boundary) / static_cast<double>(body);
}

// Whether a coarsest level with these cells would make its direct solve the larger part of the
// cycle: a slender body (a 256 x 26 x 26 cantilever) stops after one coarsening, at 25 k cells,
// whose sparse Cholesky factor of a quasi-one-dimensional lattice is dense across the section
// (2.2 s to factor, 33 ms per solve: half of each cycle, and half of the run's peak memory).
// Compact bodies reach a level that size only as a small share of their finest level (the
// armadillo at 256 cells: 2 %, coarse solve 6 % of the cycle), where the boundary rule keeps
// the rates (without it 0.774 -> 0.807 there, bunny 0.582 -> 0.702).
template <int Dim>
bool dominant_direct_solve(const std::vector<CellType>& finest,
                           const std::vector<CellType>& coarsest) {
  constexpr std::size_t kLargeCoarsest = 16384;  // interior cells
  constexpr std::size_t kDominantShare = 16;     // the coarsest holds >= 1/16 of the finest's
  const std::size_t coarse = count_interior<Dim>(coarsest);
  return coarse >= kLargeCoarsest && coarse * kDominantShare >= count_interior<Dim>(finest);
}

// Coarsening continues while the next level still resolves the body with at least
// `coarsest_min_cells` cells along its longest axis (coarser levels model traction boundaries
// too crudely to correct the body's global deformation modes) and the current level is larger
// than what the direct solver handles cheaply. The first coarsening always happens.
template <int Dim>
bool may_coarsen(const Lattice<Dim>& lattice, const std::vector<CellType>& cells,
                 std::size_t levels, const MultigridOptions& options) {
  if (!can_coarsen(lattice)) return false;
  if (options.max_levels > 0 && static_cast<int>(levels) >= options.max_levels) return false;
  if (levels == 1) return true;
  if (count_interior<Dim>(cells) * (Dim + 1) <= options.coarsest_max_unknowns) return false;
  return (lattice.cells.maxCoeff() + 1) / 2 >= options.coarsest_min_cells;
}

// The double-precision solution level of a mixed-precision solve is never smoothed: it holds
// x and b, takes corrections and back-substitutes traction values; its residual goes straight
// into the float level's right-hand side (residual_into), so it needs no r (update_residual
// allocates one if a caller asks, e.g. the FGMRES solve). What only the band sweeps read (the
// sweeps' right-hand sides, runs, blocks and their inverses, colored schedules, Fig. 8 row sets)
// would double the band's memory, so it is dropped after the build (the block partition itself
// is a few hundred bytes).
template <int Dim>
void release_sweep_data(Level<Dim, double>& level) {
  // Assigning a fresh object frees the storage (`v = {}` would keep a vector's capacity).
  const auto release = [](auto&... v) { ((v = std::remove_cvref_t<decltype(v)>()), ...); };
  release(level.r, level.pre_restriction_rows, level.post_prolongation_rows, level.band_blocks,
          level.band_block_inverse, level.band_block_inverse_id, level.band_point_rows,
          level.band_block_shapes, level.band_kernel.rhs, level.band_schedule,
          level.pre_restriction_schedule, level.post_prolongation_schedule, level.band_runs);
  drop_band_csr(level);
}

// relocation_sweeps runs the smoothing's band sweeps where a Fig. 8 set is the whole band (every
// band row of the box), so the colored schedule of that set is never read.
template <int Dim, typename Scalar>
void drop_whole_band_schedules(Level<Dim, Scalar>& level) {
  using Schedule = typename Level<Dim, Scalar>::RowSchedule;
  if (level.pre_restriction_rows.size() == level.band_kernel.rows())
    level.pre_restriction_schedule = Schedule();
  if (level.post_prolongation_rows.size() == level.band_kernel.rows())
    level.post_prolongation_schedule = Schedule();
}

// x into the finest level's unknowns (rounded to float in single precision), its live chunks only
// (live_chunks.hpp: the rest holds no variable and stays zero, with its pages released).
template <std::size_t Fields, typename T>
void copy_solution_state(const std::array<FieldArray<double>, Fields>& x,
                         std::array<FieldArray<T>, Fields>& fields, const LiveChunks& live) {
  for (std::size_t f = 0; f < Fields; ++f)
    if (x[f].size() != fields[f].size())
      throw Error("solution state field " + std::to_string(f) + " has " +
                      std::to_string(x[f].size()) + " values, the finest level has " +
                      std::to_string(fields[f].size()),
                  {.pointer = "solution state"});
  assign_live(fields, x, live);
}

// Mixed precision: the float level solves L e = r with a zero initial correction; r is already
// in its b (residual_into). Elementwise, so the static parallel loops give the same values for
// any thread count.
template <int Dim, typename Scalar>
void zero_correction(Level<Dim, Scalar>& fine) {
  // Live chunks only (live_chunks.hpp: the dead ones hold zeros and no memory).
  for (int f = 0; f <= Dim; ++f) zero_live(fine.x[f], fine.live);
}

// The double residual of the solution, rounded once, as the float level's right-hand side; its
// norm in double (of the unrounded values).
template <int Dim, typename Scalar>
double residual_to_correction_problem(const Level<Dim, double>& solution,
                                      Level<Dim, Scalar>& fine) {
  std::array<Scalar*, Dim + 1> b;
  for (int f = 0; f <= Dim; ++f) b[f] = fine.b[f].data();
  return residual_into<Dim, double, Scalar>(solution, b);
}

// Adds the correction e (the float level's INTERIOR unknowns) to the solution and leaves e zero,
// the next cycle's initial correction (zero_correction's work, done while e is in cache).
template <int Dim, typename Scalar>
void add_correction(Level<Dim, Scalar>& fine, Level<Dim, double>& solution) {
  const auto size = static_cast<std::ptrdiff_t>(fine.size());
  for (int f = 0; f <= Dim; ++f) {
    const FieldKinds kind = fine.codes.kinds(f);
    Scalar* e = fine.x[f].data();
    double* x = solution.x[f].data();
    // Chunks without an INTERIOR variable (outside an embedded body) are only zeroed; inside one
    // the add always runs and only its operand is selected (a conditional add would be a branch
    // under -ftrapping-math and keep the loop scalar); x + 0 leaves every other x as it was.
    // The chunks are the live chunks' (live_chunks.hpp), so no dead page is written.
    constexpr std::ptrdiff_t chunk = kLiveChunk;
    const std::ptrdiff_t block = interleaved_block((size + chunk - 1) / chunk);
#pragma omp parallel for schedule(static, block)
    for (std::ptrdiff_t begin = 0; begin < size; begin += chunk) {
      const std::ptrdiff_t end = std::min(begin + chunk, size);
      if (!fine.live.any_live(begin, end)) continue;
      if (solution.live.any_live(begin, end) && (kind + begin).any(end - begin, VarKind::INTERIOR))
        for (std::ptrdiff_t k = begin; k < end; ++k)
          x[k] += kind[k] == VarKind::INTERIOR ? static_cast<double>(e[k]) : 0.0;
      std::fill(e + begin, e + end, Scalar(0));
    }
  }
}

// The extra band sweeps of Fig. 8 over `rows`. Where they are the whole band (on the box every
// band row reads a coarse boundary correction) the sweeps are the smoothing's block and run-wise
// band sweeps, 2-3x cheaper per row than the point sweeps of a subset.
template <int Dim, typename Scalar>
void relocation_sweeps(Level<Dim, Scalar>& level, int sweeps,
                       const std::vector<std::uint32_t>& rows,
                       const typename Level<Dim, Scalar>::RowSchedule& schedule,
                       BandSweepOrder order) {
  // Inside a V-cycle's visit of the level: its band rhs is current (Multigrid::correct).
  if (rows.size() == level.band_kernel.rows())
    band_gauss_seidel(level, sweeps, order, BandRhs::CURRENT);
  else
    band_gauss_seidel(level, sweeps, schedule, order, BandRhs::CURRENT);
}

// The double solution level of mixed precision on a thread of its own, with the caller's OpenMP
// thread count (a new thread starts from the default). The caller keeps `finest` and `problem`
// alive and unchanged until the future is ready.
template <int Dim, typename Scalar>
std::future<Level<Dim, double>> start_solution_level(const Level<Dim, Scalar>& finest,
                                                     const ElasticityProblem<Dim>& problem,
                                                     bool release_dead_pages) {
  const int threads = omp_get_max_threads();
  return std::async(std::launch::async, [&finest, &problem, release_dead_pages, threads] {
    omp_set_num_threads(threads);
    return build_solution_level(finest, problem.material, problem.boundary_stress, problem.inertia,
                                release_dead_pages);
  });
}

}  // namespace

int default_boundary_sweeps(double poisson_ratio) {
  if (poisson_ratio <= 0.45) return 2;
  if (poisson_ratio <= 0.49) return 3;
  return 4;
}

template <int Dim, typename Scalar>
Multigrid<Dim, Scalar>::Multigrid(const ElasticityProblem<Dim>& problem, MultigridOptions options)
    : m_options(options), m_local(options.local_corrections, problem.material, problem.inertia) {
  validate(problem);
  m_options.band_sweep_order = resolved<Dim>(options.band_sweep_order);  // options() reports it
  m_boundary_sweeps = options.boundary_sweeps > 0
                          ? options.boundary_sweeps
                          : default_boundary_sweeps(problem.material.poisson_ratio);
  // Cell types of every level first: each level's band depends on the next coarser typing.
  std::vector<Lattice<Dim>> lattices{problem.lattice};
  std::vector<std::vector<CellType>> cells{problem.cells};
  std::vector<std::vector<double>> weights{{}};
  while (may_coarsen(lattices.back(), cells.back(), lattices.size(), options)) {
    Lattice<Dim> coarse = coarsen(lattices.back());
    std::vector<CellType> coarse_cells =
        coarsen_cells(lattices.back(), cells.back(), options.coarse_dirichlet);
    if (options.repair_coarse_cells) repair_coarse_cells(coarse, coarse_cells);
    std::vector<double> coarse_weights;
    if (options.coarse_fill_weights) {
      coarse_weights =
          coarse_fill_weights(lattices.back(), cells.back(), weights.back(), coarse, coarse_cells);
      if (all_full(coarse_weights, coarse_cells)) coarse_weights.clear();
    }
    // A level made mostly of boundary cells misrepresents a thin body: its traction boundaries
    // sit half a coarse cell inside and its stiffness is far off the finer level's, so its
    // correction of the body's global deformation is poor (docs/embedded-geometry.md), unless
    // stopping would leave a direct solve that outweighs the cycle.
    if (lattices.size() > 1 &&
        boundary_fraction(coarse, coarse_cells) > options.coarsest_max_boundary_fraction &&
        !dominant_direct_solve<Dim>(cells.front(), cells.back()))
      break;
    lattices.push_back(std::move(coarse));
    cells.push_back(std::move(coarse_cells));
    weights.push_back(std::move(coarse_weights));
  }
  // A coarse level that is still singular (a body part not held, or a strain-free mode the
  // repair of coarse typings does not remove) cannot be the coarsest; the hierarchy then stops
  // one level finer, down to a direct solve of the finest level itself.
  std::optional<Level<Dim, double>> solution;
  while (true) {
    build_levels(problem, lattices, cells, weights);
    install_coarse_galerkin_rows();
    // The double solution level reads only the finest level's lattice, typing and variable codes,
    // which the coarsest factorization leaves alone: it is built alongside (the factorization's
    // ordering and assembly are serial, and the two overlap on two cores).
    std::future<Level<Dim, double>> solution_build;
    if (mixed_precision())
      solution_build =
          start_solution_level(m_levels.front(), problem, m_options.release_dead_pages);
    try {
      m_coarse = std::make_unique<CoarseSolver<Dim, Scalar>>(m_levels.back());
      if (solution_build.valid()) solution = solution_build.get();
      for (Level<Dim, Scalar>& level : m_levels) {
        drop_band_csr(level);
        drop_whole_band_schedules(level);
      }
      break;
    } catch (const SingularCoarseLevel&) {
      if (solution_build.valid()) solution_build.wait();  // it reads the levels rebuilt next
      if (lattices.size() == 1) throw;
      lattices.pop_back();
      cells.pop_back();
      weights.pop_back();
    }
  }
  // The cycle restricts fresh residuals (restrict_to_next), so the levels need no r (built
  // without one; allocated where a caller asks for a residual array, update_residual).
  for (std::size_t l = 0; l + 1 < m_levels.size(); ++l)
    m_band_row_planes.push_back(band_row_planes(m_levels[l]));
  if (m_options.coarsest_operator != CoarsestOperator::REDISCRETIZED && m_levels.size() > 1)
    m_galerkin = std::make_unique<GalerkinCoarseSolver<Dim, Scalar>>(
        m_levels[m_levels.size() - 2], m_levels.back(),
        m_options.coarsest_operator == CoarsestOperator::GALERKIN_BAND);
  if (mixed_precision()) {
    m_solution = std::make_unique<Level<Dim, double>>(std::move(*solution));
    release_sweep_data(*m_solution);
    set_dirichlet_values(*m_solution, problem.dirichlet_displacement);
    write_load_right_hand_side(problem, *m_solution);
    back_substitute_traction(*m_solution);
  } else {
    set_dirichlet_values(m_levels.front(), problem.dirichlet_displacement);
    write_load_right_hand_side(problem, m_levels.front());
    back_substitute_traction(m_levels.front());
  }
  record_zero_loads();
}

// Only loads write the b of the level holding the solution (solution_level() and level(), the
// mutable accesses, forget the record).
template <int Dim, typename Scalar>
void Multigrid<Dim, Scalar>::record_zero_loads() {
  if (m_solution)
    grid::record_zero_loads(*m_solution, m_options.release_dead_pages);
  else
    grid::record_zero_loads(m_levels.front(), m_options.release_dead_pages);
}

template <int Dim, typename Scalar>
void Multigrid<Dim, Scalar>::build_levels(const ElasticityProblem<Dim>& problem,
                                          const std::vector<Lattice<Dim>>& lattices,
                                          const std::vector<std::vector<CellType>>& cells,
                                          const std::vector<std::vector<double>>& weights) {
  m_levels.clear();
  for (std::size_t l = 0; l < lattices.size(); ++l) {
    const bool finest = l == 0 && !mixed_precision();
    const bool coarsest = l + 1 == lattices.size();
    // Coarse levels clamp tangential corrections where the finest level does (decision 8a).
    const bool clamp = l > 0 && m_options.consistent_dirichlet_depth;
    m_levels.push_back(build_level<Dim, Scalar>(
        lattices[l], cells[l], problem.material,
        finest ? problem.boundary_stress : BoundaryStress<Dim>{},
        coarsest ? nullptr : &cells[l + 1], problem.inertia, m_options.band_layers, weights[l],
        clamp ? 0.5 * problem.lattice.h : 0.0,
        clamp ? finest_dirichlet_wall_layers(problem.lattice, problem.cells, lattices[l], cells[l],
                                             1 << l, m_options.misaligned_dirichlet_depth)
              : std::vector<std::uint8_t>{},
        m_options.release_dead_pages));
  }
}

// From the finest level down: a level's Galerkin rows are built from the level above as the
// cycle will run it, its own Galerkin rows included.
template <int Dim, typename Scalar>
void Multigrid<Dim, Scalar>::install_coarse_galerkin_rows() {
  const std::size_t levels = m_levels.size();
  if (levels < 2 || m_options.coarse_band_rows == CoarseBandRows::REDISCRETIZED) return;
  const std::size_t first = m_options.coarse_band_rows == CoarseBandRows::GALERKIN ? 1 : levels - 1;
  for (std::size_t l = first; l < levels; ++l)
    install_galerkin_band_rows(
        m_levels[l - 1], m_levels[l],
        l + 1 < levels ? GalerkinRowSet::AWAY_FROM_DIRICHLET : GalerkinRowSet::ALL);
}

template <int Dim, typename Scalar>
void Multigrid<Dim, Scalar>::set_dirichlet_displacement(
    const std::function<Vec<Dim>(const Vec<Dim>&)>& displacement) {
  if (m_solution) {
    set_dirichlet_values(*m_solution, displacement);
    back_substitute_traction(*m_solution);
  } else {
    set_dirichlet_values(m_levels.front(), displacement);
    back_substitute_traction(m_levels.front());
  }
}

template <int Dim, typename Scalar>
void Multigrid<Dim, Scalar>::set_loads(const ElasticityProblem<Dim>& problem) {
  if (m_solution) {
    replace_loads(*m_solution, problem);
  } else {
    replace_loads(m_levels.front(), problem);
  }
  record_zero_loads();
  m_solution_residual_current = false;
}

template <int Dim, typename Scalar>
std::size_t Multigrid<Dim, Scalar>::bytes() const {
  std::size_t total = m_solution ? m_solution->bytes() : 0;
  for (const auto& level : m_levels) total += level.bytes();
  return total + fused_restriction_bytes() + (m_krylov ? m_krylov->bytes() : 0) + m_local.bytes();
}

template <int Dim, typename Scalar>
std::vector<ByteShare> Multigrid<Dim, Scalar>::byte_breakdown() const {
  std::vector<ByteShare> total = m_levels.front().byte_breakdown();
  for (std::size_t l = 1; l < m_levels.size(); ++l) {
    const std::vector<ByteShare> shares = m_levels[l].byte_breakdown();
    for (std::size_t i = 0; i < shares.size(); ++i) total[i].bytes += shares[i].bytes;
  }
  total.push_back({"band rows by plane, residual windows", fused_restriction_bytes()});
  if (m_solution)
    for (ByteShare share : m_solution->byte_breakdown()) {
      share.name = "solution " + share.name;
      total.push_back(std::move(share));
    }
  if (m_krylov) total.push_back({"accelerated solve's vectors (kept)", m_krylov->bytes()});
  if (m_local.size() > 0) total.push_back({"local corrections", m_local.bytes()});
  return total;
}

template <int Dim, typename Scalar>
std::size_t Multigrid<Dim, Scalar>::fused_restriction_bytes() const {
  std::size_t total = m_residual_windows.bytes();
  for (const BandRowPlanes& planes : m_band_row_planes) total += planes.bytes();
  return total;
}

template <int Dim, typename Scalar>
double Multigrid<Dim, Scalar>::solution(int field, std::ptrdiff_t k) const {
  return m_solution ? m_solution->x[field][k] : static_cast<double>(m_levels.front().x[field][k]);
}

template <int Dim, typename Scalar>
void Multigrid<Dim, Scalar>::smooth(int l, bool pre) {
  Level<Dim, Scalar>& level = m_levels[l];
  // Sec. 5.2: a boundary pass, the interior distributive pass, a last boundary pass; then the
  // traction variables are back-substituted so every boundary condition holds exactly.
  Timer timer;
  band_gauss_seidel(level, m_boundary_sweeps, m_options.band_sweep_order, BandRhs::CURRENT);
  m_phases.boundary_smoothing += timer.seconds();
  observe(l, pre ? CyclePhase::PRE_SMOOTHING_BOUNDARY : CyclePhase::POST_SMOOTHING_BOUNDARY);
  timer.restart();
  distributive_sweep(level);
  m_phases.interior_smoothing += timer.seconds();
  observe(l, pre ? CyclePhase::PRE_SMOOTHING_INTERIOR : CyclePhase::POST_SMOOTHING_INTERIOR);
  timer.restart();
  band_gauss_seidel(level, m_boundary_sweeps, m_options.band_sweep_order, BandRhs::CURRENT);
  back_substitute_traction(level);
  m_phases.boundary_smoothing += timer.seconds();
  observe(l, pre ? CyclePhase::PRE_SMOOTHING_BOUNDARY_AFTER
                 : CyclePhase::POST_SMOOTHING_BOUNDARY_AFTER);
}

template <int Dim, typename Scalar>
void Multigrid<Dim, Scalar>::observe(int l, CyclePhase phase) {
  if (!m_monitor) return;
  Level<Dim, Scalar>& level = m_levels[l];
  bool finite = true;
  for (const auto& field : level.x)
    for (Scalar v : field) finite = finite && std::isfinite(v);
  // Overwrites level.r, which the cycle recomputes before it reads it (restriction).
  m_monitor->record(l, phase, compute_residual(level), finite);
}

template <int Dim, typename Scalar>
double Multigrid<Dim, Scalar>::residual() {
  if (!m_solution) return fresh_residual_norm(m_levels.front(), finest_band_planes());
  if (m_correction_pending) return refine();
  m_refined_norm = residual_to_correction_problem(*m_solution, m_levels.front());
  m_solution_residual_current = true;
  m_last_ratio = kUnknownRatio;  // a new solve: no cycle's ratio yet
  return m_refined_norm;
}

template <int Dim, typename Scalar>
double Multigrid<Dim, Scalar>::vcycle() {
  return cycle(false);
}

template <int Dim, typename Scalar>
double Multigrid<Dim, Scalar>::cycle(bool may_defer) {
  Level<Dim, Scalar>& fine = m_levels.front();
  if (!m_solution) {
    cycle_correction();
    Timer timer;
    const double norm = fresh_residual_norm(fine, finest_band_planes());
    m_phases.cycle_residual += timer.seconds();
    return norm;
  }
  // Mixed precision: the float hierarchy solves L e = r for the double residual r, which the
  // previous refinement (or residual()) left in the float level's b unless the solution changed
  // since; a pending correction goes on with that problem.
  Timer timer;
  if (!m_correction_pending) {
    if (!m_solution_residual_current) {
      m_refined_norm = residual_to_correction_problem(*m_solution, fine);
      m_phases.cycle_residual += timer.seconds();
      timer.restart();
    }
    if (!m_correction_zero) zero_correction(fine);
    m_deferred_cycles = 0;
    m_phases.refinement += timer.seconds();
  }
  const double before = m_correction_pending ? m_last_float_norm : m_refined_norm;
  cycle_correction();
  const double reduction = m_options.refinement_reduction;
  if (may_defer && reduction < 1 && ++m_deferred_cycles < kMaxDeferredCycles &&
      m_last_ratio != kUnknownRatio &&
      (m_last_ratio >= 1 || before * m_last_ratio > reduction * m_refined_norm)) {
    // The float norm (~60 % of a double residual) only where the last cycle's ratio does not
    // predict the reduction; a solve's first cycle (no ratio yet) refines without it.
    timer.restart();
    const double norm = fresh_residual_norm(fine, finest_band_planes());
    m_phases.cycle_residual += timer.seconds();
    ++m_float_norms;
    m_correction_pending = true;
    m_last_float_norm = norm;
    m_last_ratio = norm / before;
    // Refine now when reduced enough; when the cycle raised the residual above the problem's
    // start or stopped reducing it (float round-off of a large correction reached); or when the
    // norm is not finite (the double residual says more).
    if (norm > reduction * m_refined_norm && norm <= m_refined_norm &&
        m_last_ratio <= kDeferredStall && std::isfinite(norm))
      return norm;
  }
  const double norm = refine();
  m_last_ratio = before > 0 ? norm / before : kUnknownRatio;  // this cycle's, in double
  return norm;
}

template <int Dim, typename Scalar>
double Multigrid<Dim, Scalar>::refine() {
  Level<Dim, Scalar>& fine = m_levels.front();
  Timer timer;
  add_correction(fine, *m_solution);
  m_correction_zero = true;
  m_correction_pending = false;
  back_substitute_traction(*m_solution);
  m_phases.refinement += timer.seconds();
  timer.restart();
  m_refined_norm = residual_to_correction_problem(*m_solution, fine);
  m_solution_residual_current = true;
  ++m_refinements;
  m_phases.cycle_residual += timer.seconds();
  return m_refined_norm;
}

template <int Dim, typename Scalar>
void Multigrid<Dim, Scalar>::cycle_correction() {
  m_correction_zero = false;  // the cycle writes the finest level's x
  observe(0, CyclePhase::CYCLE_START);
  // The local corrections first: the cycle's smoothing then removes the residual that each
  // leaves at its box's border (after the cycle, that residual raised the residual norm of the
  // cycle that first applied a box, up to 8x).
  Timer timer;
  m_local.apply(m_levels.front());
  m_phases.coarse_solve += timer.seconds();
  correct(0);
}

// Algorithm 1 written recursively: level l improves x for its equations b; the coarse problem
// is visited once (V-cycle) or twice (W-cycle) per visit of level l.
template <int Dim, typename Scalar>
void Multigrid<Dim, Scalar>::correct(int l) {
  const int coarsest = levels() - 1;
  Timer timer;
  if (l == coarsest) {
    if (m_galerkin)
      m_galerkin->solve(m_levels[coarsest]);
    else
      m_coarse->solve(m_levels[coarsest]);
    m_phases.coarse_solve += timer.seconds();
    observe(l, CyclePhase::COARSE_SOLVE);
    return;
  }
  // b of level l is fixed until the visit ends: the band calls below read one refresh of it.
  refresh_band_rhs(m_levels[l]);
  m_phases.boundary_smoothing += timer.seconds();
  smooth(l, true);
  timer.restart();
  relocation_sweeps(m_levels[l], m_options.relocation_sweeps, m_levels[l].pre_restriction_rows,
                    m_levels[l].pre_restriction_schedule, m_options.band_sweep_order);
  m_phases.boundary_smoothing += timer.seconds();
  observe(l, CyclePhase::RELOCATION_BEFORE_RESTRICTION);
  restrict_to_next(l);
  observe(l + 1, CyclePhase::RESTRICTION);
  const int visits = (m_options.cycle == CycleType::W && l + 1 < coarsest) ? 2 : 1;
  for (int visit = 0; visit < visits; ++visit) correct(l + 1);
  timer.restart();
  prolongate_correction(m_levels[l + 1], m_levels[l]);
  m_phases.prolongation += timer.seconds();
  observe(l, CyclePhase::PROLONGATION);
  timer.restart();
  relocation_sweeps(m_levels[l], m_options.relocation_sweeps, m_levels[l].post_prolongation_rows,
                    m_levels[l].post_prolongation_schedule, m_options.band_sweep_order);
  m_phases.boundary_smoothing += timer.seconds();
  observe(l, CyclePhase::RELOCATION_AFTER_PROLONGATION);
  smooth(l, false);
}

template <int Dim, typename Scalar>
void Multigrid<Dim, Scalar>::restrict_to_next(int l) {
  Timer timer;
  if (fuses_restriction(l)) {
    restrict_fresh_residual(m_levels[l], m_band_row_planes[static_cast<std::size_t>(l)],
                            m_levels[l + 1], m_residual_windows);
    m_phases.residual += timer.seconds();  // residual and restriction in one pass
    return;
  }
  update_residual(m_levels[l]);
  m_phases.residual += timer.seconds();
  timer.restart();
  restrict_residual(m_levels[l], m_levels[l + 1]);
  m_phases.restriction += timer.seconds();
}

template <int Dim, typename Scalar>
SolveReport Multigrid<Dim, Scalar>::solve(double relative_tolerance, int max_cycles,
                                          int stall_cycles) {
  SolveReport report;
  Timer timer;
  report.residuals.push_back(residual());
  if (!std::isfinite(report.residuals.front()))
    throw Error("the initial residual is not finite (NaN or Inf in the loads or boundary values)",
                {.pointer = "loads"});
  const StartState& start = capture_start();  // for the replay of a diverging solve
  m_phases.solve_setup += timer.seconds();
  const double target = relative_tolerance * report.residuals.front();
  StallWatch stall(stall_cycles);
  // A float residual (a deferred refinement) at the tolerance is checked in double first.
  const auto reached = [&] {
    if (m_correction_pending && report.residuals.back() <= target)
      report.residuals.back() = refine();
    return report.residuals.back() <= target;
  };
  while (report.cycles() < max_cycles && !reached()) {
    try {
      throw_if_cancelled();
    } catch (const Cancelled&) {
      if (m_correction_pending) refine();  // the solution keeps the cycles' progress
      throw;
    }
    // The last cycle allowed refines without a float norm: its solve ends with a refinement.
    report.residuals.push_back(cycle(report.cycles() + 1 < max_cycles));
    const std::string reason = divergence_reason(report.residuals);
    if (!reason.empty())
      fail_diverged("V-cycle " + std::to_string(report.cycles()), reason, report.residuals, start);
    place_local_corrections(report.residuals);
    if (stall.stalled_after(report.residuals.back()) && report.residuals.back() > target) {
      report.stalled = true;
      break;
    }
  }
  if (m_correction_pending) report.residuals.back() = refine();
  report.converged = report.residuals.back() <= target;
  report.seconds = timer.seconds();
  return report;
}

template <int Dim, typename Scalar>
void Multigrid<Dim, Scalar>::place_local_corrections(const std::vector<double>& residuals) {
  const std::size_t n = residuals.size();
  if (n < 3 || levels() < 2) return;
  const auto ratio = [&](std::size_t i) { return residuals[i] / residuals[i - 1]; };
  if (!m_local.due(1, ratio(n - 1), ratio(n - 2))) return;
  Timer timer;
  const Level<Dim, Scalar>& fine = m_levels.front();
  // The float level's residual is the correction problem's: the double one, rounded.
  const int cube = m_local.cube(fine);
  m_local.place(fine,
                slow_mode_boxes<Dim>(residual_blocks<Dim>(fine, cube, SIZE_MAX), cube, fine.lattice,
                                     kLocalCorrectionMinShare, kLocalCorrectionCover, cube));
  m_phases.solve_setup += timer.seconds();
}

template <int Dim, typename Scalar>
void Multigrid<Dim, Scalar>::fail_diverged(const std::string& what, const std::string& reason,
                                           const std::vector<double>& residuals,
                                           const StartState& start) {
  // Replay plain cycles from the solve's start, checking after every phase, until the first
  // non-finite values or as many cycles as the solve used.
  restore_start(start);
  CycleMonitor monitor;
  m_monitor = &monitor;
  const int cycles = static_cast<int>(residuals.size()) - 1;
  for (int c = 1; c <= cycles && !monitor.found_non_finite(); ++c) {
    monitor.start_cycle(c);
    vcycle();
  }
  m_monitor = nullptr;
  throw Error(what + " diverged: " + reason + "; residual history: " + format_history(residuals) +
                  "; diagnosis (cycles replayed from the same start with a residual check after "
                  "every phase): " +
                  monitor.diagnosis(levels()),
              {.pointer = "solver"});
}

template <int Dim, typename Scalar>
auto Multigrid<Dim, Scalar>::capture_start() -> const StartState& {
  // The live chunks only (live_chunks.hpp): a copy of the whole box would fault in every page of
  // the copy and read the released pages of the source, each a page fault (on the armadillo at
  // 256 this took 1.3 s per solve on a virtual machine). Into the last solve's storage.
  StartState& start = m_start;
  start.packed = true;
  const auto capture = [&](const auto& level, auto& packed) {
    for (int f = 0; f <= Dim; ++f) {
      start.zero[f] = zero_where_live(level.x[f], level.live);
      if (!start.zero[f]) pack_live_into(level.x[f], level.live, packed[f]);
    }
  };
  if (single_precision()) {
    capture(m_levels.front(), start.single);
  } else if (m_solution) {
    capture(*m_solution, start.solution);
  } else {
    start.solution = solution_state();
    start.packed = false;
  }
  return start;
}

template <int Dim, typename Scalar>
void Multigrid<Dim, Scalar>::restore_start(const StartState& start) {
  m_correction_pending = false;  // the replay starts a new correction problem
  m_correction_zero = false;
  if (!start.packed) {
    set_solution_state(start.solution);
    return;
  }
  const auto restore = [&](auto& level, const auto& packed) {
    for (int f = 0; f <= Dim; ++f) {
      if (start.zero[f])
        zero_live(level.x[f], level.live);
      else
        unpack_live(packed[f], level.x[f], level.live);
    }
  };
  if (single_precision()) {
    restore(m_levels.front(), start.single);
  } else {
    restore(solution_storage(), start.solution);
    m_solution_residual_current = false;
  }
}

template <int Dim, typename Scalar>
auto Multigrid<Dim, Scalar>::solution_state() const -> const SolutionState& {
  if constexpr (std::is_same_v<Scalar, double>) {
    return m_solution ? m_solution->x : m_levels.front().x;
  } else {
    if (m_solution) return m_solution->x;
    for (int f = 0; f <= Dim; ++f)
      m_single_state[f].assign(m_levels.front().x[f].begin(), m_levels.front().x[f].end());
    return m_single_state;
  }
}

template <int Dim, typename Scalar>
void Multigrid<Dim, Scalar>::set_solution_state(const SolutionState& x) {
  if (single_precision()) {
    copy_solution_state(x, m_levels.front().x, m_levels.front().live);
  } else {
    // Only x changes: b's released zero pages stay released (solution_level() would forget them).
    Level<Dim, double>& solution = solution_storage();
    copy_solution_state(x, solution.x, solution.live);
  }
  m_solution_residual_current = false;
}

template <int Dim, typename Scalar>
SolveReport Multigrid<Dim, Scalar>::run_cycles(int cycles) {
  return solve(0.0, cycles);
}

template class Multigrid<2, float>;
template class Multigrid<2, double>;
template class Multigrid<3, float>;
template class Multigrid<3, double>;

}  // namespace mgelastic::grid
