#include "mgelastic/scene/scene.hpp"

#include <fstream>
#include <sstream>

#include "mgelastic/core/error.hpp"
#include "mgelastic/scene/schema.hpp"

namespace mgelastic::scene {
namespace {

Eigen::Vector3d vec3(const nlohmann::json& v) {
  return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
}

long line_of(const std::string& text, std::size_t byte) {
  long line = 1;
  for (std::size_t i = 0; i < byte && i < text.size(); ++i) line += text[i] == '\n';
  return line;
}

}  // namespace

Scene parse_scene(const nlohmann::json& document, const std::string& file,
                  const std::filesystem::path& directory) {
  Scene s;
  s.file = file;
  s.directory = directory;
  s.document = validate_scene(document, file);
  const nlohmann::json& d = s.document;
  s.engine = d["engine"];
  s.geometry = d["geometry"];
  s.cell_size = d["grid"]["cell_size"];
  s.resolution = d["grid"]["resolution"];
  s.padding = d["grid"]["padding"];
  s.youngs_modulus = d["material"]["youngs_modulus"];
  s.poisson_ratio = d["material"]["poisson_ratio"];
  s.density = d["material"]["density"];
  for (const auto& c : d["constraints"]) s.constraints.push_back({c["region"], c["motion"]});
  s.gravity = vec3(d["loads"]["gravity"]);
  for (const auto& t : d["loads"]["tractions"])
    s.tractions.push_back({t["region"], vec3(t["traction"])});
  s.tolerance = d["solver"]["tolerance"];
  s.max_vcycles = d["solver"]["max_vcycles"];
  s.precision = d["solver"]["precision"];
  s.cycle = d["solver"]["cycle"];
  s.boundary_sweeps = d["solver"]["boundary_sweeps"];
  s.accelerate = d["solver"]["accelerate"];
  s.output_dir = d["output"]["dir"];
  for (const auto& f : d["output"]["formats"]) s.formats.push_back(f);
  return s;
}

Scene load_scene(const std::filesystem::path& path) {
  const std::string file = path.string();
  std::ifstream in(path, std::ios::binary);
  if (!in) throw Error("cannot open the scene file", ErrorContext{.file = file});
  std::stringstream buffer;
  buffer << in.rdbuf();
  const std::string text = buffer.str();
  nlohmann::json document;
  try {
    document = nlohmann::json::parse(text);
  } catch (const nlohmann::json::parse_error& e) {
    throw Error(std::string("invalid JSON: ") + e.what(),
                ErrorContext{.file = file, .line = line_of(text, e.byte)});
  }
  return parse_scene(document, file, path.parent_path());
}

}  // namespace mgelastic::scene
