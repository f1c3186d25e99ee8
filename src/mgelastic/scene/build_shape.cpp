#include "mgelastic/scene/build_shape.hpp"

#include "mgelastic/core/error.hpp"
#include "mgelastic/geometry/csg.hpp"
#include "mgelastic/geometry/mesh_shape.hpp"
#include "mgelastic/geometry/primitives.hpp"

namespace mgelastic::scene {
namespace {

geometry::Point point(const nlohmann::json& v) {
  return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
}

geometry::ShapePtr build_kind(const std::string& kind, const nlohmann::json& v,
                              const std::filesystem::path& directory, const std::string& file,
                              const std::string& at) {
  using namespace geometry;
  if (kind == "box") return make_box(point(v["center"]), point(v["size"]));
  if (kind == "sphere") return make_sphere(point(v["center"]), v["radius"].get<double>());
  if (kind == "cylinder")
    return make_cylinder(point(v["a"]), point(v["b"]), v["radius"].get<double>());
  if (kind == "capsule")
    return make_capsule(point(v["a"]), point(v["b"]), v["radius"].get<double>());
  if (kind == "torus")
    return make_torus(point(v["center"]), point(v["axis"]), v["major_radius"].get<double>(),
                      v["minor_radius"].get<double>());
  if (kind == "mesh") {
    try {
      return load_mesh_shape(directory / v.get<std::string>());
    } catch (const Error& e) {
      // The reader names the mesh file and line; say where the scene asked for it.
      throw Error(e.what(), ErrorContext{.file = file, .pointer = at});
    }
  }
  std::vector<ShapePtr> children;
  for (std::size_t i = 0; i < v.size(); ++i)
    children.push_back(build_shape(v[i], directory, file, at + "/" + std::to_string(i)));
  if (kind == "union") return make_union(std::move(children));
  if (kind == "intersection") return make_intersection(std::move(children));
  return make_difference(std::move(children));
}

}  // namespace

geometry::ShapePtr build_shape(const nlohmann::json& spec, const std::filesystem::path& directory,
                               const std::string& file, const std::string& pointer) {
  std::string kind;
  for (const auto& [key, value] : spec.items())
    if (key != "transform") kind = key;
  geometry::ShapePtr shape;
  try {
    shape = build_kind(kind, spec[kind], directory, file, pointer + "/" + kind);
  } catch (const Error& e) {
    if (!e.context().file.empty()) throw;
    // Parameter errors from the geometry factories: add where they are in the scene.
    throw Error(
        e.reason(),
        ErrorContext{.file = file, .pointer = pointer + "/" + kind + "/" + e.context().pointer});
  }
  if (!spec.contains("transform")) return shape;
  const auto& t = spec["transform"];
  return geometry::make_transformed(shape, point(t["translate"]), point(t["rotate_axis"]),
                                    t["rotate_degrees"].get<double>(), t["scale"].get<double>());
}

}  // namespace mgelastic::scene
