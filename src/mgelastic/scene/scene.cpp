#include "mgelastic/scene/scene.hpp"

#include <algorithm>
#include <cctype>
#include <cmath>
#include <fstream>
#include <sstream>

#include "mgelastic/core/error.hpp"
#include "mgelastic/scene/schema.hpp"

namespace mgelastic::scene {
namespace {

Eigen::Vector3d scene_vec3(const nlohmann::json& v) {
  return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
}

long line_of(const std::string& text, std::size_t byte) {
  long line = 1;
  for (std::size_t i = 0; i < byte && i < text.size(); ++i) line += text[i] == '\n';
  return line;
}

Scene::Constraint parse_constraint(const nlohmann::json& c, const std::string& file,
                                   std::size_t index) {
  const std::string at = "/constraints/" + std::to_string(index);
  Scene::Constraint constraint{c["region"], c["motion"], {}};
  const nlohmann::json& keys = c["keyframes"];
  if (constraint.motion_kind == "fixed") {
    if (!keys.empty())
      throw Error("keyframes need \"motion\": \"keyframed\"",
                  ErrorContext{.file = file, .pointer = at + "/keyframes"});
    return constraint;
  }
  if (keys.empty())
    throw Error("a keyframed region needs at least one keyframe",
                ErrorContext{.file = file, .pointer = at + "/keyframes"});
  std::vector<RigidKeyframe> frames;
  for (std::size_t k = 0; k < keys.size(); ++k) {
    const Eigen::Vector3d axis = scene_vec3(keys[k]["rotate_axis"]);
    const double degrees = keys[k]["rotate_degrees"];
    if (degrees != 0 && axis.norm() == 0)
      throw Error("rotation axis must not be zero",
                  ErrorContext{.file = file, .pointer = at + "/keyframes/" + std::to_string(k)});
    const double time = keys[k]["time"];
    if (!frames.empty() && time <= frames.back().time)
      throw Error(
          "keyframe times must increase strictly",
          ErrorContext{.file = file, .pointer = at + "/keyframes/" + std::to_string(k) + "/time"});
    const Eigen::Quaterniond q =
        degrees == 0
            ? Eigen::Quaterniond::Identity()
            : Eigen::Quaterniond(Eigen::AngleAxisd(degrees * M_PI / 180, axis.normalized()));
    frames.push_back({time, scene_vec3(keys[k]["translate"]), q});
  }
  constraint.motion = KeyframedMotion(scene_vec3(c["pivot"]), std::move(frames));
  return constraint;
}

// Probe names become CSV column prefixes: unique, and free of separators and quotes.
std::vector<Scene::Probe> parse_probes(const nlohmann::json& probes, const std::string& file) {
  std::vector<Scene::Probe> out;
  for (std::size_t i = 0; i < probes.size(); ++i) {
    const std::string name = probes[i]["name"];
    const std::string pointer = "/output/probes/" + std::to_string(i) + "/name";
    const bool valid = !name.empty() && std::all_of(name.begin(), name.end(), [](char c) {
      return std::isalnum(static_cast<unsigned char>(c)) || c == '_' || c == '-' || c == '.';
    });
    if (!valid)
      throw Error("a probe name must be non-empty and use only letters, digits, _ - . (got \"" +
                      name + "\")",
                  ErrorContext{.file = file, .pointer = pointer});
    for (const Scene::Probe& earlier : out)
      if (earlier.name == name)
        throw Error("probe name \"" + name + "\" is used twice",
                    ErrorContext{.file = file, .pointer = pointer});
    out.push_back({name, scene_vec3(probes[i]["point"])});
  }
  return out;
}

// Precision single (float cycles, float solution) has no double solution level: what needs one
// is refused here, before any work, naming the field. `document` is the file as written, so an
// accelerate left at its default is not held against it (single then iterates cycles alone).
void check_single_precision(const Scene& s, const nlohmann::json& document) {
  if (s.engine != "grid" || s.precision != "single") return;
  const ErrorContext at{.file = s.file, .pointer = "/solver/precision"};
  if (s.material_model == "corotated")
    throw Error(
        "\"single\" runs the linear model only: the co-rotated model's rotations and "
        "Newton steps need double; use \"float\" (mixed precision) or \"double\"",
        at);
  if (!s.time.quasistatic)
    throw Error(
        "\"single\" runs quasistatic scenes only: backward Euler writes each step's "
        "right-hand side and start on a double solution level, which single precision "
        "does not have; use \"float\" (the same float cycles, mixed precision)",
        at);
  const auto solver = document.find("solver");
  if (s.accelerate && solver != document.end() && solver->contains("accelerate"))
    throw Error(
        "\"single\" cannot use \"accelerate\": true: FGMRES works on a double solution "
        "level, which single precision does not have; set accelerate to false or use "
        "\"float\"",
        at);
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
  s.material_model = d["material"]["model"];
  for (const auto& m : d["material"]["regions"])
    s.material_regions.push_back(
        {m["region"], m["youngs_modulus"], m["poisson_ratio"], m["density"]});
  for (std::size_t c = 0; c < d["constraints"].size(); ++c)
    s.constraints.push_back(parse_constraint(d["constraints"][c], file, c));
  s.gravity = scene_vec3(d["loads"]["gravity"]);
  const auto selection = [](const nlohmann::json& load) {
    return Scene::SurfaceSelection{load["region"], scene_vec3(load["normal"]),
                                   load["normal_tolerance_degrees"]};
  };
  for (const auto& t : d["loads"]["tractions"])
    s.tractions.push_back({selection(t), scene_vec3(t["traction"])});
  for (const auto& p : d["loads"]["pressures"])
    s.pressures.push_back({selection(p), p["pressure"]});
  for (const auto& f : d["loads"]["forces"])
    s.forces.push_back({selection(f), scene_vec3(f["force"])});
  const nlohmann::json& t = d["time"];
  s.time = {t["dt"],         t["frames"],  t["substeps"],    t["quasistatic"],
            t["integrator"], t["damping"], t["mass_damping"]};
  s.time.vcycles_per_step = t["vcycles_per_step"];
  s.time.rotation_update_every = t["rotation_update_every"];
  s.initial_velocity = scene_vec3(d["initial"]["velocity"]);
  const nlohmann::json& tet = d["tet"];
  s.tet = {tet["rotation"],       tet["resolution"], tet["linear_solver"], tet["tolerance"],
           tet["max_iterations"], tet["vcycles"],    tet["smoother"]};
  s.tet.feature_patches = {tet["feature_patches"]["max_valence"],
                           tet["feature_patches"]["max_size"],
                           tet["feature_patches"]["adaptive_rounds"]};
  s.surface_interpolation = d["output"]["surface"]["interpolation"];
  s.surface_spacing = d["output"]["surface"]["spacing"];
  s.tolerance = d["solver"]["tolerance"];
  s.max_vcycles = d["solver"]["max_vcycles"];
  s.precision = d["solver"]["precision"];
  s.cycle = d["solver"]["cycle"];
  s.boundary_sweeps = d["solver"]["boundary_sweeps"];
  s.corotated_smoother = d["solver"]["corotated_smoother"];
  s.band_layers = d["solver"]["band_layers"];
  s.local_corrections = d["solver"]["local_corrections"];
  s.smoother_order = d["solver"]["smoother_order"];
  s.accelerate = d["solver"]["accelerate"];
  s.output_dir = d["output"]["dir"];
  s.checkpoint_every = d["output"]["checkpoint_every"];
  for (const auto& f : d["output"]["formats"]) s.formats.push_back(f);
  s.vtk_encoding = d["output"]["vtk_encoding"];
  s.probes = parse_probes(d["output"]["probes"], file);
  check_single_precision(s, document);
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
  } catch (const nlohmann::json::exception& e) {
    // Not only syntax: a number beyond double's range throws out_of_range (found by fuzzing).
    throw Error(std::string("invalid JSON: ") + e.what(), ErrorContext{.file = file});
  }
  return parse_scene(document, file, path.parent_path());
}

}  // namespace mgelastic::scene
