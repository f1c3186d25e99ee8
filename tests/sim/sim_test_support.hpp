#pragma once
// Helpers shared by the simulation tests.
#include <nlohmann/json.hpp>

#include "mgelastic/scene/scene.hpp"

namespace mgelastic::test {

// The scene of a JSON document, as a scene file in the current directory would give it.
inline scene::Scene make(const nlohmann::json& document) {
  return scene::parse_scene(document, "test scene", ".");
}

}  // namespace mgelastic::test
