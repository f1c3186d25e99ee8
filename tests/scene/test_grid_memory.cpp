// The memory estimate that refuses too-large grid scenes (scene/grid_memory.hpp): it covers the
// solver's own arrays in every precision, and it follows solver.precision and solver.accelerate
// (a single-precision scene fits where the same scene in mixed precision is refused).
#include <gtest/gtest.h>

#include <string>

#include "mgelastic/core/error.hpp"
#include "mgelastic/grid/coarsening.hpp"
#include "mgelastic/grid/local_correction.hpp"
#include "mgelastic/grid/local_corrections.hpp"
#include "mgelastic/grid/multigrid.hpp"
#include "mgelastic/scene/grid_memory.hpp"
#include "mgelastic/scene/grid_setup.hpp"

namespace mgelastic::scene {
namespace {

Scene box(const std::string& precision, bool accelerate) {
  nlohmann::json d = nlohmann::json::parse(R"({
    "geometry": {"box": {"size": [1, 0.5, 0.5]}},
    "grid": {"resolution": 24},
    "constraints": [{"region": {"box": {"center": [-0.5, 0, 0], "size": [0.1, 1, 1]}}}]})");
  d["solver"] = {{"precision", precision}, {"accelerate", accelerate}};
  return parse_scene(d, "box.json", ".");
}

Eigen::Vector3d cells(const GridSetup& setup) {
  const auto& n = setup.problem.lattice.cells;
  return {double(n[0]), double(n[1]), double(n[2])};
}

// The measured solver working set (Multigrid::bytes) of the scene in its precision.
std::size_t solver_bytes(const Scene& s, const GridSetup& setup) {
  grid::MultigridOptions options;
  options.mixed_precision = s.precision != "single";
  if (s.precision == "double") return grid::Multigrid<3, double>(setup.problem, options).bytes();
  return grid::Multigrid<3, float>(setup.problem, options).bytes();
}

TEST(GridMemory, EstimateCoversTheSolverArraysInEveryPrecision) {
  for (const std::string precision : {"single", "float", "double"}) {
    const Scene s = box(precision, false);
    const GridSetup setup = build_grid_setup(s);
    EXPECT_GT(estimated_grid_bytes(s, cells(setup)), static_cast<double>(solver_bytes(s, setup)))
        << precision;
  }
}

// The largest box a placement may build, a solid block of kLocalCorrectionMaxCells cells (the
// most fill per unknown), stays within the estimate's bytes per unknown; the estimate counts
// solver.local_corrections such boxes.
TEST(GridMemory, LargestLocalCorrectionBoxFitsItsEstimate) {
  Scene s = box("float", false);
  s.resolution = 48;  // 48 x 24 x 24 cells
  const GridSetup setup = build_grid_setup(s);
  const auto& problem = setup.problem;
  const auto coarse = grid::coarsen_cells(problem.lattice, problem.cells);
  const auto level =
      grid::build_level<3, float>(problem.lattice, problem.cells, problem.material, {}, &coarse);
  const grid::IVec<3> lo(10, 1, 1), hi(42, 25, 22);  // 32 x 24 x 21 = 16128 cells
  ASSERT_LE(static_cast<std::size_t>((hi - lo).prod()), grid::kLocalCorrectionMaxCells);
  const grid::LocalCorrection<3, float> local(level, problem.material, 0.0, lo, hi);
  const double per_unknown =
      static_cast<double>(local.bytes()) / static_cast<double>(local.unknowns());
  std::printf("largest local correction box: %zu unknowns, %.1f MB, %.0f bytes per unknown\n",
              local.unknowns(), local.bytes() / 1e6, per_unknown);
  EXPECT_GT(local.unknowns(), 3u * 16128u);
  EXPECT_LT(per_unknown, kGridLocalCorrectionBytesPerUnknown);
  Scene without = s;
  without.local_corrections = 0;
  const Eigen::Vector3d n(512, 512, 512);
  EXPECT_GE(estimated_grid_bytes(s, n) - estimated_grid_bytes(without, n),
            s.local_corrections * static_cast<double>(grid::kLocalCorrectionMaxCells) * 4 *
                kGridLocalCorrectionBytesPerUnknown);
}

TEST(GridMemory, SinglePrecisionAndPlainCyclesAreEstimatedSmaller) {
  const Eigen::Vector3d n(128, 128, 128);
  const double single = estimated_grid_bytes(box("single", false), n);
  const double mixed = estimated_grid_bytes(box("float", false), n);
  const double accelerated = estimated_grid_bytes(box("float", true), n);
  EXPECT_LT(single, mixed);
  EXPECT_LT(mixed, accelerated);
}

// The co-rotated model's rows and smoother blocks dwarf the linear hierarchy (measured ten
// times the linear double run's peak per lattice point, grid_memory.hpp).
TEST(GridMemory, CorotatedModelIsEstimatedAboveTheLinearOne) {
  const Eigen::Vector3d n(96, 96, 96);
  Scene corotated = box("double", true);
  corotated.material_model = "corotated";
  EXPECT_GT(estimated_grid_bytes(corotated, n), 5 * estimated_grid_bytes(box("double", true), n));
}

TEST(GridMemory, SingleFitsWhereTheMixedSceneIsRefused) {
  const Eigen::Vector3d n(512, 512, 512);
  const Scene single = box("single", false), mixed = box("float", false);
  const double between = 0.5 * (estimated_grid_bytes(single, n) + estimated_grid_bytes(mixed, n));
  const auto available = static_cast<std::uint64_t>(between);
  EXPECT_NO_THROW(check_grid_size(single, n, available, "test"));
  try {
    check_grid_size(mixed, n, available, "test");
    FAIL() << "the mixed-precision scene was not refused";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/grid/resolution: the grid would need about"),
              std::string::npos)
        << e.what();
  }
}

}  // namespace
}  // namespace mgelastic::scene
