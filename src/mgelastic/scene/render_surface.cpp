#include "mgelastic/scene/render_surface.hpp"

#include <Eigen/Geometry>
#include <cmath>

#include "mgelastic/geometry/marching_cubes.hpp"
#include "mgelastic/geometry/surface_mesh_readers.hpp"

namespace mgelastic::scene {
namespace {

Eigen::Vector3d vec3(const nlohmann::json& v) {
  return {v[0].get<double>(), v[1].get<double>(), v[2].get<double>()};
}

// Same map as geometry::make_transformed: x -> translate + R(axis, degrees) (scale x).
void apply_transform(const nlohmann::json& t, geometry::TriangleMesh& mesh) {
  const Eigen::Vector3d axis = vec3(t["rotate_axis"]);
  const double degrees = t["rotate_degrees"];
  const Eigen::Matrix3d rotation =
      axis.norm() > 0
          ? Eigen::AngleAxisd(degrees * M_PI / 180, axis.normalized()).toRotationMatrix()
          : Eigen::Matrix3d::Identity();
  const Eigen::Matrix3d linear = rotation * t["scale"].get<double>();
  const Eigen::RowVector3d translate = vec3(t["translate"]).transpose();
  mesh.vertices = (mesh.vertices * linear.transpose()).rowwise() + translate;
}

}  // namespace

geometry::TriangleMesh rest_surface(const Scene& scene, const geometry::Shape& body,
                                    double cell_size) {
  if (!scene.geometry.contains("mesh"))
    return geometry::extract_surface(body, scene.surface_spacing * cell_size);
  geometry::TriangleMesh mesh =
      geometry::read_surface_mesh(scene.directory / scene.geometry["mesh"].get<std::string>());
  if (geometry::mesh_facts(mesh).signed_volume < 0) geometry::flip_orientation(mesh);
  if (scene.geometry.contains("transform")) apply_transform(scene.geometry["transform"], mesh);
  return mesh;
}

}  // namespace mgelastic::scene
