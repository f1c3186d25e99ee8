#pragma once
// The one declarative description of the scene file (polyfem's lesson): every key with its type,
// default, unit and documentation. The loader validates documents against it before any work,
// reporting `file: /json/pointer: reason`, and docs/scene-format.md is generated from it
// (`mgelastic scene-format`; a test keeps the page in sync).
#include <nlohmann/json.hpp>
#include <optional>
#include <string>
#include <vector>

namespace mgelastic::scene {

enum class FieldType { NUMBER, INTEGER, STRING, BOOLEAN, VECTOR3, OBJECT, ARRAY, SHAPE };

struct Field {
  std::string name;
  FieldType type = FieldType::NUMBER;
  std::string description;
  std::string unit;
  nlohmann::json default_value;  // null: no default
  bool required = false;
  std::optional<double> minimum, maximum;
  bool exclusive_minimum = false, exclusive_maximum = false;
  std::vector<std::string> choices;  // allowed values of a STRING
  std::vector<Field> children;       // members of an OBJECT, or the element of an ARRAY
};

// The root object of a scene file.
const Field& scene_schema();

// Validates `document` and returns it with every default filled in. Throws mgelastic::Error
// naming `file` and the JSON pointer of the first problem.
nlohmann::json validate_scene(const nlohmann::json& document, const std::string& file);

// The Markdown reference generated from the schema.
std::string scene_format_markdown();

}  // namespace mgelastic::scene
