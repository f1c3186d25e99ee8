#include "mgelastic/scene/surface_selection.hpp"

#include <cmath>
#include <numbers>

#include "mgelastic/core/error.hpp"
#include "mgelastic/scene/build_shape.hpp"

namespace mgelastic::scene {
namespace {

struct TriangleFacts {
  Eigen::Vector3d centroid, normal;
  double area = 0.0;
};

TriangleFacts facts(const geometry::TriangleMesh& surface, Eigen::Index t) {
  const Eigen::Vector3d a = surface.vertices.row(surface.triangles(t, 0)).transpose();
  const Eigen::Vector3d b = surface.vertices.row(surface.triangles(t, 1)).transpose();
  const Eigen::Vector3d c = surface.vertices.row(surface.triangles(t, 2)).transpose();
  const Eigen::Vector3d area_normal = 0.5 * (b - a).cross(c - a);
  TriangleFacts f{(a + b + c) / 3.0, Eigen::Vector3d::Zero(), area_normal.norm()};
  if (f.area > 0) f.normal = area_normal / f.area;
  return f;
}

}  // namespace

std::vector<int> select_surface(const geometry::TriangleMesh& surface,
                                const Scene::SurfaceSelection& selection, const Scene& scene,
                                const std::string& pointer, const std::string& surface_name) {
  const auto region =
      build_shape(selection.region, scene.directory, scene.file, pointer + "/region");
  const bool by_normal = selection.normal.norm() > 0;
  const Eigen::Vector3d direction = by_normal ? selection.normal.normalized() : Eigen::Vector3d();
  // A small slack keeps faces exactly at the cone's edge (e.g. 90 degrees) selected.
  const double min_cosine =
      std::cos(selection.tolerance_degrees * std::numbers::pi / 180.0) - 1e-12;
  std::vector<int> selected;
  bool in_region = false;
  for (Eigen::Index t = 0; t < surface.triangle_count(); ++t) {
    const TriangleFacts f = facts(surface, t);
    if (f.area == 0 || !region->contains(f.centroid)) continue;
    in_region = true;
    if (by_normal && f.normal.dot(direction) < min_cosine) continue;
    selected.push_back(static_cast<int>(t));
  }
  if (!in_region)
    throw Error("the region contains no " + surface_name,
                ErrorContext{.file = scene.file, .pointer = pointer + "/region"});
  if (selected.empty())
    throw Error("no surface triangle in the region has its normal within " +
                    std::to_string(selection.tolerance_degrees) + " degrees of this direction",
                ErrorContext{.file = scene.file, .pointer = pointer + "/normal"});
  return selected;
}

std::vector<TriangleForce> surface_load_forces(const Scene& scene,
                                               const geometry::TriangleMesh& surface,
                                               const std::string& surface_name) {
  std::vector<TriangleForce> forces;
  const auto add = [&](const Scene::SurfaceSelection& selection, const std::string& pointer,
                       auto&& force_of) {
    const std::vector<int> selected =
        select_surface(surface, selection, scene, pointer, surface_name);
    double total_area = 0.0;
    for (int t : selected) total_area += facts(surface, t).area;
    for (int t : selected) {
      const TriangleFacts f = facts(surface, t);
      forces.push_back({t, f.centroid, force_of(f, total_area), f.normal});
    }
  };
  for (std::size_t i = 0; i < scene.tractions.size(); ++i)
    add(scene.tractions[i].surface, "/loads/tractions/" + std::to_string(i),
        [&](const TriangleFacts& f, double) {
          return Eigen::Vector3d(f.area * scene.tractions[i].traction);
        });
  for (std::size_t i = 0; i < scene.pressures.size(); ++i)
    add(scene.pressures[i].surface, "/loads/pressures/" + std::to_string(i),
        [&](const TriangleFacts& f, double) {
          return Eigen::Vector3d(-scene.pressures[i].pressure * f.area * f.normal);
        });
  for (std::size_t i = 0; i < scene.forces.size(); ++i)
    add(scene.forces[i].surface, "/loads/forces/" + std::to_string(i),
        [&](const TriangleFacts& f, double total_area) {
          return Eigen::Vector3d(f.area / total_area * scene.forces[i].force);
        });
  return forces;
}

}  // namespace mgelastic::scene
