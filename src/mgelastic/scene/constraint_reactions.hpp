#pragma once
// Per-constraint reactions of a scene's run (core/reaction.hpp): the force each constraint
// (Scene::constraints, same order) applies to the body and its moment about the centroid of the
// constraint's Dirichlet cells (grid engine) or vertices (tet engine, rest positions). Meant for
// the per-frame output of `mgelastic run` after each frame's solve.
#include <vector>

#include "mgelastic/core/reaction.hpp"
#include "mgelastic/grid/level.hpp"
#include "mgelastic/scene/grid_setup.hpp"
#include "mgelastic/scene/tet_setup.hpp"
#include "mgelastic/tet/corotated_solver.hpp"

namespace mgelastic::scene {

// Grid engine, linear model: `solution` is Multigrid::solution_level() after the solve
// (grid/constraint_reactions.hpp).
std::vector<Reaction> grid_constraint_reactions(const GridSetup& setup,
                                                const grid::Level<3, double>& solution);

// Grid engine, co-rotated model: `solution` is CorotatedMultigrid::solution_level() after the
// solve (grid/constraint_reactions.hpp; the default, symmetrized, stress of the scene's runs).
std::vector<Reaction> grid_corotated_constraint_reactions(const GridSetup& setup,
                                                          const grid::Level<3, double>& solution);

// Tet engine: after CorotatedSolver::solve_static (tet/constraint_reactions.hpp).
std::vector<Reaction> tet_constraint_reactions(const TetSetup& setup,
                                               const tet::CorotatedSolver& solver);

}  // namespace mgelastic::scene
