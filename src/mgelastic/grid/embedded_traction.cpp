#include "mgelastic/grid/embedded_traction.hpp"

#include <array>
#include <cmath>
#include <memory>

namespace mgelastic::grid {

template <int Dim>
typename BoundaryStressTable<Dim>::Key BoundaryStressTable<Dim>::key(int i, int j,
                                                                     const Vec<Dim>& where) const {
  // Stress locations lie on a half-cell lattice: quantize to quarter cells.
  Key k;
  k[0] = i * Dim + j;
  for (int a = 0; a < Dim; ++a) k[a + 1] = std::llround(4.0 * where[a] / m_h);
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

  // Where a share on variable (axis i, face g) goes (Sec. 9.2): an interior variable takes it as
  // a force density; a traction variable as the eliminated boundary stress of its grid face
  // (P_ii on a face between an interior and an exterior cell; P_ij on the edge toward an interior
  // face row for a face half a cell outside); a Dirichlet variable holds it by the constraint.
  // Any other variable is referenced by no equation and cannot carry force.
  enum class Carrier { NONE, DIRICHLET, INTERIOR, NORMAL_STRESS, SHEAR_STRESS };
  struct Target {
    Carrier carrier = Carrier::NONE;
    int j = 0;                // SHEAR_STRESS: the edge's second axis
    std::ptrdiff_t edge = 0;  // SHEAR_STRESS: flat index of the edge
    double outward = 1.0;     // sign of the grid face normal N' along e_i (or e_j)
  };

  Target target(int i, std::ptrdiff_t g) const {
    const auto& lat = problem.lattice;
    const CellType lower = cell(g - lat.stride(i)), upper = cell(g);
    if (lower == CellType::DIRICHLET || upper == CellType::DIRICHLET) return {Carrier::DIRICHLET};
    if (lower == CellType::INTERIOR && upper == CellType::INTERIOR) return {Carrier::INTERIOR};
    if (lower == CellType::INTERIOR || upper == CellType::INTERIOR) {
      // A one-cell-thin body along e_i has no u_i equation that reads this stress.
      const std::ptrdiff_t si = lat.stride(i);
      const std::ptrdiff_t beyond = lower == CellType::INTERIOR ? g - 2 * si : g + si;
      if (cell(beyond) == CellType::EXTERIOR) return {Carrier::NONE};
      return {Carrier::NORMAL_STRESS, i, g, lower == CellType::INTERIOR ? 1.0 : -1.0};
    }
    for (int j = 0; j < Dim; ++j) {
      if (j == i) continue;
      const std::ptrdiff_t sj = lat.stride(j);
      for (int side : {-1, 1}) {
        const std::ptrdiff_t partner = g + side * sj;
        if (partner < 0 || partner >= static_cast<std::ptrdiff_t>(lat.size())) continue;
        if (!interior_face(i, partner)) continue;
        // The interior row lies opposite the outward normal N' of the edge's grid face.
        return {Carrier::SHEAR_STRESS, j, side < 0 ? g : g + sj, side < 0 ? 1.0 : -1.0};
      }
    }
    return {Carrier::NONE};
  }

  void deposit(int i, std::ptrdiff_t g, const Target& to, double share) {
    const auto& lat = problem.lattice;
    const double area = std::pow(lat.h, Dim - 1);
    switch (to.carrier) {
      case Carrier::INTERIOR:
        loads.push_back({i, g, share / (area * lat.h)});
        return;
      // The share becomes a traction t_i = share / area on the grid face with outward normal
      // N' = +-e_a, i.e. the eliminated stress P_ia = t_i N'_a: the stress then carries exactly
      // the force share (force is conserved on any staircase).
      case Carrier::NORMAL_STRESS:
        table.add(i, i, lat.face_center(i, g), to.outward * share / area);
        return;
      case Carrier::SHEAR_STRESS:
        table.add(i, to.j, lat.edge_center(i, to.j, to.edge), to.outward * share / area);
        return;
      case Carrier::DIRICHLET:
      case Carrier::NONE:
        return;
    }
  }

  // Multilinear weights of point p on the u_i lattice (face centers of axis i), renormalized
  // over the corners that can carry force: at staircase corners some corners are inactive faces
  // (no equation references them), and dropping their shares loses a fixed fraction of the
  // boundary force per cut cell, an error that does not shrink under refinement.
  void distribute(const SurfaceForce<Dim>& f) {
    const auto& lat = problem.lattice;
    constexpr int kCorners = 1 << Dim;
    for (int i = 0; i < Dim; ++i) {
      IVec<Dim> base;
      Vec<Dim> frac;
      for (int a = 0; a < Dim; ++a) {
        const double t = (f.position[a] - lat.origin[a]) / lat.h + (a == i ? 1.0 : 0.5);
        base[a] = static_cast<int>(std::floor(t));
        frac[a] = t - base[a];
      }
      std::array<std::ptrdiff_t, kCorners> face{};
      std::array<Target, kCorners> to{};
      std::array<double, kCorners> weight{};
      double carried = 0.0;
      for (int corner = 0; corner < kCorners; ++corner) {
        IVec<Dim> s = base;
        double w = 1.0;
        for (int a = 0; a < Dim; ++a) {
          const int bit = (corner >> a) & 1;
          s[a] += bit;
          w *= bit ? frac[a] : 1.0 - frac[a];
        }
        bool inside = true;
        // Storage coordinates 0 .. n+1; a face at coordinate 0 along its own axis has no lower
        // cell.
        for (int a = 0; a < Dim; ++a)
          inside = inside && s[a] >= (a == i ? 1 : 0) && s[a] <= lat.cells[a] + 1;
        if (w == 0.0 || !inside) continue;
        face[corner] = lat.index(s);
        to[corner] = target(i, face[corner]);
        if (to[corner].carrier == Carrier::NONE) continue;
        weight[corner] = w;
        carried += w;
      }
      // A point in an interior cell has its own u_i faces as carriers unless the body is one cell
      // thin along e_i there and every other corner is inactive too: then the share is lost.
      if (carried == 0.0) continue;
      for (int corner = 0; corner < kCorners; ++corner)
        if (weight[corner] != 0.0)
          deposit(i, face[corner], to[corner], weight[corner] / carried * f.force[i]);
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
