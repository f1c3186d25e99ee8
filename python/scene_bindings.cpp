// mgelastic.Scene: a validated scene (scene/scene.hpp), read from a file or a Python dict with the
// CLI's schema and error messages.
#include <pybind11/pybind11.h>
#include <pybind11/stl/filesystem.h>

#include <filesystem>
#include <memory>
#include <nlohmann/json.hpp>

#include "bindings.hpp"
#include "mgelastic/scene/scene.hpp"

namespace py = pybind11;

namespace mgelastic::python {
namespace {

using ScenePtr = std::shared_ptr<scene::Scene>;

ScenePtr load(const std::filesystem::path& path) {
  try {
    return std::make_shared<scene::Scene>(scene::load_scene(path));
  } catch (const Error& e) {
    raise_scene_error(e);
  }
}

// The dict goes through Python's json module, so that what is valid JSON for Python is what the
// schema sees (NaN and infinities are not: they fail as in a file).
ScenePtr from_dict(const py::dict& document, const std::string& name,
                   const std::filesystem::path& directory) {
  const std::string text = py::module_::import("json").attr("dumps")(document).cast<std::string>();
  try {
    nlohmann::json parsed;
    try {
      parsed = nlohmann::json::parse(text);
    } catch (const nlohmann::json::exception& e) {
      throw Error(std::string("not valid JSON: ") + e.what(), ErrorContext{.file = name});
    }
    return std::make_shared<scene::Scene>(scene::parse_scene(parsed, name, directory));
  } catch (const Error& e) {
    raise_scene_error(e);
  }
}

py::dict to_dict(const scene::Scene& s) {
  return py::module_::import("json").attr("loads")(s.document.dump());
}

}  // namespace

void bind_scene(py::module_& m) {
  py::class_<scene::Scene, ScenePtr>(
      m, "Scene", "A validated scene (docs/scene-format.md), defaults filled in.")
      .def_static("load", &load, py::arg("path"),
                  "Reads and validates a scene file; raises SceneError naming the file and line "
                  "(JSON syntax) or the JSON pointer (schema).")
      .def_static("from_dict", &from_dict, py::arg("document"), py::arg("name") = "<dict>",
                  py::arg("directory") = std::filesystem::path("."),
                  "Validates a scene given as a dict (the JSON document of a scene file); "
                  "`name` names it in errors, relative mesh paths are resolved in `directory`.")
      .def("to_dict", &to_dict,
           "The validated document with every default filled in; Scene.from_dict of it is the "
           "same scene.")
      .def_property_readonly("file", [](const scene::Scene& s) { return s.file; })
      .def_property_readonly("directory", [](const scene::Scene& s) { return s.directory; })
      .def_property_readonly(
          "engine", [](const scene::Scene& s) { return s.engine; }, "'grid' or 'tet'")
      .def_property_readonly("frames", [](const scene::Scene& s) { return s.time.frames; })
      .def_property_readonly(
          "dt", [](const scene::Scene& s) { return s.time.dt; }, "frame interval, s")
      .def_property_readonly("quasistatic",
                             [](const scene::Scene& s) { return s.time.quasistatic; })
      .def_property_readonly(
          "constraints", [](const scene::Scene& s) { return s.constraints.size(); },
          "number of constraint regions (set_region_pose indices)")
      .def("__repr__", [](const scene::Scene& s) {
        return "<mgelastic.Scene '" + s.file + "' engine=" + s.engine +
               " frames=" + std::to_string(s.time.frames) + ">";
      });
}

}  // namespace mgelastic::python
