#pragma once
// One level of the grid hierarchy: the discretized augmented system (5) on a typed lattice,
// with the classification of variables and equations of Sec. 5.1 and the explicit boundary-band
// rows of Sec. 5.3.
//
// Fields (x = unknowns incl. Dirichlet and back-substituted traction values, b = right-hand
// side, r = residual scratch, empty from build_level until a caller asks for it:
// residual.hpp's ensure_residual_storage) are arrays of lattice.size() entries in the layout of
// lattice.hpp (on an embedded body with the pages far from every variable released:
// live_chunks.hpp); index 0..Dim-1 is u_i, index Dim is p. A "global variable index" is field *
// size + k.
//
// Memory (byte_breakdown(); docs/performance.md "Memory per unknown"). Per lattice point and
// field: x, b (2 Scalars; r a third where allocated); per cell its type and the variable codes
// (kind and relaxation of its Dim + 1 variables, 2 bytes: var_codes.hpp). Per band row: target
// (global index and (field, index)), start, constant, Schur diagonal, eliminated pressures. Per
// band entry: (field, index, value) (5 bytes of index + one Scalar). These CSR rows are the build's
// form: the compact patterns (band_kernel) hold the same rows at ~1/7 of the bytes, and Multigrid
// drops the CSR once blocks, runs and schedules are built from it (drop_band_csr). On top, for the
// sweeps: cell blocks with their inverses, runs and colored schedules. Band arrays are trimmed to
// their size after the build. The double-precision solution level of a mixed-precision solve keeps
// only what residuals, corrections and traction back-substitution read (Multigrid drops the rest).
#include <array>
#include <cstddef>
#include <cstdint>
#include <functional>
#include <span>
#include <string>
#include <unordered_map>
#include <utility>
#include <vector>

#include "mgelastic/grid/band_block_shapes.hpp"
#include "mgelastic/grid/band_kernel.hpp"
#include "mgelastic/grid/band_runs.hpp"
#include "mgelastic/grid/block_partition.hpp"
#include "mgelastic/grid/lattice.hpp"
#include "mgelastic/grid/live_chunks.hpp"
#include "mgelastic/grid/material.hpp"
#include "mgelastic/grid/var_codes.hpp"

namespace mgelastic::grid {

// Explicit rows in CSR form. Row value = sum value[e] * x[column_field[e]][column_index[e]];
// `constant` holds boundary stresses moved to the right-hand side (equation: row = b - constant).
// Entries are stored once, as (field, flat index): the sweeps read x[field][index] without
// dividing, and a global variable index (level.hpp) is field * size + index. Per entry 5 bytes
// of index + one Scalar; per row the target in both forms (rows are few next to entries).
template <typename Scalar>
struct SparseRows {
  std::vector<std::uint32_t> target;  // global index of the row's own (collocated) variable
  std::vector<std::uint32_t> start{0};
  std::vector<Scalar> value;
  std::vector<Scalar> constant;
  std::vector<std::uint8_t> target_field, column_field;
  std::vector<std::uint32_t> target_index, column_index;
  std::size_t rows() const { return target.size(); }
  std::size_t entries() const { return value.size(); }
};

// Each row's number by its target's global index, for lookups by variable.
template <typename Scalar>
std::unordered_map<std::uint32_t, std::uint32_t> rows_by_target(const SparseRows<Scalar>& rows) {
  std::unordered_map<std::uint32_t, std::uint32_t> row_of;
  for (std::uint32_t m = 0; m < rows.rows(); ++m) row_of[rows.target[m]] = m;
  return row_of;
}

// Back-substitution of traction variables (Sec. 5.3, last paragraph). First the faces between an
// interior and an exterior cell from the normal stress condition P_ii = sigma, then faces half a
// cell outside from the shear conditions P_ij = sigma (averaged over the available edges).
template <typename Scalar>
struct NormalTractionRule {
  std::uint32_t face, partner, cell;  // global indices: traction face, other face of cell, p
  Scalar sign;                        // +1: face is the cell's upper face
  Scalar sigma;
};
template <typename Scalar>
struct ThinTractionRule {  // both faces of a one-cell-thin interior cell are traction faces
  std::uint32_t lower, upper, cell;
  std::vector<std::uint32_t> neighbors;  // known u_i values that set the mean displacement
  Scalar sigma;
};
template <typename Scalar>
struct ShearTractionCandidate {
  std::uint32_t partner, plus, minus;  // u_i[face] = u_i[partner] + sign (u_j[plus] - u_j[minus])
  Scalar sign;                         //              + sigma_term
  Scalar sigma_term;
};
template <typename Scalar>
struct ShearTractionRule {  // u_i[face] = the mean of its candidates' values
  std::uint32_t face;
  std::uint32_t first, count;  // its candidates in TractionRules::shear_candidates
};
template <typename Scalar>
struct TractionRules {
  std::vector<NormalTractionRule<Scalar>> normal;
  std::vector<ThinTractionRule<Scalar>> thin;
  // Rules with at least one candidate; the candidates of all in one array (a vector per rule
  // cost 32 bytes of header and allocation per rule, ~40 % of the rules' memory on the box).
  std::vector<ShearTractionRule<Scalar>> shear;
  std::vector<ShearTractionCandidate<Scalar>> shear_candidates;
  std::span<const ShearTractionCandidate<Scalar>> candidates(
      const ShearTractionRule<Scalar>& rule) const {
    return {shear_candidates.data() + rule.first, rule.count};
  }
  std::span<ShearTractionCandidate<Scalar>> candidates(const ShearTractionRule<Scalar>& rule) {
    return {shear_candidates.data() + rule.first, rule.count};
  }
};

// Per field, address stretches [begin, end) of a level's own arrays: valid while those arrays
// are not reallocated, so a copied level (new arrays) starts without any; a move keeps them.
template <std::size_t Fields>
class FieldStretches {
 public:
  using Stretches = std::vector<std::pair<std::uintptr_t, std::uintptr_t>>;
  FieldStretches() = default;
  FieldStretches(const FieldStretches&) {}
  FieldStretches(FieldStretches&&) noexcept = default;
  FieldStretches& operator=(const FieldStretches&) {
    clear();
    return *this;
  }
  FieldStretches& operator=(FieldStretches&&) noexcept = default;
  Stretches& operator[](std::size_t field) { return m_fields[field]; }
  const Stretches& operator[](std::size_t field) const { return m_fields[field]; }
  void clear() {
    for (Stretches& stretches : m_fields) stretches.clear();
  }

 private:
  std::array<Stretches, Fields> m_fields;
};

// One named group of a level's arrays and the bytes it holds (Level::byte_breakdown).
struct ByteShare {
  std::string name;
  std::size_t bytes = 0;
};

// Boundary stress values for the eliminated stresses (see problem.hpp); empty = zero traction.
template <int Dim>
using BoundaryStress = std::function<double(int i, int j, const Vec<Dim>&)>;

// A global variable index field * n + k (Level::global) split into field and k by comparisons:
// the co-rotated rows address every entry by its global index, and Dim comparisons cost less
// than a division by the runtime n per entry.
template <int Dim>
struct GlobalSplit {
  std::size_t n;
  int field(std::uint32_t global_index) const {
    int f = 0;
    for (int d = 1; d <= Dim; ++d) f += global_index >= d * n;
    return f;
  }
  std::size_t index(std::uint32_t global_index, int f) const { return global_index - f * n; }
  // fields[field][k]: the level's x, b or r, or raw pointers to them.
  template <typename Fields>
  auto& operator()(Fields& fields, std::uint32_t global_index) const {
    const int f = field(global_index);
    return fields[f][index(global_index, f)];
  }
};

template <int Dim, typename Scalar>
struct Level {
  Lattice<Dim> lattice;
  std::vector<CellType> cells;
  Scalar mu = 1, lambda = 0;
  Scalar inertia = 0;  // c of a backward-Euler step: momentum rows read L u - c u (Sec. 8)
  // Fill weights of the cells (fill_weights.hpp); empty = every body cell full (weight 1).
  // Rows that touch a partly filled cell are band rows (explicit, weighted).
  std::vector<double> cell_weight;
  // Coarse levels: depth inside the Dirichlet region where the finest level's tangential
  // Dirichlet variables sit (h_finest / 2); 0 on the finest level (explicit_rows.hpp).
  double dirichlet_zero_depth = 0.0;
  // Per cell and face (2 Dim k + 2 a + side): where a Dirichlet cell's face meets the finest
  // level's Dirichlet wall, 1 + the finest layers between them (finest_dirichlet_wall_layers,
  // coarsening.hpp), else 0; only these faces clamp at the finest depth.
  std::vector<std::uint8_t> dirichlet_wall_layers;
  std::array<FieldArray<Scalar>, Dim + 1> x, b, r;
  // The stretches of x, b and r that hold or border a variable (live_chunks.hpp); outside them
  // the fields are zero with their pages released, and the passes over whole arrays skip them.
  LiveChunks live;
  // Per field, the stretches [begin, end) of b's pages that record_zero_loads handed back
  // because they held only zeros (beyond the dead chunks'); cleared once a writer may have
  // filled them again, so the memory accounting counts them then.
  FieldStretches<Dim + 1> zero_load_pages;
  // Per field: b held only zeros when the loads were recorded (record_zero_loads; gravity along
  // y leaves b of u_x, u_z and p zero), so the residual reads no b there. Forgotten with
  // zero_load_pages (forget_zero_loads) once a writer may fill b again.
  std::array<bool, Dim + 1> zero_load{};
  void forget_zero_loads() {
    zero_load_pages.clear();
    zero_load = {};
  }
  std::size_t zero_load_bytes(int field) const;
  // Each variable's kind and relaxation, two bits each in one code per cell (var_codes.hpp);
  // the double solution level of a mixed-precision solve shares them with the float finest.
  VarCodes codes;
  VarKind kind(int field, std::ptrdiff_t k) const { return codes.kind(field, k); }
  Relaxation relaxation(int field, std::ptrdiff_t k) const { return codes.relaxation(field, k); }

  // Boundary band (Sec. 5.3): momentum rows relaxed by Gauss-Seidel on the Schur complement
  // L_phi - G D_p^-1 G^T, and the pressure rows eliminated there (updated exactly).
  SparseRows<Scalar> band_u;
  std::vector<Scalar> band_u_schur_diagonal;
  // Keeping eliminated pressures exact while u moves: p_c -= factor * delta for the (up to two)
  // band pressures of the row (factor = D_c^-1 G_fc; cell index c, UINT32_MAX when absent).
  std::vector<std::array<std::uint32_t, 2>> band_u_pressure;
  std::vector<std::array<Scalar, 2>> band_u_pressure_factor;
  SparseRows<Scalar> band_p;           // u terms only; the p diagonal is D = mu^2/lambda + extra
  std::vector<Scalar> band_p_extra;    // mu/2 per eliminated boundary gradient F_ii
  std::vector<Scalar> band_p_inverse;  // 1 / D (0 when lambda = 0, where p vanishes)
  // Band momentum rows that get the extra sweeps of Sec. 6 (Fig. 8): before restriction (their
  // residual would land on coarse non-equations) and after prolongation (they read corrections
  // from coarse boundary variables). Indices into band_u.
  std::vector<std::uint32_t> pre_restriction_rows, post_prolongation_rows;
  TractionRules<Scalar> traction;
  // Block relaxation of the band (Sec. 5.3, Gauss-Seidel on the Schur complement in blocks):
  // the band faces of each eliminated cell are solved together, with the inverse of their
  // Schur block S_loc stored (row-major, block_size^2 entries per cell); band rows outside
  // every block are relaxed point-wise.
  static constexpr int block_size = 2 * Dim;
  std::vector<std::array<std::uint32_t, 2 * Dim>> band_blocks;  // band_u rows, UINT32_MAX = none
  // The distinct inverses (block_size^2 each; blocks of one shape, most on flat faces, share
  // one, so they stay in cache during the sweeps) and each block's inverse id.
  std::vector<Scalar> band_block_inverse;
  std::vector<std::uint32_t> band_block_inverse_id;
  const Scalar* block_inverse(std::size_t block) const {
    return band_block_inverse.data() +
           static_cast<std::size_t>(band_block_inverse_id[block]) * block_size * block_size;
  }
  std::vector<std::uint32_t> band_point_rows;
  // The blocks' dense form for the step-by-step sweeps (band_block_shapes.hpp); empty where the
  // blocks seldom repeat. Rebuilt with the blocks.
  BandBlockShapes<Scalar> band_block_shapes;
  // band_u, its Schur diagonal and pressure factors in the compact form the sweeps read
  // (band_kernel.hpp); rebuild with build_band_kernel after changing any of them.
  BandKernel<Scalar> band_kernel;
  // band_p in the same compact form (its rows' own variable is the cell's pressure): what
  // update_band_pressures reads (band_kernel.hpp: build_band_pressure_kernel).
  BandKernel<Scalar> band_p_kernel;

  // Multithreading (Sec. 9.4): colored blocks of the volume for the distributive sweeps, and
  // the band's work grouped by the same blocks (the separate partition of the boundary band),
  // per color: per block, its eliminated-cell blocks and point rows in sweep order.
  struct BandWork {
    std::vector<std::uint32_t> cell_blocks, point_rows;
  };
  BlockPartition<Dim> blocks;
  std::array<std::vector<BandWork>, (1 << Dim)> band_schedule;
  // A subset of band_u rows grouped the same way: per color, per block, rows in band_u order.
  using RowSchedule = std::array<std::vector<std::vector<std::uint32_t>>, (1 << Dim)>;
  // pre_restriction_rows and post_prolongation_rows as colored schedules, so that their extra
  // sweeps run in parallel too (Multigrid drops one whose set is the whole band: those sweeps
  // are then the smoothing's band sweeps).
  RowSchedule pre_restriction_schedule, post_prolongation_schedule;
  // band_schedule with runs of equally shaped steps along x relaxed together (band_runs.hpp);
  // rebuild with build_band_runs after the band rows change (invalid ones are not used).
  BandRuns<Dim, Scalar> band_runs;

  std::size_t size() const { return lattice.size(); }
  std::uint32_t global(int field, std::ptrdiff_t k) const {
    return static_cast<std::uint32_t>(field * static_cast<std::ptrdiff_t>(size()) + k);
  }
  GlobalSplit<Dim> split() const { return {size()}; }
  Scalar& at(std::uint32_t global_index) { return split()(x, global_index); }
  Scalar at(std::uint32_t global_index) const { return split()(x, global_index); }
  std::size_t interior_unknowns() const;  // interior u and p variables
  // Whether band_u's displacement terms are Galerkin rows (galerkin_band_rows.hpp) instead of
  // RowBuilder's: the coarsest solve then assembles them from band_u.
  bool galerkin_band_rows = false;
  // Memory held by the level's arrays, by group (capacity, as vector_bytes), and in total.
  std::vector<ByteShare> byte_breakdown() const;
  std::size_t bytes() const;
};

// What a level is built for: a level of the cycle (smoothed: band blocks, sweep schedules and
// runs) or the double solution level of mixed precision (residuals and loads only).
enum class LevelUse { CYCLE, RESIDUAL };

// Builds a level: classifies variables, picks distributive vs band relaxation, builds the band
// rows and traction rules. `coarse_cells` (may be null on the coarsest level) is the next coarser
// level's typing, which defines the Fig. 8 sets. Dirichlet values are not set here. `inertia`
// is the c of a dynamics step (the same on every level: the equations are force densities and
// the transfers average, so the coarse term is the consistently scaled one). `band_layers`
// extra cell layers join the band (MultigridOptions::band_layers). `cell_weight` (may be empty)
// holds the fill weights of a coarse level.
template <int Dim, typename Scalar>
Level<Dim, Scalar> build_level(const Lattice<Dim>& lattice, std::vector<CellType> cells,
                               const Material& material, const BoundaryStress<Dim>& sigma,
                               const std::vector<CellType>* coarse_cells, double inertia = 0.0,
                               int band_layers = 0, std::vector<double> cell_weight = {},
                               double dirichlet_zero_depth = 0.0,
                               std::vector<std::uint8_t> dirichlet_wall_layers = {},
                               bool release_dead_pages = true, LevelUse use = LevelUse::CYCLE);

// The double solution level of a mixed-precision solve (LevelUse::RESIDUAL) for the cycle's
// finest level: its lattice, typing and variable codes (shared, not recomputed: the codes depend
// on the typing alone, not on the loads), its own double band rows and traction rules with the
// boundary stress `sigma`.
template <int Dim, typename Scalar>
Level<Dim, double> build_solution_level(const Level<Dim, Scalar>& finest, const Material& material,
                                        const BoundaryStress<Dim>& sigma, double inertia,
                                        bool release_dead_pages = true);

// Rebuilds what the band sweeps derive from band_u, its Schur diagonal and pressure factors (the
// compact kernel, eliminated-cell blocks and their inverses, the colored schedule, the runs)
// after the rows changed, e.g. to Galerkin rows (galerkin_band_rows.hpp). Needs the CSR rows.
template <int Dim, typename Scalar>
void rebuild_band_sweep_data(Level<Dim, Scalar>& level);

// Writes prescribed displacements into every Dirichlet variable of the level.
template <int Dim, typename Scalar>
void set_dirichlet_values(Level<Dim, Scalar>& level,
                          const std::function<Vec<Dim>(const Vec<Dim>&)>& displacement);

// For a right-hand side that only its loads write (the level holding the solution: the double
// solution level of a mixed-precision solve, else the finest): records which fields of b hold
// only zeros (zero_load) and, with release_pages, hands back the pages of b that hold only zeros
// (release_zero_pages, live_chunks.hpp) and records them in zero_load_pages. Gravity along y
// leaves b of u_x, u_z and p zero, 3/4 of its bytes.
template <int Dim, typename Scalar>
void record_zero_loads(Level<Dim, Scalar>& level, bool release_pages);

}  // namespace mgelastic::grid
