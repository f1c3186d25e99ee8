#include "mgelastic/grid/constraint_reactions.hpp"

#include "mgelastic/core/error.hpp"

namespace mgelastic::grid {

std::vector<Reaction> constraint_reactions(const Level<3, double>& level,
                                           const std::function<int(const Vec<3>&)>& constraint_of,
                                           const std::vector<Eigen::Vector3d>& points) {
  if (!level.cell_weight.empty() || level.dirichlet_zero_depth != 0.0)
    throw Error("constraint_reactions: needs the finest level");
  const Lattice<3>& lat = level.lattice;
  const double h = lat.h, mu = level.mu;
  const auto& u = level.x;
  const auto& p = level.x[3];
  const auto exterior = [&](std::ptrdiff_t c) { return level.cells[c] == CellType::EXTERIOR; };
  std::vector<Reaction> reactions(points.size());
  for (std::size_t c = 0; c < points.size(); ++c) reactions[c].point = points[c];
  // The clamp's share through one stress: `force` (component i) at `where`, attributed to the
  // constraint of the Dirichlet variable `other` of axis i.
  const auto add = [&](int i, std::ptrdiff_t other, double force, const Vec<3>& where) {
    const int c = constraint_of(lat.face_center(i, other));
    if (c < 0 || c >= static_cast<int>(reactions.size()))
      throw Error("constraint_reactions: constraint index out of range");
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    f[i] = force;
    reactions[static_cast<std::size_t>(c)].force += f;
    reactions[static_cast<std::size_t>(c)].moment += (where - points[c]).cross(f);
  };
  const double area = h * h;
  for (int i = 0; i < 3; ++i) {
    const std::ptrdiff_t si = lat.stride(i);
    const auto& ui = u[i];
    const auto dirichlet = [&](std::ptrdiff_t k) { return level.kind[i][k] == VarKind::DIRICHLET; };
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(lat.size()); ++k) {
      if (level.kind[i][k] != VarKind::INTERIOR) continue;
      // Normal stresses in the two cells of the face (both interior: never eliminated).
      if (dirichlet(k + si))
        add(i, k + si, area * (2 * mu * (ui[k + si] - ui[k]) / h - mu * p[k]), lat.cell_center(k));
      if (dirichlet(k - si))
        add(i, k - si, -area * (2 * mu * (ui[k] - ui[k - si]) / h - mu * p[k - si]),
            lat.cell_center(k - si));
      // Shear stresses on the edges above and below along e_j; computed only where the edge's
      // four cells are all in the body (else eliminated).
      for (int j = 0; j < 3; ++j) {
        if (j == i) continue;
        const std::ptrdiff_t sj = lat.stride(j);
        const auto& uj = u[j];
        if (dirichlet(k + sj)) {
          const std::ptrdiff_t e = k + sj;  // edge at the lower (i, j) corner of cell e
          if (!exterior(e) && !exterior(e - si) && !exterior(e - sj) && !exterior(e - si - sj))
            add(i, k + sj, area * mu * ((ui[k + sj] - ui[k]) + (uj[k + sj] - uj[k + sj - si])) / h,
                lat.edge_center(i, j, e));
        }
        if (dirichlet(k - sj)) {
          const std::ptrdiff_t e = k;
          if (!exterior(e) && !exterior(e - si) && !exterior(e - sj) && !exterior(e - si - sj))
            add(i, k - sj, -area * mu * ((ui[k] - ui[k - sj]) + (uj[k] - uj[k - si])) / h,
                lat.edge_center(i, j, e));
        }
      }
    }
  }
  return reactions;
}

Eigen::Vector3d free_load(const Level<3, double>& level) {
  const double volume = level.lattice.h * level.lattice.h * level.lattice.h;
  Eigen::Vector3d load = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i)
    for (std::size_t k = 0; k < level.size(); ++k)
      if (level.kind[i][k] == VarKind::INTERIOR) load[i] -= volume * level.b[i][k];
  // Boundary stresses moved into the band rows' constants (compact rows: the CSR form may be
  // dropped, band_kernel.hpp).
  const auto& rows = level.band_kernel;
  for (std::size_t m = 0; m < rows.rows(); ++m)
    if (level.kind[rows.field[m]][rows.target[m]] == VarKind::INTERIOR)
      load[rows.field[m]] += volume * rows.constant[m];
  return load;
}

}  // namespace mgelastic::grid
