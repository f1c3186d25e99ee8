#pragma once
// Non-zero traction on an embedded boundary (Zhu et al. 2010, Sec. 9.2). The boundary is given
// as point forces on it (a polygon's segment forces l * t, half to each endpoint). Each force
// component f_i is distributed to the u_i variables around its point with the bilinear
// (trilinear) weights of the staggered u_i lattice. A share w f_i landing on an interior variable
// becomes a force density w f_i / h^d on the right-hand side; a share landing on a traction
// variable becomes a traction on the grid face it belongs to, t_i = w f_i / h^(d-1), i.e. the
// value of the boundary stress that Sec. 5.3 eliminates there (P_ii for faces between an interior
// and an exterior cell, P_ij on the edge next to faces half a cell outside), signed by the face's
// outward normal N'. The paper writes t_i = f_i (N . N') / h; the factor N . N' < 1 would lose
// force on every inclined staircase face, so it is left out (docs/grid-engine.md, decision 9).
// Shares on Dirichlet variables are held by the constraint. Corners that no equation references
// (inactive faces at staircase corners, one-cell-thin bodies) cannot carry force: the weights are
// renormalized over the other corners, so the force on the body is conserved exactly.
#include <array>
#include <cstdint>
#include <map>
#include <vector>

#include "mgelastic/grid/problem.hpp"

namespace mgelastic::grid {

template <int Dim>
struct SurfaceForce {
  Vec<Dim> position;  // on the embedded boundary
  Vec<Dim> force;     // N in 3D, N/m in 2D
  Vec<Dim> normal;    // outward unit normal of the embedded boundary
};

// Values of eliminated boundary stresses keyed by (i, j, location), looked up at the points
// explicit_rows.cpp evaluates them (traction face centers, edge centers); absent = 0.
template <int Dim>
class BoundaryStressTable {
 public:
  explicit BoundaryStressTable(double h) : m_h(h) {}
  void add(int i, int j, const Vec<Dim>& where, double value) {
    m_values[key(i, j, where)] += value;
  }
  double operator()(int i, int j, const Vec<Dim>& where) const {
    const auto it = m_values.find(key(i, j, where));
    return it == m_values.end() ? 0.0 : it->second;
  }
  std::size_t size() const { return m_values.size(); }

 private:
  // (i * Dim + j, location in quarter cells): exact, so no two stresses can share an entry.
  using Key = std::array<std::int64_t, Dim + 1>;
  Key key(int i, int j, const Vec<Dim>& where) const;
  double m_h;
  std::map<Key, double> m_values;
};

// Adds the forces to `problem`: variable loads for interior shares, and a boundary-stress table
// (combined with any existing problem.boundary_stress) for traction shares.
template <int Dim>
void apply_surface_forces(ElasticityProblem<Dim>& problem,
                          const std::vector<SurfaceForce<Dim>>& forces);

}  // namespace mgelastic::grid
