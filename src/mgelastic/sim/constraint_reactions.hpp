#pragma once
// Reaction force and moment of every constraint (core/reaction.hpp) in the current state of a
// Simulation, in scene order: grid engine, linear model (scene/constraint_reactions.hpp); tet
// engine. The grid engine's co-rotated model has none (its rotated cell stresses are not
// summed yet): std::nullopt.
#include <optional>
#include <vector>

#include "mgelastic/core/reaction.hpp"

namespace mgelastic::sim {

class Simulation;

std::optional<std::vector<Reaction>> constraint_reactions(const Simulation& simulation);

}  // namespace mgelastic::sim
