#pragma once
// Helpers shared by the scene tests.
#include <nlohmann/json.hpp>
#include <string>

#include "mgelastic/core/error.hpp"
#include "mgelastic/scene/scene.hpp"

namespace mgelastic::test {

// The message of the Error that parsing `document` as "scene.json" throws; "" when it parses.
inline std::string parse_error_of(const nlohmann::json& document) {
  try {
    scene::parse_scene(document, "scene.json", ".");
  } catch (const Error& e) {
    return e.what();
  }
  return "";
}

}  // namespace mgelastic::test
