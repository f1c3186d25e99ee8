#include "mgelastic/grid/box_problem.hpp"

#include <algorithm>

#include "mgelastic/core/error.hpp"

namespace mgelastic::grid {

int clamp_thickness(const BoxSpec& spec) {
  return spec.clamp_cells > 0 ? spec.clamp_cells : std::max(1, spec.cells / 8);
}

template <int Dim>
ElasticityProblem<Dim> make_box_problem(const BoxSpec& spec) {
  if (spec.cells < 4)
    throw Error("must be at least 4 for one coarsening (got " + std::to_string(spec.cells) + ")",
                {.pointer = "--n"});
  ElasticityProblem<Dim> problem;
  problem.lattice = Lattice<Dim>(IVec<Dim>::Constant(spec.cells), spec.size / spec.cells);
  problem.material = {spec.youngs_modulus, spec.poisson_ratio};
  problem.cells.assign(problem.lattice.size(), CellType::EXTERIOR);
  if (spec.clamp_cells < 0 || spec.clamp_cells >= spec.cells)
    throw Error("must be between 1 and " + std::to_string(spec.cells - 1) +
                    " (the box's cells minus one), or 0 for cells / 8 (got " +
                    std::to_string(spec.clamp_cells) + ")",
                {.pointer = "--clamp-cells"});
  const int slab = clamp_thickness(spec);
  for (std::ptrdiff_t k = 0; k < static_cast<std::ptrdiff_t>(problem.lattice.size()); ++k) {
    const IVec<Dim> s = problem.lattice.coords(k);
    if (!problem.lattice.is_real(s)) continue;
    bool dirichlet = false;
    if (spec.boundary == BoxBoundary::MIXED) {
      dirichlet = s[0] <= slab;
    } else {
      for (int a = 0; a < Dim; ++a) dirichlet = dirichlet || s[a] == 1 || s[a] == spec.cells;
    }
    problem.cells[k] = dirichlet ? CellType::DIRICHLET : CellType::INTERIOR;
  }
  const double force = spec.body_force;
  problem.body_force = [force](const Vec<Dim>&) {
    Vec<Dim> f = Vec<Dim>::Zero();
    f[1] = -force;
    return f;
  };
  return problem;
}

template ElasticityProblem<2> make_box_problem<2>(const BoxSpec&);
template ElasticityProblem<3> make_box_problem<3>(const BoxSpec&);

}  // namespace mgelastic::grid
