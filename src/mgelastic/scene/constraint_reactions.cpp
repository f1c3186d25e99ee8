#include "mgelastic/scene/constraint_reactions.hpp"

#include "mgelastic/grid/constraint_reactions.hpp"
#include "mgelastic/tet/constraint_reactions.hpp"

namespace mgelastic::scene {

std::vector<Reaction> grid_constraint_reactions(const GridSetup& setup,
                                                const grid::Level<3, double>& solution) {
  return grid::constraint_reactions(
      solution, [&setup](const grid::Vec<3>& x) { return constraint_at(setup, x); },
      setup.constraint_centroids);
}

std::vector<Reaction> grid_corotated_constraint_reactions(const GridSetup& setup,
                                                          const grid::Level<3, double>& solution) {
  return grid::corotated_constraint_reactions(
      solution, setup.problem.boundary_stress,
      [&setup](const grid::Vec<3>& x) { return constraint_at(setup, x); },
      setup.constraint_centroids);
}

std::vector<Reaction> tet_constraint_reactions(const TetSetup& setup,
                                               const tet::CorotatedSolver& solver) {
  return tet::constraint_reactions(solver.unbalanced_forces(), solver.positions(),
                                   setup.vertex_constraint, setup.constraint_centroids);
}

}  // namespace mgelastic::scene
