#include "mgelastic/grid/corotated_multigrid.hpp"

#include <Eigen/Dense>
#include <Eigen/UmfPackSupport>
#include <algorithm>
#include <cmath>
#include <cstdio>
#include <string>

#include "mgelastic/core/blas_threads.hpp"
#include "mgelastic/core/cancellation.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/core/timer.hpp"
#include "mgelastic/grid/corotated_acceleration.hpp"
#include "mgelastic/grid/corotated_band_smoother.hpp"
#include "mgelastic/grid/corotated_distributive_smoother.hpp"
#include "mgelastic/grid/corotated_newton_krylov.hpp"
#include "mgelastic/grid/load_update.hpp"
#include "mgelastic/grid/transfer.hpp"

namespace mgelastic::grid {

// Box-smoother blocks of one level: per interior cell, the rows of its interior faces and its
// pressure, with the inverse of their diagonal block (row-major).
//
// The sweeps run in parallel over colored zones (block_partition.hpp's scheme: rectangular zones
// of cells, 2^d colors by the parity of the zone index along every axis): zones of one color are
// a whole zone apart, wider along every axis than the rows reach (row_reach), so their blocks
// are relaxed concurrently, each zone's in lattice order. The order is fixed, so results do not
// depend on the thread count.
template <int Dim>
struct CorotatedMultigrid<Dim>::Blocks {
  std::vector<std::uint32_t> start{0}, rows;
  std::vector<std::ptrdiff_t> cell;  // the interior cell of each block
  std::vector<std::size_t> inverse_start{0};
  std::vector<double> inverse;
  // Blocks holding a Fig. 8 relocated-boundary variable (Level::pre_restriction_rows and
  // post_prolongation_rows): swept again before restriction and after prolongation.
  std::vector<std::uint32_t> relocated;
  // Blocks holding a row the linear level relaxes in its band (DISTRIBUTIVE smoother only).
  std::vector<std::uint32_t> band;
  // ALL, BAND and RELOCATED (BlockSet order): per color, per zone, the set's blocks in order.
  using Schedule = std::array<std::vector<std::vector<std::uint32_t>>, (1 << Dim)>;
  std::array<Schedule, 3> schedule;
};

template <int Dim>
struct CorotatedMultigrid<Dim>::Interior {
  CorotatedDistributiveSmoother<Dim> smoother;
  CorotatedBandSmoother<Dim> band;
};

// LU of the coarsest level's rows (unsymmetric next to traction rows, indefinite). UMFPACK: its
// BLAS-3 supernodes factor a 24 k-unknown coarsest level several times faster than Eigen's
// SparseLU. A refresh keeps the rows' columns, so the symbolic analysis (ordering) is reused
// while the pattern stays the same.
template <int Dim>
struct CorotatedMultigrid<Dim>::CoarseFactor {
  Eigen::UmfPackLU<Eigen::SparseMatrix<double>> lu;
  Eigen::SparseMatrix<double> matrix;  // factored; the LU's solves read it (refinement steps)

  bool same_pattern(const Eigen::SparseMatrix<double>& a) const {
    return a.rows() == matrix.rows() && a.nonZeros() == matrix.nonZeros() &&
           std::equal(a.outerIndexPtr(), a.outerIndexPtr() + a.outerSize() + 1,
                      matrix.outerIndexPtr()) &&
           std::equal(a.innerIndexPtr(), a.innerIndexPtr() + a.nonZeros(), matrix.innerIndexPtr());
  }
  bool factor(Eigen::SparseMatrix<double> a) {
    const SingleThreadedBlas one_blas_thread;  // results independent of the thread count
    const bool analyzed = same_pattern(a);
    matrix = std::move(a);
    if (!analyzed) lu.analyzePattern(matrix);
    lu.factorize(matrix);
    return lu.info() == Eigen::Success;
  }
};

namespace {

constexpr double kDivergenceGrowth = 1e4;  // residual growth within one solve taken as divergence

std::string scientific(double value) {
  char text[32];
  std::snprintf(text, sizeof text, "%.3g", value);
  return text;
}

// A block per interior cell: the rows of its faces and its pressure (Sec. 5.2's box). Which rows
// exist does not change between refreshes, so the blocks are built once; a refresh recomputes
// their inverses (block_inverses).
template <int Dim>
void build_blocks(const Level<Dim, double>& level, const CorotatedRows& rows,
                  std::vector<std::uint32_t>& start, std::vector<std::uint32_t>& block_rows,
                  std::vector<std::ptrdiff_t>& block_cells,
                  std::vector<std::size_t>& inverse_start) {
  const auto n = static_cast<std::ptrdiff_t>(level.size());
  for (std::ptrdiff_t c = 0; c < n; ++c) {
    if (level.cells[c] != CellType::INTERIOR) continue;
    const std::size_t first = block_rows.size();
    for (int i = 0; i < Dim; ++i)
      for (std::ptrdiff_t face : {c, c + level.lattice.stride(i)}) {
        const std::int32_t row = rows.row_of[level.global(i, face)];
        if (row >= 0) block_rows.push_back(static_cast<std::uint32_t>(row));
      }
    const std::int32_t p_row = rows.row_of[level.global(Dim, c)];
    if (p_row >= 0) block_rows.push_back(static_cast<std::uint32_t>(p_row));
    const std::size_t m = block_rows.size() - first;
    if (m == 0) continue;
    start.push_back(static_cast<std::uint32_t>(block_rows.size()));
    block_cells.push_back(c);
    inverse_start.push_back(inverse_start.back() + m * m);
  }
}

// Each block's inverse from the current rows, blocks in parallel (each writes its own slot).
void block_inverses(const CorotatedRows& rows, const std::vector<std::uint32_t>& start,
                    const std::vector<std::uint32_t>& block_rows,
                    const std::vector<std::size_t>& inverse_start, std::vector<double>& inverse) {
  constexpr int kMax = 7;  // 2 Dim faces and the pressure
  using Block = Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, 0, kMax, kMax>;
  inverse.resize(inverse_start.back());
  const auto blocks = static_cast<std::ptrdiff_t>(start.size()) - 1;
#pragma omp parallel for schedule(dynamic, 256)
  for (std::ptrdiff_t b = 0; b < blocks; ++b) {
    const std::uint32_t* members = block_rows.data() + start[b];
    const int m = static_cast<int>(start[b + 1] - start[b]);
    Block a(m, m);
    for (int r = 0; r < m; ++r)
      for (int c = 0; c < m; ++c) a(r, c) = rows.coefficient(members[r], rows.target[members[c]]);
    const Eigen::FullPivLU<Block> lu(a);
    // A singular block (degenerate rotations) is relaxed by its pseudo-inverse-free fallback:
    // the diagonal only, so a sweep never produces NaN.
    Block inv = Block::Zero(m, m);
    if (lu.isInvertible())
      inv = lu.inverse();
    else
      for (int r = 0; r < m; ++r) inv(r, r) = a(r, r) != 0 ? 1.0 / a(r, r) : 0.0;
    double* out = inverse.data() + inverse_start[b];
    for (int r = 0; r < m; ++r)
      for (int c = 0; c < m; ++c) out[r * m + c] = inv(r, c);
  }
}

// The largest coordinate difference along each axis between a row's variable and its columns.
// A column's offset is split by the strides from the top axis down (rounded to the nearest
// multiple, no division), checked against the flat index and the lattice rows, and only where
// that fails (offsets longer than half a stride: tiny lattices) taken from the coordinates.
template <int Dim>
IVec<Dim> row_reach(const Level<Dim, double>& level, const CorotatedRows& rows) {
  const Lattice<Dim>& lattice = level.lattice;
  const GlobalSplit<Dim> split = level.split();
  const auto index = [&](std::uint32_t global) {
    return static_cast<std::ptrdiff_t>(split.index(global, split.field(global)));
  };
  const auto offset_coords = [&](std::ptrdiff_t d) {
    IVec<Dim> c;
    for (int a = Dim - 1; a >= 1; --a) {
      const std::ptrdiff_t stride = lattice.stride(a);
      std::ptrdiff_t q = 0;
      while (d - q * stride > stride / 2) ++q;
      while (d - q * stride < -(stride / 2)) --q;
      c[a] = static_cast<int>(q);
      d -= q * stride;
    }
    c[0] = static_cast<int>(d);
    return c;
  };
  IVec<Dim> reach = IVec<Dim>::Zero();
  for (std::size_t m = 0; m < rows.rows(); ++m) {
    const std::ptrdiff_t self = index(rows.target[m]);
    const IVec<Dim> at = lattice.coords(self);
    for (std::uint32_t e = rows.start[m]; e < rows.start[m + 1]; ++e) {
      const std::ptrdiff_t k = index(rows.column[e]);
      IVec<Dim> c = offset_coords(k - self);
      bool exact = lattice.index(at + c) == k;
      for (int a = 0; a + 1 < Dim; ++a)  // no wrap around a lattice row or plane
        exact =
            exact && at[a] + c[a] >= 0 && at[a] + c[a] < lattice.stride(a + 1) / lattice.stride(a);
      if (!exact) c = lattice.coords(k) - at;
      reach = reach.cwiseMax(c.cwiseAbs());
    }
  }
  return reach;
}

// Zones of 16 x 8 (x 8) cells (many per color for the threads, long enough along x for the
// rows' streams), wider than the rows reach.
template <int Dim>
IVec<Dim> zone_size(const IVec<Dim>& reach) {
  IVec<Dim> size = IVec<Dim>::Constant(8);
  size[0] = 16;
  return size.cwiseMax(reach + IVec<Dim>::Ones());
}

// The blocks `members` (all blocks when null) grouped by colored zone (the colors of
// BlockPartition::color_of), in order.
template <int Dim, typename Schedule>
Schedule zone_schedule(const Lattice<Dim>& lattice, const std::vector<std::ptrdiff_t>& block_cells,
                       const std::vector<std::uint32_t>* members, const IVec<Dim>& zone) {
  BlockPartition<Dim> zones;
  zones.block_size = zone;
  for (int a = 0; a < Dim; ++a)
    zones.blocks_per_axis[a] = (lattice.cells[a] + zone[a] - 1) / zone[a];
  std::vector<std::vector<std::uint32_t>> by_zone(
      static_cast<std::size_t>(zones.blocks_per_axis.prod()));
  std::vector<int> color_of_zone(by_zone.size());
  const auto add = [&](std::uint32_t b) {
    const IVec<Dim> s = lattice.coords(block_cells[b]);
    std::size_t id = 0;
    for (int a = Dim - 1; a >= 0; --a) id = id * zones.blocks_per_axis[a] + (s[a] - 1) / zone[a];
    by_zone[id].push_back(b);
    color_of_zone[id] = zones.color_of(s);
  };
  if (members)
    for (std::uint32_t b : *members) add(b);
  else
    for (std::uint32_t b = 0; b < block_cells.size(); ++b) add(b);
  Schedule schedule;
  for (std::size_t id = 0; id < by_zone.size(); ++id)
    if (!by_zone[id].empty()) schedule[color_of_zone[id]].push_back(std::move(by_zone[id]));
  return schedule;
}

}  // namespace

template <int Dim>
CorotatedMultigrid<Dim>::CorotatedMultigrid(const ElasticityProblem<Dim>& problem,
                                            MultigridOptions multigrid, CorotatedOptions options)
    : m_multigrid(problem, multigrid),
      m_options(options),
      m_sigma(problem.boundary_stress),
      m_sigma_full(problem.boundary_stress) {
  if (options.rotation_update_every < 1)
    throw Error("rotation_update_every must be at least 1, got " +
                    std::to_string(options.rotation_update_every),
                {.pointer = "time.rotation_update_every"});
  m_rotations.resize(levels());
  m_rows.resize(levels());
  m_blocks.resize(levels());
  m_interior.resize(levels());
  const auto& finest = m_multigrid.level(0);
  for (int f = 0; f < Dim; ++f)
    for (std::size_t k = 0; k < finest.size(); ++k)
      if (finest.kind(f, k) == VarKind::DIRICHLET) m_dirichlet.push_back(finest.global(f, k));
  // Zero load: the state u = 0 the first solve_with_load_steps ramps from.
  for (auto& field : m_equilibrium.b) field.assign(finest.size(), 0.0);
  m_equilibrium.dirichlet.assign(m_dirichlet.size(), 0.0);
  refresh_rotations();
}

template <int Dim>
CorotatedMultigrid<Dim>::~CorotatedMultigrid() = default;

template <int Dim>
void CorotatedMultigrid<Dim>::set_dirichlet_displacement(
    const std::function<Vec<Dim>(const Vec<Dim>&)>& displacement) {
  m_multigrid.set_dirichlet_displacement(displacement);
  back_substitute(0);
}

template <int Dim>
void CorotatedMultigrid<Dim>::set_loads(const ElasticityProblem<Dim>& problem) {
  // Not Multigrid::set_loads: its back-substitution with the linear traction rules would change
  // x, which a restored build keeps.
  Level<Dim, double>& finest = m_multigrid.level(0);
  check_same_system(finest, problem);
  replace_boundary_stress(finest, problem.boundary_stress);
  write_load_right_hand_side(problem, finest);
  m_sigma_full = problem.boundary_stress;
  set_traction_scale(1.0);
  m_rows[0].constant =
      build_corotated_rows(finest, m_rotations[0], m_sigma, false, m_options.stress).constant;
  m_fresh_rotations = false;
  m_equilibrium = current_load();
}

template <int Dim>
void CorotatedMultigrid<Dim>::refresh_rotations() {
  cell_rotations(m_multigrid.level(0), m_rotations[0]);
  refresh_levels();
}

// Every level's system from the finest rotations m_rotations[0].
template <int Dim>
void CorotatedMultigrid<Dim>::refresh_levels() {
  for (int l = 1; l < levels(); ++l) {
    const auto& fine = m_multigrid.level(l - 1);
    m_rotations[l] = restrict_rotations(fine.lattice, fine.cells, m_rotations[l - 1],
                                        m_multigrid.level(l).lattice);
  }
  for (int l = 0; l < levels(); ++l) build_level_system(l);
  m_cycles_since_refresh = 0;
}

template <int Dim>
void CorotatedMultigrid<Dim>::build_level_system(int l) {
  const auto& level = m_multigrid.level(l);
  build_corotated_rows(level, m_rotations[l], m_sigma, l > 0, m_options.stress, m_rows[l]);
  const int coarsest = levels() - 1;
  if (l == coarsest) {
    const CorotatedRows& rows = m_rows[l];
    std::vector<Eigen::Triplet<double>> entries;
    for (std::size_t m = 0; m < rows.rows(); ++m)
      for (std::uint32_t e = rows.start[m]; e < rows.start[m + 1]; ++e) {
        const std::int32_t col = rows.row_of[rows.column[e]];
        if (col >= 0) entries.emplace_back(static_cast<int>(m), col, rows.value[e]);
      }
    const auto size = static_cast<int>(rows.rows());
    Eigen::SparseMatrix<double> a(size, size);
    a.setFromTriplets(entries.begin(), entries.end());
    a.makeCompressed();
    if (!m_coarse) m_coarse = std::make_unique<CoarseFactor>();
    if (!m_coarse->factor(std::move(a)))
      throw Error("the co-rotated coarsest-level matrix is singular (a body without support?)");
    return;
  }
  if (!m_blocks[l]) build_block_structure(l);  // a refresh keeps the rows, with new values
  Blocks& blocks = *m_blocks[l];
  block_inverses(m_rows[l], blocks.start, blocks.rows, blocks.inverse_start, blocks.inverse);
  if (m_options.smoother == CorotatedSmoother::DISTRIBUTIVE)
    m_interior[l] = std::make_unique<Interior>(Interior{{level, m_rows[l]}, {level, m_rows[l]}});
}

// The box smoother's blocks, their relocated and band subsets and colored schedules: which rows
// exist does not depend on R (the rows keep one pattern for every R, corotated_operator.cpp), so
// this is built once per level.
template <int Dim>
void CorotatedMultigrid<Dim>::build_block_structure(int l) {
  const auto& level = m_multigrid.level(l);
  m_blocks[l] = std::make_unique<Blocks>();
  Blocks* blocks = m_blocks[l].get();
  build_blocks(level, m_rows[l], blocks->start, blocks->rows, blocks->cell, blocks->inverse_start);
  std::vector<std::uint8_t> marked(m_rows[l].rows(), 0);
  for (const auto* set : {&level.pre_restriction_rows, &level.post_prolongation_rows})
    for (std::uint32_t m : *set) {
      const std::int32_t row = m_rows[l].row_of[level.band_kernel.global_target(m, level.size())];
      if (row >= 0) marked[row] = 1;
    }
  for (std::uint32_t b = 0; b + 1 < blocks->start.size(); ++b)
    for (std::uint32_t e = blocks->start[b]; e < blocks->start[b + 1]; ++e)
      if (marked[blocks->rows[e]]) {
        blocks->relocated.push_back(b);
        break;
      }
  if (m_options.smoother == CorotatedSmoother::DISTRIBUTIVE) {
    const std::size_t n = level.size();
    for (std::uint32_t b = 0; b + 1 < blocks->start.size(); ++b)
      for (std::uint32_t e = blocks->start[b]; e < blocks->start[b + 1]; ++e) {
        const std::uint32_t t = m_rows[l].target[blocks->rows[e]];
        if (level.relaxation(t / n, t % n) != Relaxation::DISTRIBUTIVE) {
          blocks->band.push_back(b);
          break;
        }
      }
  }
  using Schedule = typename Blocks::Schedule;
  const IVec<Dim> zone = zone_size(row_reach(level, m_rows[l]));
  const auto& cells = blocks->cell;
  blocks->schedule[0] = zone_schedule<Dim, Schedule>(level.lattice, cells, nullptr, zone);
  blocks->schedule[1] = zone_schedule<Dim, Schedule>(level.lattice, cells, &blocks->band, zone);
  blocks->schedule[2] =
      zone_schedule<Dim, Schedule>(level.lattice, cells, &blocks->relocated, zone);
}

template <int Dim>
void CorotatedMultigrid<Dim>::back_substitute(int l) {
  corotated_back_substitute(m_multigrid.level(l), m_rotations[l], m_sigma, l > 0);
}

template <int Dim>
void CorotatedMultigrid<Dim>::box_sweep(int l, bool forward, BlockSet set) {
  auto& level = m_multigrid.level(l);
  const CorotatedRows& rows = m_rows[l];
  const Blocks& blocks = *m_blocks[l];
  const GlobalSplit<Dim> split = level.split();
  const double weight = m_options.block_weight;
  const auto relax = [&](std::uint32_t b) {
    constexpr int kMax = 2 * Dim + 1;
    std::array<double, kMax> r{}, delta{};
    const std::uint32_t first = blocks.start[b];
    const int m = static_cast<int>(blocks.start[b + 1] - first);
    for (int a = 0; a < m; ++a) {
      const std::uint32_t row = blocks.rows[first + a];
      double value = rows.constant[row];
      for (std::uint32_t e = rows.start[row]; e < rows.start[row + 1]; ++e)
        value += rows.value[e] * level.at(rows.column[e]);
      r[a] = split(level.b, rows.target[row]) - value;
    }
    const double* inv = blocks.inverse.data() + blocks.inverse_start[b];
    for (int a = 0; a < m; ++a) {
      delta[a] = 0;
      for (int c = 0; c < m; ++c) delta[a] += inv[a * m + c] * r[c];
    }
    for (int a = 0; a < m; ++a) level.at(rows.target[blocks.rows[first + a]]) += weight * delta[a];
  };
  // Forward: colors, and each zone's blocks, in order; backward: both reversed.
  const typename Blocks::Schedule& schedule = blocks.schedule[static_cast<int>(set)];
  constexpr int kColors = 1 << Dim;
  for (int step = 0; step < kColors; ++step) {
    const auto& zones = schedule[forward ? step : kColors - 1 - step];
    const auto count = static_cast<std::ptrdiff_t>(zones.size());
#pragma omp parallel for schedule(dynamic, 1)
    for (std::ptrdiff_t z = 0; z < count; ++z) {
      const std::vector<std::uint32_t>& members = zones[z];
      if (forward)
        for (std::uint32_t b : members) relax(b);
      else
        for (auto b = members.rbegin(); b != members.rend(); ++b) relax(*b);
    }
  }
}

template <int Dim>
void CorotatedMultigrid<Dim>::band_pass(int l, bool forward) {
  if (m_options.band == CorotatedBand::SCHUR) {
    m_interior[l]->band.sweep(m_multigrid.level(l), m_rows[l], m_multigrid.boundary_sweeps());
    return;
  }
  for (int sweep = 0; sweep < m_options.band_sweeps; ++sweep) box_sweep(l, forward, BlockSet::BAND);
}

// One smoothing step, then the traction variables from the co-rotated traction conditions.
template <int Dim>
void CorotatedMultigrid<Dim>::smooth(int l, bool forward) {
  if (m_options.smoother == CorotatedSmoother::BOX) {
    box_sweep(l, forward, BlockSet::ALL);
  } else {
    // Sec. 5.2: a band pass, the interior distributive pass, a last band pass.
    band_pass(l, forward);
    m_interior[l]->smoother.sweep(m_multigrid.level(l), m_rows[l]);
    band_pass(l, forward);
  }
  back_substitute(l);
}

template <int Dim>
void CorotatedMultigrid<Dim>::correct(int l) {
  auto& level = m_multigrid.level(l);
  const int coarsest = levels() - 1;
  if (l == coarsest) {
    const CorotatedRows& rows = m_rows[l];
    Eigen::VectorXd rhs(static_cast<Eigen::Index>(rows.rows()));
    for (std::size_t m = 0; m < rows.rows(); ++m) {
      double value = level.split()(level.b, rows.target[m]) - rows.constant[m];
      for (std::uint32_t e = rows.start[m]; e < rows.start[m + 1]; ++e)
        if (rows.row_of[rows.column[e]] < 0) value -= rows.value[e] * level.at(rows.column[e]);
      rhs[static_cast<Eigen::Index>(m)] = value;
    }
    const Eigen::VectorXd solution = m_coarse->lu.solve(rhs);
    for (std::size_t m = 0; m < rows.rows(); ++m)
      level.at(rows.target[m]) = solution[static_cast<Eigen::Index>(m)];
    back_substitute(l);
    return;
  }
  for (int sweep = 0; sweep < m_options.sweeps; ++sweep) smooth(l, true);
  for (int sweep = 0; sweep < m_options.relocation_sweeps; ++sweep) {
    box_sweep(l, true, BlockSet::RELOCATED);
    back_substitute(l);
  }
  corotated_residual(level, m_rows[l]);
  restrict_residual(level, m_multigrid.level(l + 1));
  correct(l + 1);
  prolongate_correction(m_multigrid.level(l + 1), level);
  for (int sweep = 0; sweep < m_options.relocation_sweeps; ++sweep) {
    box_sweep(l, false, BlockSet::RELOCATED);
    back_substitute(l);
  }
  for (int sweep = 0; sweep < m_options.sweeps; ++sweep) smooth(l, false);
}

template <int Dim>
double CorotatedMultigrid<Dim>::quasi_linear_residual() {
  return corotated_residual(m_multigrid.level(0), m_rows[0]);
}

// Matrix-free: each row is applied as it is built. When the next cycle refreshes, the rotations
// are kept for it. (Building the rows here for that refresh cost a whole row build per call
// whose x then moved before the refresh: a backward-Euler step's right-hand side and its last
// residual, an Anderson cycle's rejected iterates.)
template <int Dim>
double CorotatedMultigrid<Dim>::nonlinear_residual() {
  const double residual = matrix_free_nonlinear_residual();
  m_fresh_rotations = m_cycles_since_refresh >= m_options.rotation_update_every;
  return residual;
}

// Refreshes the rotations once k cycles have passed, reusing those of the last non-linear
// residual when it left them; the cache is dropped either way (the next cycle moves x).
template <int Dim>
void CorotatedMultigrid<Dim>::refresh_rotations_when_due() {
  if (m_cycles_since_refresh >= m_options.rotation_update_every) {
    if (m_fresh_rotations) {
      std::swap(m_rotations[0], m_scratch_rotations);  // the old ones: the next scratch
      refresh_levels();
    } else {
      refresh_rotations();
    }
  }
  m_fresh_rotations = false;
}

template <int Dim>
double CorotatedMultigrid<Dim>::vcycle() {
  m_fresh_rotations = false;
  return solve_cycle();
}

template <int Dim>
double CorotatedMultigrid<Dim>::solve_cycle() {
  refresh_rotations_when_due();
  correct(0);
  ++m_cycles_since_refresh;
  return quasi_linear_residual();
}

template <int Dim>
Eigen::VectorXd CorotatedMultigrid<Dim>::gather_unknowns() const {
  const CorotatedRows& rows = m_rows[0];
  const auto& level = m_multigrid.level(0);
  Eigen::VectorXd values(static_cast<Eigen::Index>(rows.rows()));
  for (std::size_t m = 0; m < rows.rows(); ++m)
    values[static_cast<Eigen::Index>(m)] = level.at(rows.target[m]);
  return values;
}

template <int Dim>
void CorotatedMultigrid<Dim>::scatter_unknowns(const Eigen::VectorXd& values) {
  const CorotatedRows& rows = m_rows[0];
  auto& level = m_multigrid.level(0);
  for (std::size_t m = 0; m < rows.rows(); ++m)
    level.at(rows.target[m]) = values[static_cast<Eigen::Index>(m)];
  back_substitute(0);
}

// One Anderson-mixed cycle; returns the non-linear residual of the accepted iterate. The mixed
// iterate is kept when it lowers the non-linear residual; otherwise the history restarts
// (safeguard against extrapolating across a changed map) and the smaller of the mixed and the
// plain cycle's residuals is kept.
template <int Dim>
double CorotatedMultigrid<Dim>::accelerated_cycle(AndersonMixing& anderson, double previous,
                                                  double& quasi_linear) {
  const Eigen::VectorXd x = gather_unknowns();
  quasi_linear = solve_cycle();
  const Eigen::VectorXd gx = gather_unknowns();
  const bool extrapolated = anderson.history() > 0;
  const Eigen::VectorXd mixed = anderson.mix(x, gx);
  if (!extrapolated) return nonlinear_residual();
  scatter_unknowns(mixed);
  double residual = nonlinear_residual();
  if (residual >= previous) {
    anderson.reset();
    scatter_unknowns(gx);
    const double plain = nonlinear_residual();
    if (plain <= residual) return plain;
    scatter_unknowns(mixed);  // both rose: keep the smaller (the mixed one)
    residual = nonlinear_residual();
  }
  // The non-linear residual (computed last) may have kept rotations for the next refresh;
  // the quasi-linear residual only reads m_rows.
  quasi_linear = quasi_linear_residual();
  return residual;
}

// The finest level's r at the rows' variables (after a residual evaluation).
template <int Dim>
Eigen::VectorXd CorotatedMultigrid<Dim>::residual_vector() const {
  const CorotatedRows& rows = m_rows[0];
  const auto& level = m_multigrid.level(0);
  Eigen::VectorXd r(static_cast<Eigen::Index>(rows.rows()));
  for (std::size_t m = 0; m < rows.rows(); ++m)
    r[static_cast<Eigen::Index>(m)] = level.split()(level.r, rows.target[m]);
  return r;
}

// The rotations of x into m_scratch_rotations (no longer those of an earlier x).
template <int Dim>
double CorotatedMultigrid<Dim>::matrix_free_nonlinear_residual() {
  auto& finest = m_multigrid.level(0);
  cell_rotations(finest, m_scratch_rotations);
  m_fresh_rotations = false;
  return corotated_residual(finest, m_scratch_rotations, m_sigma, false, m_options.stress,
                            &m_residual_scratch);
}

// z = B v, B = one frozen V-cycle: the cycle from x after shifting b so that the frozen
// residual at x is v (v == nullptr: v = r0, the plain cycle). The cycle is affine and leaves a
// zero-residual x unchanged, so the change of x is B v. Restores x and b.
template <int Dim>
Eigen::VectorXd CorotatedMultigrid<Dim>::frozen_cycle_direction(const Eigen::VectorXd& x,
                                                                const Eigen::VectorXd& r0,
                                                                const Eigen::VectorXd* v) {
  auto& level = m_multigrid.level(0);
  const CorotatedRows& rows = m_rows[0];
  // The loads are saved in storage kept between calls (a fresh vector of the finest unknowns is
  // paged in anew on every call).
  std::vector<double>& saved = m_saved_loads;
  if (v) {
    saved.resize(rows.rows());
    for (std::size_t m = 0; m < rows.rows(); ++m) {
      double& b = level.split()(level.b, rows.target[m]);
      saved[m] = b;
      b += (*v)[static_cast<Eigen::Index>(m)] - r0[static_cast<Eigen::Index>(m)];
    }
  }
  correct(0);
  Eigen::VectorXd z = gather_unknowns() - x;
  if (v)
    for (std::size_t m = 0; m < rows.rows(); ++m) level.split()(level.b, rows.target[m]) = saved[m];
  scatter_unknowns(x);
  return z;
}

// Whether the finest rotations are the identity (those of u = 0, as built).
template <int Dim>
bool CorotatedMultigrid<Dim>::rest_rotations() const {
  return std::all_of(m_rotations[0].begin(), m_rotations[0].end(), [](const Matrix<Dim>& r) {
    return (r - Matrix<Dim>::Identity()).cwiseAbs().maxCoeff() <= 1e-12;
  });
}

// One Newton step at the refreshed rotations (corotated_newton_krylov.hpp); pushes the
// non-linear residual after each direction (one frozen V-cycle each) and returns how many were
// used (fewer when `target` is reached first).
template <int Dim>
int CorotatedMultigrid<Dim>::newton_krylov_step(int directions, double target,
                                                CorotatedReport& report) {
  // The rotations only precondition (the Jacobian products use the true residual), so they
  // are refreshed every k cycles as in the Picard iteration.
  refresh_rotations_when_due();
  // The traction variables of x from the current rotations, as at every evaluation below (the
  // finite differences must not see a change of the rotations).
  const Eigen::VectorXd x = gather_unknowns();
  scatter_unknowns(x);
  quasi_linear_residual();
  const Eigen::VectorXd frozen = residual_vector();
  matrix_free_nonlinear_residual();
  MinimalResidualCombination combination(residual_vector());
  const Eigen::VectorXd r0 = combination.residual();
  // w = J z by a forward difference, ~sqrt(machine epsilon) of the unknowns' size (at least the
  // cell); the first cycle direction's image is its chord (corotated_newton_krylov.hpp). The
  // evaluation point lives in storage kept between steps (each fresh vector of the finest
  // unknowns is paged in anew).
  const double scale = 1e-7 * std::max(x.lpNorm<Eigen::Infinity>(), m_multigrid.level(0).lattice.h);
  auto add_direction = [&](Eigen::VectorXd z, bool chord) {
    const double largest = z.lpNorm<Eigen::Infinity>();
    if (!(largest > 0 && std::isfinite(largest))) {
      combination.add(std::move(z), Eigen::VectorXd());
      return;
    }
    const double eps = chord ? 1.0 : scale / largest;
    m_trial_unknowns = x + eps * z;
    scatter_unknowns(m_trial_unknowns);
    matrix_free_nonlinear_residual();
    Eigen::VectorXd image = residual_vector();
    image = (r0 - image) / eps;
    combination.add(std::move(z), std::move(image));
  };
  for (const Eigen::VectorXd& z : m_recycled) add_direction(z, false);
  for (int j = 0; j < directions; ++j) {
    throw_if_cancelled();
    // The first cycle on the rest rotations moves toward the frozen (linear) system's solution.
    Eigen::VectorXd v = combination.residual();
    if (j == 0 && m_cycles_since_refresh == 0 && rest_rotations()) v += frozen - r0;
    add_direction(frozen_cycle_direction(x, frozen, &v), j == 0);
    const Eigen::VectorXd correction = combination.correction();
    m_trial_unknowns = x + correction;
    scatter_unknowns(m_trial_unknowns);
    const bool last = j + 1 == directions;
    ++m_cycles_since_refresh;
    // After the last direction the residual keeps its rows when the next step refreshes.
    report.nonlinear.push_back(last ? nonlinear_residual() : matrix_free_nonlinear_residual());
    report.quasi_linear.push_back(combination.residual().norm());
    if (last && m_options.recycled_directions > 0 && correction.allFinite()) {
      m_recycled.push_back(correction);
      if (static_cast<int>(m_recycled.size()) > m_options.recycled_directions)
        m_recycled.pop_front();
    }
    if (!std::isfinite(report.nonlinear.back()) || report.nonlinear.back() <= target) return j + 1;
  }
  return directions;
}

template <int Dim>
CorotatedReport CorotatedMultigrid<Dim>::solve(double relative_tolerance, int max_cycles,
                                               bool accelerate, CorotatedOuter outer,
                                               int newton_directions) {
  CorotatedReport report;
  Timer timer;
  report.nonlinear.push_back(nonlinear_residual());
  report.quasi_linear.push_back(quasi_linear_residual());
  const double initial = report.nonlinear.front();
  if (!std::isfinite(initial))
    throw Error("the initial co-rotated residual is not finite (NaN or Inf in loads or values)");
  AndersonMixing anderson(m_options.acceleration_depth);
  for (int cycle = 0; cycle < max_cycles; ++cycle) {
    throw_if_cancelled();
    if (initial == 0.0) {
      report.converged = true;
      break;
    }
    if (outer == CorotatedOuter::NEWTON_KRYLOV) {
      const int directions = std::min(newton_directions, max_cycles - cycle);
      cycle += newton_krylov_step(directions, relative_tolerance * initial, report) - 1;
    } else if (accelerate && m_options.acceleration_depth > 0) {
      double quasi_linear = 0;
      report.nonlinear.push_back(
          accelerated_cycle(anderson, report.nonlinear.back(), quasi_linear));
      report.quasi_linear.push_back(quasi_linear);
    } else {
      report.quasi_linear.push_back(solve_cycle());
      report.nonlinear.push_back(nonlinear_residual());
    }
    if (!std::isfinite(report.nonlinear.back()) || !std::isfinite(report.quasi_linear.back()))
      throw Error("co-rotated multigrid diverged: residual not finite after cycle " +
                  std::to_string(cycle + 1));
    // A cold start may overshoot (the first refresh of a bent bar: 15x), never by this much;
    // stopping here keeps the iterate finite instead of growing to Inf over many steps.
    if (report.nonlinear.back() > kDivergenceGrowth * initial)
      throw Error("co-rotated multigrid diverged: non-linear residual grew from " +
                  scientific(initial) + " to " + scientific(report.nonlinear.back()) +
                  " by cycle " + std::to_string(cycle + 1));
    if (report.nonlinear.back() <= relative_tolerance * initial) {
      report.converged = true;
      break;
    }
  }
  report.seconds = timer.seconds();
  return report;
}

template <int Dim>
CorotatedCarriedState<Dim> CorotatedMultigrid<Dim>::carried_state() const {
  CorotatedCarriedState<Dim> state;
  state.rotations.reserve(m_rotations[0].size() * Dim * Dim);
  for (const Matrix<Dim>& r : m_rotations[0])
    state.rotations.insert(state.rotations.end(), r.data(), r.data() + Dim * Dim);
  state.cycles_since_refresh = m_cycles_since_refresh;
  state.recycled.assign(m_recycled.begin(), m_recycled.end());
  return state;
}

template <int Dim>
void CorotatedMultigrid<Dim>::restore_carried_state(const CorotatedCarriedState<Dim>& state) {
  const std::size_t cells = m_rotations[0].size();
  const auto unknowns = static_cast<Eigen::Index>(gather_unknowns().size());
  if (state.rotations.size() != cells * Dim * Dim)
    throw Error("co-rotated state: " + std::to_string(state.rotations.size()) +
                " rotation entries for " + std::to_string(cells) + " cells of " +
                std::to_string(Dim) + " x " + std::to_string(Dim));
  if (state.cycles_since_refresh < 0)
    throw Error("co-rotated state: negative cycle count since the last rotation refresh");
  for (const Eigen::VectorXd& z : state.recycled)
    if (z.size() != unknowns)
      throw Error("co-rotated state: a recycled correction has " + std::to_string(z.size()) +
                  " entries, the hierarchy " + std::to_string(unknowns) + " unknowns");
  set_traction_scale(1.0);  // as saved between solves (a cancelled load step may have left less)
  for (std::size_t c = 0; c < cells; ++c)
    m_rotations[0][c] = Eigen::Map<const Matrix<Dim>>(state.rotations.data() + c * Dim * Dim);
  refresh_levels();
  m_cycles_since_refresh = state.cycles_since_refresh;
  m_recycled.assign(state.recycled.begin(), state.recycled.end());
  m_fresh_rotations = false;
  m_equilibrium = current_load();
}

template class CorotatedMultigrid<2>;
template class CorotatedMultigrid<3>;

}  // namespace mgelastic::grid
