// Real meshes from $MGELASTIC_DATA_DIR (see shared/meshes/README.md): load each and run a few
// implicit Euler steps under gravity with the lowest 10% (along y) fixed. Skipped when the
// variable is unset; a missing file with the variable set is a failure.
#include <gtest/gtest.h>

#include <cstdlib>
#include <filesystem>
#include <string>

#include "mgelastic/geometry/tet_mesh_readers.hpp"
#include "mgelastic/tet/corotated_solver.hpp"

namespace mgelastic::tet {
namespace {

void simulate(const std::string& name, int expected_tets) {
  const char* dir = std::getenv("MGELASTIC_DATA_DIR");
  if (dir == nullptr || std::string(dir).empty()) GTEST_SKIP() << "MGELASTIC_DATA_DIR not set";
  const std::filesystem::path path = std::filesystem::path(dir) / name;
  ASSERT_TRUE(std::filesystem::exists(path))
      << "MGELASTIC_DATA_DIR is set but " << path << " is missing";
  const geometry::TetMesh mesh = geometry::read_tet_mesh(path);
  EXPECT_EQ(mesh.tet_count(), expected_tets);
  const double low = mesh.vertices.col(1).minCoeff();
  const double extent = mesh.vertices.col(1).maxCoeff() - low;
  std::vector<int> fixed;
  for (int v = 0; v < mesh.vertex_count(); ++v)
    if (mesh.vertices(v, 1) < low + 0.1 * extent) fixed.push_back(v);
  CorotatedSolverSettings settings;
  settings.gravity = Eigen::Vector3d(0, -9.81, 0);
  settings.time_step = 0.01;
  settings.pcg.tolerance = 1e-6;
  // Soft enough (relative to the model's size) that gravity visibly deforms it in a few steps.
  const double e = 1e4 * extent;
  CorotatedSolver solver(mesh, ElementMaterials::uniform(mesh.tet_count(), {e, 0.3, 1000.0}),
                         settings);
  solver.set_dirichlet(fixed);
  for (int i = 0; i < 5; ++i) {
    const StepStats& stats = solver.step();
    EXPECT_TRUE(stats.solve.converged) << name << " step " << i;
  }
  ASSERT_TRUE(solver.positions().allFinite());
  // Starting at rest with zero energy, a dissipative integrator cannot create energy: the total
  // stays <= 0 up to the PCG tolerance; gravity must have done work (the body sagged).
  const double gravity = solver.gravity_energy();
  const double total = solver.kinetic_energy() + solver.elastic_energy() + gravity;
  EXPECT_LT(gravity, 0.0) << name;
  EXPECT_LE(total, 1e-3 * std::abs(gravity)) << name;
}

TEST(RealMeshes, BunnyGmsh) {
  simulate("bunny.msh", 19379);
}
TEST(RealMeshes, Armadillo13kGmsh) {
  simulate("armadillo_13k.msh", 54985);
}
TEST(RealMeshes, HandMedit) {
  simulate("hand.mesh", 29998);
}
TEST(RealMeshes, Armadillo4kTetGen) {
  simulate("armadillo_4k.node", 3717);
}

}  // namespace
}  // namespace mgelastic::tet
