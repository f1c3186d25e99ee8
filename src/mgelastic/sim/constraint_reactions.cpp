#include "mgelastic/sim/constraint_reactions.hpp"

#include "mgelastic/scene/constraint_reactions.hpp"
#include "mgelastic/sim/simulation.hpp"

namespace mgelastic::sim {

std::optional<std::vector<Reaction>> constraint_reactions(const Simulation& simulation) {
  if (simulation.scene().constraints.empty()) return std::vector<Reaction>{};
  if (const GridStepper* grid = simulation.grid()) {
    if (const grid::Level<3, double>* solution = grid->linear_solution())
      return scene::grid_constraint_reactions(grid->setup(), *solution);
    if (const grid::Level<3, double>* solution = grid->corotated_solution())
      return scene::grid_corotated_constraint_reactions(grid->setup(), *solution);
    return std::nullopt;
  }
  const TetStepper& tet = *simulation.tet();
  return scene::tet_constraint_reactions(tet.setup(), tet.solver());
}

}  // namespace mgelastic::sim
