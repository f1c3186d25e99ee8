#pragma once
// Builds geometry::Shape objects from validated scene shape descriptions (see schema.cpp).
#include <filesystem>
#include <nlohmann/json.hpp>
#include <string>

#include "mgelastic/geometry/shape.hpp"

namespace mgelastic::scene {

// `file` and `pointer` locate the description for error messages; mesh paths are relative to
// `directory`.
geometry::ShapePtr build_shape(const nlohmann::json& spec, const std::filesystem::path& directory,
                               const std::string& file, const std::string& pointer);

}  // namespace mgelastic::scene
