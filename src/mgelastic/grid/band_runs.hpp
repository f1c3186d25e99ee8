#pragma once
// Run-wise relaxation of the boundary band (Sec. 5.3), same Gauss-Seidel order as the step-by-step
// sweep of boundary_smoother.cpp.
//
// A band sweep works block by block through a list of steps: the block solve of one eliminated
// cell (delta = S_loc^-1 r over its band faces, Level::band_blocks) or the point rows of one
// location (relaxed one after the other). On flat faces consecutive steps often have the same
// shape (member patterns, fields, offsets between member targets, S_loc^-1) and every member's
// target one cell further along x. Along such a run of L steps, step s sees the earlier steps only
// through fixed multiples of their deltas:
//   r_s = r0_s - sum_{j=1..J} C_j delta_{s-j},   delta_s = W r_s,
// with r0_s the residuals of step s from the values before the run, C_j[a][b] the change of
// member a's residual per unit delta of member b j steps earlier (through b's own variable and
// its eliminated pressures), and W = S_loc^-1 for a cell block or (D + L_0)^-1 (forward
// substitution over the location's rows, L_0 = couplings to earlier rows of the same step) for a
// point group. Hence delta_s = W r0_s - sum_j A_j delta_{s-j} with A_j = W C_j, formed once per
// shape. So a run is relaxed in three passes: all r0 and W r0 (contiguous along x, vectorized),
// the recurrence (two small dense products per step, with the member count a template argument
// so they stay in registers; the lag-2 product is off the step-to-step dependency chain), all
// moves (vectorized). The deltas equal those of the step-by-step sweep up to round-off. Shapes
// whose couplings reach further than kMaxLag steps cap their runs below that reach, so every
// coupling inside a run is one of C_1..C_J.
//
// Runs along y: where the band is only a few cells thick in x (faces across x), a block's steps
// off the x-runs, taken with y fastest, form runs one lattice row apart (stride n_x; passes 1
// and 3 strided). A block's order: its x-runs, its y-runs, then its other steps in their original
// order. build_band_runs writes that order back into Level::band_schedule, so the step-by-step
// sweep keeps the run-wise one's order.
//
// Layout: steps of one run have members a = 0..members-1; the band_u row of member a at step s is
// rows[first_row + s * members + a]; its target is target + offset[a] + s * stride in field
// field[a].
#include <array>
#include <cstddef>
#include <cstdint>
#include <vector>

namespace mgelastic::grid {

template <int Dim, typename Scalar>
struct Level;

template <typename Scalar>
struct BandKernel;

inline constexpr int kBandRunMaxLag = 2;      // couplings C_1..C_J kept per shape
inline constexpr int kBandRunMaxLength = 64;  // longest run (a block row is up to 128 cells)
inline constexpr int kBandRunMinLength = 4;   // shorter runs are relaxed step by step

template <int Dim, typename Scalar>
struct BandRunShape {
  static constexpr int G = 2 * Dim;  // members at most (a cell block's faces)
  int members = 0;
  int max_length = kBandRunMaxLength;      // below the smallest non-zero lag > kBandRunMaxLag
  std::array<std::uint32_t, G> pattern{};  // BandKernel pattern of each member
  std::array<std::uint8_t, G> field{};
  std::array<std::int32_t, G> offset{};  // member target - member 0's target
  std::array<Scalar, G * G> weight{};    // W, row-major, zero outside members x members
  // A_j = W C_j for j = 1..kBandRunMaxLag, row-major: delta_s = W r0_s - sum_j A_j delta_{s-j}.
  std::array<std::array<Scalar, G * G>, kBandRunMaxLag> lag_response{};
};

struct BandRun {
  std::uint32_t shape = 0, length = 0, first_row = 0;
  std::ptrdiff_t target = 0;  // flat index of member 0's variable at step 0
  std::ptrdiff_t stride = 1;  // flat distance between consecutive steps (1: along x)
};

// Work items of one block in sweep order: a run, one cell block (Level::band_blocks index) or
// one point row (band_u index), tagged in the top two bits.
enum class BandItem : std::uint32_t { RUN = 0u << 30, CELL_BLOCK = 1u << 30, POINT_ROW = 2u << 30 };
inline constexpr std::uint32_t kBandItemIndexMask = (1u << 30) - 1;

template <int Dim, typename Scalar>
struct BandRuns {
  std::vector<BandRunShape<Dim, Scalar>> shapes;
  std::vector<BandRun> runs;
  std::vector<std::uint32_t> rows;
  // Per color, the blocks of Level::band_schedule that have band work, largest first (the
  // sweeps hand a color's blocks to the threads in this order, so the color ends on small ones):
  // each block's items. (The Fig. 8 relocation sweeps keep their row-by-row path: as runs of
  // point groups they were 5-20 % slower.)
  using Schedule = std::array<std::vector<std::vector<std::uint32_t>>, (1 << Dim)>;
  Schedule schedule;
  std::size_t band_rows = 0;  // band_u rows when built (stale when band_u changed)
  // Coverage of `schedule` (one sweep): steps and row relaxations, all and inside runs.
  std::size_t steps = 0, steps_in_runs = 0, row_relaxations = 0, row_relaxations_in_runs = 0;

  bool valid_for(std::size_t band_u_rows) const { return band_rows == band_u_rows && band_rows; }
  std::size_t bytes() const;
};

// Detects the runs of Level::band_schedule (needs band_blocks, band_block_inverse, band_kernel
// and band_schedule) and puts each block's steps of band_schedule in run order (above).
template <int Dim, typename Scalar>
void build_band_runs(Level<Dim, Scalar>& level);

// Row relaxations of one block's items in one sweep (a run: its steps times its members); the
// schedule holds only blocks with work, largest first in each color (see build_band_runs).
template <int Dim, typename Scalar>
std::size_t band_block_work(const Level<Dim, Scalar>& level, const BandRuns<Dim, Scalar>& runs,
                            const std::vector<std::uint32_t>& items);

// Relaxes one run. x: the level's Dim + 1 field arrays; rhs: BandKernel::rhs (b - constant).
template <int Dim, typename Scalar>
void relax_band_run(const std::array<Scalar*, Dim + 1>& x, const BandKernel<Scalar>& kernel,
                    const BandRunShape<Dim, Scalar>& shape, const BandRun& run,
                    const std::uint32_t* rows);

}  // namespace mgelastic::grid
