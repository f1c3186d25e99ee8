#include "mgelastic/grid/half_cell_body_force.hpp"

#include <cmath>
#include <memory>

namespace mgelastic::grid {
namespace {

// +1 when the body lies below the traction face at x along axis i (an upper face), -1 when
// above, 0 when neither or both cells are part of the body, and 0 off the face planes: the
// build samples a one-cell-thin cell's condition at the cell's center (level.cpp, explicit_rows),
// where the cell's weight along i has no center to move to.
template <int Dim>
int face_side(const Lattice<Dim>& lattice, const std::vector<CellType>& cells, int i,
              const Vec<Dim>& x) {
  // Storage coordinates: cell s has its center at origin + h (s - 1/2); the face at x along i
  // lies between cells s_i - 1 and s_i with s_i = (x_i - origin_i) / h + 1.
  const double along = (x[i] - lattice.origin[i]) / lattice.h + 1.0;
  if (std::abs(along - std::round(along)) > 0.25) return 0;
  IVec<Dim> s;
  for (int a = 0; a < Dim; ++a)
    s[a] = static_cast<int>(
        std::lround(a == i ? along : (x[a] - lattice.origin[a]) / lattice.h + 0.5));
  IVec<Dim> lower = s;
  lower[i] -= 1;
  for (int a = 0; a < Dim; ++a)
    if (lower[a] < 0 || s[a] > lattice.cells[a] + 1) return 0;
  const bool below = cells[lattice.index(lower)] != CellType::EXTERIOR;
  const bool above = cells[lattice.index(s)] != CellType::EXTERIOR;
  return below == above ? 0 : (below ? 1 : -1);
}

}  // namespace

template <int Dim>
void add_half_cell_body_force(ElasticityProblem<Dim>& problem) {
  if (!problem.body_force || problem.inertia != 0.0) return;
  const auto lattice = problem.lattice;
  const auto cells = std::make_shared<const std::vector<CellType>>(problem.cells);
  auto previous = problem.boundary_stress;
  auto body_force = problem.body_force;
  problem.boundary_stress = [=](int i, int j, const Vec<Dim>& x) {
    const double sigma = previous ? previous(i, j, x) : 0.0;
    if (i != j) return sigma;
    const int sign = face_side<Dim>(lattice, *cells, i, x);
    return sigma + sign * 0.5 * lattice.h * body_force(x)[i];
  };
}

template void add_half_cell_body_force<2>(ElasticityProblem<2>&);
template void add_half_cell_body_force<3>(ElasticityProblem<3>&);

}  // namespace mgelastic::grid
