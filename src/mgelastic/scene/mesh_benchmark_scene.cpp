#include "mgelastic/scene/mesh_benchmark_scene.hpp"

#include "mgelastic/geometry/surface_mesh_readers.hpp"

namespace mgelastic::scene {

nlohmann::json mesh_benchmark_scene(const std::string& file, int resolution, double youngs_modulus,
                                    double poisson_ratio) {
  const geometry::TriangleMesh mesh = geometry::read_surface_mesh(file);
  const Eigen::Vector3d lo = mesh.vertices.colwise().minCoeff().transpose();
  const Eigen::Vector3d hi = mesh.vertices.colwise().maxCoeff().transpose();
  const Eigen::Vector3d extent = hi - lo, center = 0.5 * (lo + hi);
  // A box around the lowest 5 % of the height, twice the mesh's width: every cell there fixed.
  return {
      {"geometry", {{"mesh", file}}},
      {"grid", {{"resolution", resolution}, {"padding", 1}}},
      {"material",
       {{"youngs_modulus", youngs_modulus}, {"poisson_ratio", poisson_ratio}, {"density", 1000}}},
      {"constraints",
       {{{"region",
          {{"box",
            {{"center", {center.x(), lo.y(), center.z()}},
             {"size", {2 * extent.x(), 0.1 * extent.y(), 2 * extent.z()}}}}}}}}}};
}

}  // namespace mgelastic::scene
