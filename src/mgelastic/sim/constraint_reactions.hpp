#pragma once
// Reaction force and moment of every constraint (core/reaction.hpp) in the current state of a
// Simulation, in scene order: grid engine, linear and co-rotated models
// (scene/constraint_reactions.hpp); tet engine. std::nullopt where a model has none (none
// today: the optional stays for models without a double solution level).
#include <optional>
#include <vector>

#include "mgelastic/core/reaction.hpp"

namespace mgelastic::sim {

class Simulation;

std::optional<std::vector<Reaction>> constraint_reactions(const Simulation& simulation);

}  // namespace mgelastic::sim
