#include "mgelastic/grid/embedded_traction.hpp"

#include <cmath>
#include <memory>

namespace mgelastic::grid {

template <int Dim>
std::int64_t BoundaryStressTable<Dim>::key(int i, int j, const Vec<Dim>& where) const {
  // Stress locations lie on a half-cell lattice: quantize to quarter cells.
  std::int64_t k = i * Dim + j;
  for (int a = 0; a < Dim; ++a) k = k * 4000003 + std::llround(4.0 * where[a] / m_h);
  return k;
}

namespace {

template <int Dim>
struct ForceDistributor {
  const ElasticityProblem<Dim>& problem;
  BoundaryStressTable<Dim>& table;
  std::vector<VariableLoad>& loads;

  CellType cell(std::ptrdiff_t k) const { return problem.cells[k]; }
  bool interior(std::ptrdiff_t k) const { return cell(k) == CellType::INTERIOR; }

  // Face (axis i, flat k) is an interior variable.
  bool interior_face(int i, std::ptrdiff_t k) const {
    return interior(k) && interior(k - problem.lattice.stride(i));
  }

  void deposit(int i, std::ptrdiff_t g, double share) {
    const auto& lat = problem.lattice;
    const std::ptrdiff_t si = lat.stride(i);
    const CellType lower = cell(g - si), upper = cell(g);
    if (lower == CellType::DIRICHLET || upper == CellType::DIRICHLET) return;
    const double area = std::pow(lat.h, Dim - 1);
    if (lower == CellType::INTERIOR && upper == CellType::INTERIOR) {
      loads.push_back({i, g, share / (area * lat.h)});
      return;
    }
    // The share becomes a traction t_i = share / area on the grid face with outward normal
    // N' = +-e_a, i.e. the eliminated stress P_ia = t_i N'_a: the stress then carries exactly
    // the force share (force is conserved on any staircase).
    if (lower == CellType::INTERIOR || upper == CellType::INTERIOR) {
      const double outward = lower == CellType::INTERIOR ? 1.0 : -1.0;
      table.add(i, i, lat.face_center(i, g), outward * share / area);
      return;
    }
    // Half a cell outside: the shear stress on the edge toward an interior face row.
    for (int j = 0; j < Dim; ++j) {
      if (j == i) continue;
      const std::ptrdiff_t sj = lat.stride(j);
      for (int side : {-1, 1}) {
        const std::ptrdiff_t partner = g + side * sj;
        if (partner < 0 || partner >= static_cast<std::ptrdiff_t>(lat.size())) continue;
        if (!interior_face(i, partner)) continue;
        const std::ptrdiff_t edge = side < 0 ? g : g + sj;
        const double outward = side < 0 ? 1.0 : -1.0;  // the interior row lies opposite N'
        table.add(i, j, lat.edge_center(i, j, edge), outward * share / area);
        return;
      }
    }
  }

  // Multilinear weights of point p on the u_i lattice (face centers of axis i).
  void distribute(const SurfaceForce<Dim>& f) {
    const auto& lat = problem.lattice;
    for (int i = 0; i < Dim; ++i) {
      IVec<Dim> base;
      Vec<Dim> frac;
      for (int a = 0; a < Dim; ++a) {
        const double t = (f.position[a] - lat.origin[a]) / lat.h + (a == i ? 1.0 : 0.5);
        base[a] = static_cast<int>(std::floor(t));
        frac[a] = t - base[a];
      }
      for (int corner = 0; corner < (1 << Dim); ++corner) {
        IVec<Dim> s = base;
        double w = 1.0;
        for (int a = 0; a < Dim; ++a) {
          const int bit = (corner >> a) & 1;
          s[a] += bit;
          w *= bit ? frac[a] : 1.0 - frac[a];
        }
        if (w == 0.0) continue;
        bool inside = true;
        // Storage coordinates 0 .. n+1; a face at coordinate 0 along its own axis has no lower
        // cell.
        for (int a = 0; a < Dim; ++a)
          inside = inside && s[a] >= (a == i ? 1 : 0) && s[a] <= lat.cells[a] + 1;
        if (inside) deposit(i, lat.index(s), w * f.force[i]);
      }
    }
  }
};

}  // namespace

template <int Dim>
void apply_surface_forces(ElasticityProblem<Dim>& problem,
                          const std::vector<SurfaceForce<Dim>>& forces) {
  auto table = std::make_shared<BoundaryStressTable<Dim>>(problem.lattice.h);
  ForceDistributor<Dim> distributor{problem, *table, problem.variable_loads};
  for (const auto& f : forces) distributor.distribute(f);
  auto previous = problem.boundary_stress;
  problem.boundary_stress = [table, previous](int i, int j, const Vec<Dim>& x) {
    return (*table)(i, j, x) + (previous ? previous(i, j, x) : 0.0);
  };
}

template class BoundaryStressTable<2>;
template class BoundaryStressTable<3>;
template void apply_surface_forces<2>(ElasticityProblem<2>&, const std::vector<SurfaceForce<2>>&);
template void apply_surface_forces<3>(ElasticityProblem<3>&, const std::vector<SurfaceForce<3>>&);

}  // namespace mgelastic::grid
