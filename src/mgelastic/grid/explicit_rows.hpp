#pragma once
// Explicit rows of the eliminated system L* of Sec. 5.3, built from the divergence form (11):
//   momentum row of u_i at face k:  sum_j [P_ij(k + e_j/2) - P_ij(k - e_j/2)] / h
//   pressure row at cell k:         mu sum_i F_ii + (mu^2/lambda) p
// Interior stresses (stencils of only interior or Dirichlet variables) are expanded with the
// finite differences (9)-(10); a boundary stress (one incident cell exterior) is replaced by its
// traction value, moved to `constant`. A boundary gradient F_ii in a pressure row is eliminated
// with P_ii = 2 mu F_ii - mu p = sigma, i.e. mu F_ii -> (sigma + mu p) / 2, which adds mu/2 to
// the pressure diagonal (`pressure_extra`) and sigma/2 to `constant`.
// Variables are global indices (field * lattice.size() + k); Dirichlet variables stay as terms,
// except on coarse levels (dirichlet_zero_depth > 0, homogeneous corrections): there a
// tangential Dirichlet neighbor across a Dirichlet wall sits H/2 inside the Dirichlet region,
// where the finest level's sits h/2 inside; it is replaced by the linear extrapolation of the
// row's own variable to zero at the finest level's depth d (only across faces of
// `dirichlet_wall_layers` that meet the finest wall; d = h/2 + the finest layers m between the
// coarse wall and the finest one times h, the mean of the variable's two cells, as a clamp top
// between coarse faces lies inside the coarse Dirichlet cells): u_ghost = -(H/2 - d)/(H/2 + d)
// u_self, so every level clamps the tangential correction at the same place. The inertia term of
// a dynamics step (Sec. 8), -c u_i, is part of every momentum row. Optional fill weights w
// (fill_weights.hpp) scale the stresses of coarse cells: P_ii(cell) by w(cell), P_ij(edge) by the
// mean w of its four cells, and the inertia of a face by the mean w of its two cells. Pressure rows
// stay unweighted, so a momentum row's pressure coefficient is w times the pressure row's u
// coefficient (the Schur complement G W D^-1 G^T stays symmetric).
#include <cstdint>
#include <optional>
#include <vector>

#include "mgelastic/grid/level.hpp"

namespace mgelastic::grid {

struct RowTerm {
  std::uint32_t variable;
  double coefficient;
};

struct ExplicitRow {
  std::vector<RowTerm> terms;  // sorted by variable, duplicates merged
  double constant = 0.0;
  double pressure_extra = 0.0;  // pressure rows only
};

// Row m of a level's CSR rows (e.g. band_u) as an explicit row: its stored terms and constant.
template <int Dim, typename Scalar>
ExplicitRow stored_row(const Level<Dim, Scalar>& level, const SparseRows<Scalar>& rows,
                       std::uint32_t m) {
  ExplicitRow row;
  row.constant = static_cast<double>(rows.constant[m]);
  for (std::uint32_t e = rows.start[m]; e < rows.start[m + 1]; ++e)
    row.terms.push_back({level.global(rows.column_field[e], rows.column_index[e]),
                         static_cast<double>(rows.value[e])});
  return row;
}

template <int Dim>
class RowBuilder {
 public:
  RowBuilder(const Lattice<Dim>& lattice, const std::vector<CellType>& cells, double mu,
             BoundaryStress<Dim> sigma, double inertia = 0.0,
             const std::vector<double>* cell_weight = nullptr, double dirichlet_zero_depth = 0.0,
             const std::vector<std::uint8_t>* dirichlet_wall_layers = nullptr);
  ExplicitRow momentum(int axis, std::ptrdiff_t k) const;
  ExplicitRow pressure(std::ptrdiff_t k) const;

 private:
  bool exterior(std::ptrdiff_t cell) const { return m_cells[cell] == CellType::EXTERIOR; }
  double sigma(int i, int j, const Vec<Dim>& x) const { return m_sigma ? m_sigma(i, j, x) : 0.0; }
  double weight(std::ptrdiff_t cell) const { return m_cell_weight ? (*m_cell_weight)[cell] : 1.0; }
  std::optional<Vec<Dim>> traction_face(int i, std::ptrdiff_t cell) const;
  std::uint32_t u(int axis, std::ptrdiff_t k) const;
  std::uint32_t p(std::ptrdiff_t k) const;
  void add_normal_stress(int i, std::ptrdiff_t cell, double weight, ExplicitRow& row) const;
  void add_shear_stress(int i, int j, std::ptrdiff_t edge, double weight, ExplicitRow& row) const;
  void fold_tangential_dirichlet(int axis, std::ptrdiff_t k, ExplicitRow& row) const;

  const Lattice<Dim>& m_lattice;
  const std::vector<CellType>& m_cells;
  double m_mu;
  BoundaryStress<Dim> m_sigma;
  double m_inertia;
  const std::vector<double>* m_cell_weight;
  double m_dirichlet_zero_depth;
  const std::vector<std::uint8_t>* m_dirichlet_wall_layers;
};

}  // namespace mgelastic::grid
