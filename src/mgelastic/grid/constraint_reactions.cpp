#include "mgelastic/grid/constraint_reactions.hpp"

#include <optional>

#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/corotation.hpp"

namespace mgelastic::grid {
namespace {

// The telescoped flux of the header for one model. `normal(i, cell)` is P_ii at a cell,
// `shear(i, j, edge)` P_ij at an (i, j) edge, each std::nullopt where the rows hold no stress of
// x there (a boundary stress: its traction value is a load, not a reaction). `where(i, j, k)`:
// the point of application of the stress at location k (j == i: a cell center).
template <typename Normal, typename Shear, typename Where>
std::vector<Reaction> sum_fluxes(const Level<3, double>& level,
                                 const std::function<int(const Vec<3>&)>& constraint_of,
                                 const std::vector<Eigen::Vector3d>& points, const Normal& normal,
                                 const Shear& shear, const Where& where) {
  if (!level.cell_weight.empty() || level.dirichlet_zero_depth != 0.0)
    throw Error("constraint_reactions: needs the finest level");
  const Lattice<3>& lat = level.lattice;
  std::vector<Reaction> reactions(points.size());
  for (std::size_t c = 0; c < points.size(); ++c) reactions[c].point = points[c];
  // The clamp's share through one stress: `force` (component i) at `at`, attributed to the
  // constraint of the Dirichlet variable `other` of axis i.
  const auto add = [&](int i, std::ptrdiff_t other, double force, const Vec<3>& at) {
    const int c = constraint_of(lat.face_center(i, other));
    if (c < 0 || c >= static_cast<int>(reactions.size()))
      throw Error("constraint_reactions: constraint index out of range");
    Eigen::Vector3d f = Eigen::Vector3d::Zero();
    f[i] = force;
    reactions[static_cast<std::size_t>(c)].force += f;
    reactions[static_cast<std::size_t>(c)].moment += (at - points[c]).cross(f);
  };
  const double area = lat.h * lat.h;
  const auto flux = [&](int i, std::ptrdiff_t other, double sign, const std::optional<double>& p,
                        int j, std::ptrdiff_t location) {
    if (p) add(i, other, sign * area * *p, where(i, j, location));
  };
  for (int i = 0; i < 3; ++i) {
    const std::ptrdiff_t si = lat.stride(i);
    const auto dirichlet = [&](std::ptrdiff_t k) { return level.kind(i, k) == VarKind::DIRICHLET; };
    for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(lat.size()); ++k) {
      if (level.kind(i, k) != VarKind::INTERIOR) continue;
      if (dirichlet(k + si)) flux(i, k + si, +1, normal(i, k), i, k);
      if (dirichlet(k - si)) flux(i, k - si, -1, normal(i, k - si), i, k - si);
      for (int j = 0; j < 3; ++j) {
        if (j == i) continue;
        const std::ptrdiff_t sj = lat.stride(j);
        // The edges above (at the lower (i, j) corner of cell k + e_j) and below along e_j.
        if (dirichlet(k + sj)) flux(i, k + sj, +1, shear(i, j, k + sj), j, k + sj);
        if (dirichlet(k - sj)) flux(i, k - sj, -1, shear(i, j, k), j, k);
      }
    }
  }
  return reactions;
}

// Rest location of the stress P_ij at k (j == i: cell center, else the (i, j) edge).
Vec<3> stress_location(const Lattice<3>& lat, int i, int j, std::ptrdiff_t k) {
  return i == j ? lat.cell_center(k) : lat.edge_center(i, j, k);
}

// Displacement at a stress location: each component the mean of its active face variables
// around the location (2 for a cell center's components and an edge's own axes, 8 for the
// component along the edge).
Eigen::Vector3d displacement_at(const Level<3, double>& level, int i, int j, std::ptrdiff_t k) {
  const Lattice<3>& lat = level.lattice;
  Eigen::Vector3d u = Eigen::Vector3d::Zero();
  for (int a = 0; a < 3; ++a) {
    const std::ptrdiff_t sa = lat.stride(a);
    double sum = 0;
    int count = 0;
    const auto take = [&](std::ptrdiff_t face) {
      if (level.kind(a, face) == VarKind::INACTIVE) return;
      sum += level.x[a][face];
      ++count;
    };
    if (i == j) {  // cell center: the two a faces of cell k
      take(k);
      take(k + sa);
    } else if (a == i || a == j) {  // (i, j) edge at the lower corner of cell k
      const std::ptrdiff_t other = lat.stride(a == i ? j : i);
      take(k);
      take(k - other);
    } else {
      for (std::ptrdiff_t c :
           {k, k - lat.stride(i), k - lat.stride(j), k - lat.stride(i) - lat.stride(j)}) {
        take(c);
        take(c + sa);
      }
    }
    if (count > 0) u[a] = sum / count;
  }
  return u;
}

}  // namespace

std::vector<Reaction> constraint_reactions(const Level<3, double>& level,
                                           const std::function<int(const Vec<3>&)>& constraint_of,
                                           const std::vector<Eigen::Vector3d>& points) {
  const Lattice<3>& lat = level.lattice;
  const double h = lat.h, mu = level.mu;
  const auto& u = level.x;
  const auto& p = level.x[3];
  const auto exterior = [&](std::ptrdiff_t c) { return level.cells[c] == CellType::EXTERIOR; };
  // Normal stresses in the two cells of an interior face: never eliminated.
  const auto normal = [&](int i, std::ptrdiff_t c) -> std::optional<double> {
    return 2 * mu * (u[i][c + lat.stride(i)] - u[i][c]) / h - mu * p[c];
  };
  // Shear stresses: computed only where the edge's four cells are all in the body.
  const auto shear = [&](int i, int j, std::ptrdiff_t e) -> std::optional<double> {
    const std::ptrdiff_t si = lat.stride(i), sj = lat.stride(j);
    if (exterior(e) || exterior(e - si) || exterior(e - sj) || exterior(e - si - sj))
      return std::nullopt;
    return mu * ((u[i][e] - u[i][e - sj]) + (u[j][e] - u[j][e - si])) / h;
  };
  return sum_fluxes(level, constraint_of, points, normal, shear,
                    [&](int i, int j, std::ptrdiff_t k) { return stress_location(lat, i, j, k); });
}

std::vector<Reaction> corotated_constraint_reactions(
    const Level<3, double>& level, const BoundaryStress<3>& sigma,
    const std::function<int(const Vec<3>&)>& constraint_of,
    const std::vector<Eigen::Vector3d>& points, CorotatedStress form) {
  const std::vector<Matrix<3>> rotations = cell_rotations(level);
  const auto normal = [&](int i, std::ptrdiff_t c) {
    return corotated_stress(level, rotations, sigma, i, i, c, form);
  };
  const auto shear = [&](int i, int j, std::ptrdiff_t e) {
    return corotated_stress(level, rotations, sigma, i, j, e, form);
  };
  const auto where = [&](int i, int j, std::ptrdiff_t k) -> Vec<3> {
    return stress_location(level.lattice, i, j, k) + displacement_at(level, i, j, k);
  };
  return sum_fluxes(level, constraint_of, points, normal, shear, where);
}

Eigen::Vector3d free_load(const Level<3, double>& level) {
  const double volume = level.lattice.h * level.lattice.h * level.lattice.h;
  Eigen::Vector3d load = Eigen::Vector3d::Zero();
  for (int i = 0; i < 3; ++i)
    for (std::size_t k = 0; k < level.size(); ++k)
      if (level.kind(i, k) == VarKind::INTERIOR) load[i] -= volume * level.b[i][k];
  // Boundary stresses moved into the band rows' constants (compact rows: the CSR form may be
  // dropped, band_kernel.hpp).
  const auto& rows = level.band_kernel;
  for (std::size_t m = 0; m < rows.rows(); ++m)
    if (level.kind(rows.field[m], rows.target[m]) == VarKind::INTERIOR)
      load[rows.field[m]] += volume * rows.constant[m];
  return load;
}

}  // namespace mgelastic::grid
