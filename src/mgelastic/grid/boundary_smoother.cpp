#include "mgelastic/grid/boundary_smoother.hpp"

namespace mgelastic::grid {
namespace {

template <int Dim, typename Scalar>
Scalar row_dot(const Level<Dim, Scalar>& level, const SparseRows<Scalar>& rows, std::size_t m) {
  Scalar sum = 0;
  for (std::uint32_t e = rows.start[m]; e < rows.start[m + 1]; ++e)
    sum += rows.value[e] * level.x[rows.column_field[e]][rows.column_index[e]];
  return sum;
}

// Right-hand side minus the moved boundary stresses of row m.
template <int Dim, typename Scalar>
Scalar row_rhs(const Level<Dim, Scalar>& level, const SparseRows<Scalar>& rows, std::size_t m) {
  return level.b[rows.target_field[m]][rows.target_index[m]] - rows.constant[m];
}

template <int Dim, typename Scalar>
Scalar& row_variable(Level<Dim, Scalar>& level, const SparseRows<Scalar>& rows, std::size_t m) {
  return level.x[rows.target_field[m]][rows.target_index[m]];
}

template <int Dim, typename Scalar>
void move_band_variable(Level<Dim, Scalar>& level, std::uint32_t m, Scalar delta) {
  row_variable(level, level.band_u, m) += delta;
  for (int c = 0; c < 2; ++c) {
    const std::uint32_t cell = level.band_u_pressure[m][c];
    if (cell != UINT32_MAX) level.x[Dim][cell] -= level.band_u_pressure_factor[m][c] * delta;
  }
}

template <int Dim, typename Scalar>
void relax_band_row(Level<Dim, Scalar>& level, std::uint32_t m) {
  const auto& rows = level.band_u;
  const Scalar residual = row_rhs(level, rows, m) - row_dot(level, rows, m);
  move_band_variable(level, m, residual / level.band_u_schur_diagonal[m]);
}

// Solves the band faces of one eliminated cell together: delta = S_loc^-1 r.
template <int Dim, typename Scalar>
void relax_band_block(Level<Dim, Scalar>& level, std::size_t block) {
  constexpr int B = 2 * Dim;
  const auto& rows = level.band_u;
  const auto& members = level.band_blocks[block];
  std::array<Scalar, B> residual{};
  for (int a = 0; a < B && members[a] != UINT32_MAX; ++a) {
    const std::uint32_t m = members[a];
    residual[a] = row_rhs(level, rows, m) - row_dot(level, rows, m);
  }
  const Scalar* inverse = &level.band_block_inverse[block * B * B];
  for (int a = 0; a < B && members[a] != UINT32_MAX; ++a) {
    Scalar delta = 0;
    for (int b = 0; b < B; ++b) delta += inverse[a * B + b] * residual[b];
    move_band_variable(level, members[a], delta);
  }
}

}  // namespace

template <int Dim, typename Scalar>
void update_band_pressures(Level<Dim, Scalar>& level) {
  const auto& rows = level.band_p;
  const auto count = static_cast<std::ptrdiff_t>(rows.rows());
  // Each eliminated pressure depends on u only: independent updates.
#pragma omp parallel for schedule(static)
  for (std::ptrdiff_t m = 0; m < count; ++m)
    row_variable(level, rows, m) =
        level.band_p_inverse[m] * (row_rhs(level, rows, m) - row_dot(level, rows, m));
}

template <int Dim, typename Scalar>
void band_gauss_seidel(Level<Dim, Scalar>& level, int sweeps,
                       const std::vector<std::uint32_t>* subset) {
  update_band_pressures(level);
  for (int sweep = 0; sweep < sweeps; ++sweep) {
    if (subset) {
      for (std::uint32_t m : *subset) relax_band_row(level, m);
    } else {
      // Colored blocks: the blocks of one color touch disjoint variables.
      for (const auto& color : level.band_schedule) {
        const auto count = static_cast<std::ptrdiff_t>(color.size());
#pragma omp parallel for schedule(dynamic, 1)
        for (std::ptrdiff_t b = 0; b < count; ++b) {
          for (std::uint32_t e : color[b].cell_blocks) relax_band_block(level, e);
          for (std::uint32_t m : color[b].point_rows) relax_band_row(level, m);
        }
      }
    }
  }
}

template <int Dim, typename Scalar>
void back_substitute_traction(Level<Dim, Scalar>& level) {
  const Scalar h = static_cast<Scalar>(level.lattice.h);
  const Scalar mu = level.mu;
  for (const auto& rule : level.traction.normal) {
    // P_ii = 2 mu (u_upper - u_lower) / h - mu p = sigma.
    level.at(rule.face) =
        level.at(rule.partner) + rule.sign * h * (rule.sigma + mu * level.at(rule.cell)) / (2 * mu);
  }
  for (const auto& rule : level.traction.thin) {
    Scalar mean = 0;
    for (std::uint32_t nb : rule.neighbors) mean += level.at(nb);
    if (!rule.neighbors.empty()) mean /= static_cast<Scalar>(rule.neighbors.size());
    const Scalar half_jump = h * (rule.sigma + mu * level.at(rule.cell)) / (4 * mu);
    level.at(rule.lower) = mean - half_jump;
    level.at(rule.upper) = mean + half_jump;
  }
  for (const auto& rule : level.traction.shear) {
    if (rule.candidates.empty()) continue;
    Scalar sum = 0;
    for (const auto& c : rule.candidates)
      sum += level.at(c.partner) + c.sign * (level.at(c.plus) - level.at(c.minus)) + c.sigma_term;
    level.at(rule.face) = sum / static_cast<Scalar>(rule.candidates.size());
  }
}

#define MGELASTIC_INSTANTIATE(D, S)                                                            \
  template void update_band_pressures<D, S>(Level<D, S>&);                                     \
  template void band_gauss_seidel<D, S>(Level<D, S>&, int, const std::vector<std::uint32_t>*); \
  template void back_substitute_traction<D, S>(Level<D, S>&);
MGELASTIC_INSTANTIATE(2, float)
MGELASTIC_INSTANTIATE(2, double)
MGELASTIC_INSTANTIATE(3, float)
MGELASTIC_INSTANTIATE(3, double)
#undef MGELASTIC_INSTANTIATE

}  // namespace mgelastic::grid
