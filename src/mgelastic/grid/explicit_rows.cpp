#include "mgelastic/grid/explicit_rows.hpp"

#include <algorithm>

namespace mgelastic::grid {
namespace {

void merge_duplicates(ExplicitRow& row) {
  std::sort(row.terms.begin(), row.terms.end(),
            [](const RowTerm& a, const RowTerm& b) { return a.variable < b.variable; });
  std::vector<RowTerm> merged;
  for (const RowTerm& term : row.terms) {
    if (!merged.empty() && merged.back().variable == term.variable) {
      merged.back().coefficient += term.coefficient;
    } else {
      merged.push_back(term);
    }
  }
  std::erase_if(merged, [](const RowTerm& t) { return t.coefficient == 0.0; });
  row.terms = std::move(merged);
}

}  // namespace

template <int Dim>
RowBuilder<Dim>::RowBuilder(const Lattice<Dim>& lattice, const std::vector<CellType>& cells,
                            double mu, BoundaryStress<Dim> sigma, double inertia,
                            const std::vector<double>* cell_weight, double dirichlet_zero_depth,
                            const std::vector<std::uint8_t>* dirichlet_wall_layers)
    : m_lattice(lattice),
      m_cells(cells),
      m_mu(mu),
      m_sigma(std::move(sigma)),
      m_inertia(inertia),
      m_cell_weight(cell_weight),
      m_dirichlet_zero_depth(dirichlet_zero_depth),
      m_dirichlet_wall_layers(dirichlet_wall_layers) {}

template <int Dim>
void RowBuilder<Dim>::fold_tangential_dirichlet(int axis, std::ptrdiff_t k,
                                                ExplicitRow& row) const {
  const double half = 0.5 * m_lattice.h;
  if (m_dirichlet_zero_depth <= 0.0 || m_dirichlet_zero_depth >= half) return;
  if (!m_dirichlet_wall_layers || m_dirichlet_wall_layers->empty()) return;
  const auto& walls = *m_dirichlet_wall_layers;
  const std::ptrdiff_t si = m_lattice.stride(axis);
  // Finest cells between the cell's face toward the row (2 j + side) and the finest wall behind
  // it, or -1 where that face does not meet the finest wall.
  auto wall_layers = [&](std::ptrdiff_t cell, int j, int side) {
    if (m_cells[cell] != CellType::DIRICHLET) return -1;
    return static_cast<int>(walls[cell * 2 * Dim + 2 * j + side]) - 1;
  };
  double self = 0.0;
  for (int j = 0; j < Dim; ++j) {
    if (j == axis) continue;
    for (const int side : {0, 1}) {
      // side 0: the neighbor above the row along e_j, seen through its lower face.
      const std::ptrdiff_t nb = side == 0 ? k + m_lattice.stride(j) : k - m_lattice.stride(j);
      const int upper = wall_layers(nb, j, side), lower = wall_layers(nb - si, j, side);
      if (upper < 0 || lower < 0) continue;
      // The variable sits on the face between the two cells: their mean wall depth.
      const double depth = m_dirichlet_zero_depth * (1 + upper + lower);
      const double ratio = (half - depth) / (half + depth);
      for (RowTerm& t : row.terms) {
        if (t.variable != u(axis, nb)) continue;
        self -= ratio * t.coefficient;
        t.coefficient = 0.0;
      }
    }
  }
  if (self != 0.0) row.terms.push_back({u(axis, k), self});
}

template <int Dim>
std::uint32_t RowBuilder<Dim>::u(int axis, std::ptrdiff_t k) const {
  return static_cast<std::uint32_t>(axis * static_cast<std::ptrdiff_t>(m_lattice.size()) + k);
}

template <int Dim>
std::uint32_t RowBuilder<Dim>::p(std::ptrdiff_t k) const {
  return u(Dim, k);
}

// Where the traction condition fixing P_ii (and F_ii) of `cell` holds: the center of its face
// toward an exterior neighbor along e_i (the cell center for a one-cell-thin feature), or none.
template <int Dim>
std::optional<Vec<Dim>> RowBuilder<Dim>::traction_face(int i, std::ptrdiff_t cell) const {
  const std::ptrdiff_t si = m_lattice.stride(i);
  const bool lower_exterior = exterior(cell - si);
  const bool upper_exterior = exterior(cell + si);
  if (lower_exterior && upper_exterior) return m_lattice.cell_center(cell);
  if (lower_exterior) return m_lattice.face_center(i, cell);
  if (upper_exterior) return m_lattice.face_center(i, cell + si);
  return std::nullopt;
}

// weight * P_ii(cell), P_ii = 2 mu (u_i[cell + s_i] - u_i[cell]) / h - mu p[cell].
template <int Dim>
void RowBuilder<Dim>::add_normal_stress(int i, std::ptrdiff_t cell, double weight,
                                        ExplicitRow& row) const {
  const std::ptrdiff_t si = m_lattice.stride(i);
  if (const auto where = traction_face(i, cell)) {
    // Boundary stress: the traction condition on the exterior face fixes its value.
    row.constant += weight * sigma(i, i, *where);
    return;
  }
  const double h = m_lattice.h;
  weight *= this->weight(cell);
  row.terms.push_back({u(i, cell + si), weight * 2.0 * m_mu / h});
  row.terms.push_back({u(i, cell), -weight * 2.0 * m_mu / h});
  row.terms.push_back({p(cell), -weight * m_mu});
}

// weight * P_ij(edge), P_ij = mu (u_i[e] - u_i[e - s_j] + u_j[e] - u_j[e - s_i]) / h.
template <int Dim>
void RowBuilder<Dim>::add_shear_stress(int i, int j, std::ptrdiff_t edge, double weight,
                                       ExplicitRow& row) const {
  const std::ptrdiff_t si = m_lattice.stride(i);
  const std::ptrdiff_t sj = m_lattice.stride(j);
  if (exterior(edge) || exterior(edge - si) || exterior(edge - sj) || exterior(edge - si - sj)) {
    row.constant += weight * sigma(i, j, m_lattice.edge_center(i, j, edge));
    return;
  }
  if (m_cell_weight) {
    weight *= 0.25 * (this->weight(edge) + this->weight(edge - si) + this->weight(edge - sj) +
                      this->weight(edge - si - sj));
  }
  const double c = weight * m_mu / m_lattice.h;
  row.terms.push_back({u(i, edge), c});
  row.terms.push_back({u(i, edge - sj), -c});
  row.terms.push_back({u(j, edge), c});
  row.terms.push_back({u(j, edge - si), -c});
}

template <int Dim>
ExplicitRow RowBuilder<Dim>::momentum(int axis, std::ptrdiff_t k) const {
  ExplicitRow row;
  const double inv_h = 1.0 / m_lattice.h;
  const std::ptrdiff_t si = m_lattice.stride(axis);
  add_normal_stress(axis, k, inv_h, row);
  add_normal_stress(axis, k - si, -inv_h, row);
  for (int j = 0; j < Dim; ++j) {
    if (j == axis) continue;
    add_shear_stress(axis, j, k + m_lattice.stride(j), inv_h, row);
    add_shear_stress(axis, j, k, -inv_h, row);
  }
  if (m_inertia != 0.0)
    row.terms.push_back({u(axis, k), -m_inertia * 0.5 * (weight(k) + weight(k - si))});
  merge_duplicates(row);
  fold_tangential_dirichlet(axis, k, row);
  merge_duplicates(row);
  return row;
}

template <int Dim>
ExplicitRow RowBuilder<Dim>::pressure(std::ptrdiff_t k) const {
  ExplicitRow row;
  const double h = m_lattice.h;
  for (int i = 0; i < Dim; ++i) {
    const std::ptrdiff_t si = m_lattice.stride(i);
    if (const auto where = traction_face(i, k)) {
      // Boundary gradient: mu F_ii = (sigma + mu p) / 2 from the traction condition.
      row.constant += 0.5 * sigma(i, i, *where);
      row.pressure_extra += 0.5 * m_mu;
      continue;
    }
    row.terms.push_back({u(i, k + si), m_mu / h});
    row.terms.push_back({u(i, k), -m_mu / h});
  }
  merge_duplicates(row);
  return row;
}

template class RowBuilder<2>;
template class RowBuilder<3>;

}  // namespace mgelastic::grid
