#pragma once
// Boundary-band Gauss-Seidel for the quasi-linear co-rotated system (Zhu et al. 2010, Sec. 7,
// last paragraph, and Sec. 5.3): the R != I generalization of boundary_smoother.hpp.
//
// The co-rotated rows (corotated_operator.hpp) are already in divergence form with the boundary
// stresses eliminated and R_ij p averaged over the four cells of each edge (edge-averaged
// pressures). Split the band into its momentum rows u (targets the linear level relaxes in its
// band, Relaxation != DISTRIBUTIVE) and its eliminated pressures p_c (the linear level's
// eliminated cells; their rows read mu R_ij G_ij + D_c p_c = b_c with D_c diagonal):
//   [A  G ] [u]   [b_u]      Schur complement on u:  S = A - G D^-1 G',
//   [G' D ] [p] = [b_p]      S_ff = A_ff - sum_c G_fc G'_cf / D_c.
// Gauss-Seidel on S with the eliminated pressures kept exact (p_c = D_c^-1 (b_c - G'_c u), and
// p_c -= G'_cf / D_c * delta when u_f moves), so the Schur residual of a row equals its
// augmented residual. Every other variable (distributive rows' u and p, Dirichlet values) is
// held fixed. As in the linear engine, the band faces of each eliminated cell are relaxed
// together with the stored inverse of their Schur block (2d x 2d, all S entries of the block,
// so the wider pressure coupling of R != I is included), the remaining band rows point-wise.
// At R = I the rows, pivots and blocks are the linear ones: one pass equals band_gauss_seidel.
//
// Order and threads: the linear level's band schedule (its band_u rows mapped to co-rotated
// rows), colour by colour, the blocks of one colour in parallel. A relaxation writes u_f and
// pressures of cells within one cell of f and reads within two cells; blocks of one colour are
// at least 8 cells apart, so results do not depend on the thread count. Band rows the linear
// schedule lacks (none on the levels built so far) are relaxed afterwards, serially.
//
// Data: per co-rotated row, 1 / S_ff and a CSR list of (pressure variable, G'_cf / D_c); per
// cell block, its rows and S_loc^-1 (row-major, (2d)^2); per eliminated pressure its row and
// 1 / D_c. Double precision only.
#include <array>
#include <cstdint>
#include <vector>

#include "mgelastic/grid/corotated_operator.hpp"
#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

template <int Dim>
class CorotatedBandSmoother {
 public:
  // `rows`: the level's frozen co-rotated rows; the smoother keeps no reference to them.
  CorotatedBandSmoother(const Level<Dim, double>& level, const CorotatedRows& rows);

  // An exact update of the eliminated pressures, then `sweeps` forward Gauss-Seidel sweeps over
  // the band momentum rows.
  void sweep(Level<Dim, double>& level, const CorotatedRows& rows, int sweeps) const;

  // p_c = D_c^-1 (b_c - constant - G'_c u) for every eliminated pressure.
  void update_pressures(Level<Dim, double>& level, const CorotatedRows& rows) const;

  std::size_t band_rows() const { return m_band_rows; }
  std::size_t eliminated_pressures() const { return m_pressure_rows.size(); }
  std::size_t cell_blocks() const { return m_blocks.size(); }

 private:
  static constexpr int B = 2 * Dim;
  struct Work {
    std::vector<std::uint32_t> cell_blocks, point_rows;
  };
  struct Sweep;

  void build_pressures(const Level<Dim, double>& level, const CorotatedRows& rows);
  void build_factors(const Level<Dim, double>& level, const CorotatedRows& rows);
  void build_schedule(const Level<Dim, double>& level, const CorotatedRows& rows);
  template <typename DenseRow>
  double schur_entry(const DenseRow& row_a, const CorotatedRows& rows, std::uint32_t b) const;

  std::vector<std::uint32_t> m_pressure_rows;
  std::vector<double> m_pressure_inverse;
  std::vector<std::uint8_t> m_in_band;           // per row: band momentum row
  std::vector<std::int32_t> m_pressure_slot;     // per row: index into m_pressure_rows or -1
  std::vector<std::uint32_t> m_factor_start{0};  // per row
  std::vector<std::uint32_t> m_factor_variable;
  std::vector<double> m_factor;
  std::vector<double> m_inverse_pivot;  // per row: 1 / S_ff (0 outside the band)
  std::vector<std::array<std::uint32_t, B>> m_blocks;
  std::vector<double> m_block_inverse;
  std::array<std::vector<Work>, (1 << Dim)> m_schedule;
  std::vector<std::uint32_t> m_unscheduled;
  std::size_t m_band_rows = 0;
};

}  // namespace mgelastic::grid
