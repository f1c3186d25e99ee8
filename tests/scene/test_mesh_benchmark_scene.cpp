// The embedded-body benchmark scene (scene/mesh_benchmark_scene.hpp) that `bench vcycle --mesh`
// and the kernel benchmarks share: the mesh's lowest 5 % of height is clamped, the rest free.
#include "mgelastic/scene/mesh_benchmark_scene.hpp"

#include <gtest/gtest.h>

#include <algorithm>
#include <filesystem>

#include "mgelastic/core/error.hpp"
#include "mgelastic/io/surface_mesh_writers.hpp"
#include "mgelastic/scene/grid_setup.hpp"

namespace mgelastic::scene {
namespace {

// A closed box mesh [0, 1] x [0, 2] x [0, 1] (y up), outward triangles.
std::filesystem::path write_tall_box() {
  io::SurfaceVertices v(8, 3);
  for (int i = 0; i < 8; ++i) v.row(i) << (i & 1), 2.0 * ((i >> 1) & 1), (i >> 2) & 1;
  io::SurfaceTriangles t(12, 3);
  t << 0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6, 1,
      3, 5, 3, 7, 5;
  const auto path = std::filesystem::temp_directory_path() / "mgelastic_tall_box.obj";
  io::write_obj(path, v, t);
  return path;
}

TEST(MeshBenchmarkScene, ClampsTheLowestFivePercentOfTheHeight) {
  const auto path = write_tall_box();
  const GridSetup setup =
      build_grid_setup(parse_scene(mesh_benchmark_scene(path.string(), 80, 1e5, 0.45), "b", "."));
  const auto& lattice = setup.problem.lattice;
  const auto& cells = setup.problem.cells;
  std::size_t body = 0, clamped = 0;
  for (std::size_t k = 0; k < cells.size(); ++k) {
    if (cells[k] == grid::CellType::EXTERIOR) continue;
    ++body;
    const double y = lattice.cell_center(static_cast<std::ptrdiff_t>(k))[1];
    if (cells[k] == grid::CellType::DIRICHLET) {
      ++clamped;
      EXPECT_LT(y, 0.05 * 2.0 + lattice.h) << "cell " << k;
    } else {
      EXPECT_GT(y, 0.05 * 2.0 - lattice.h) << "cell " << k;
    }
  }
  ASSERT_GT(body, 0u);
  const double share = static_cast<double>(clamped) / static_cast<double>(body);
  EXPECT_GT(share, 0.03);
  EXPECT_LT(share, 0.08) << clamped << " of " << body;
  std::filesystem::remove(path);
}

TEST(MeshBenchmarkScene, MissingMeshIsAnErrorNamingTheFile) {
  try {
    mesh_benchmark_scene("/nonexistent/armadillo.obj", 64, 1e5, 0.45);
    FAIL() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("armadillo.obj"), std::string::npos) << e.what();
  }
}

}  // namespace
}  // namespace mgelastic::scene
