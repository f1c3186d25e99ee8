// sim::Simulation: frame/time semantics, field shapes, checkpoint continuation, region poses, and
// that the output observer's checkpoint (what `mgelastic run` writes) holds exactly the state of
// a simulation stepped by hand. Continuations compare bits: the solvers are deterministic for a
// fixed thread count, which is what checkpoints promise (io/checkpoint.hpp).
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <iterator>
#include <nlohmann/json.hpp>

#include "mgelastic/sim/output_observer.hpp"
#include "mgelastic/sim/simulation.hpp"
#include "sim/sim_test_support.hpp"

namespace mgelastic::sim {
namespace {

// A 1 x 0.2 x 0.2 bar, fixed at x = -0.5; the end at x = +0.5 keyframed (pulled and turned).
nlohmann::json bar(const std::string& engine, bool quasistatic, const std::string& model) {
  nlohmann::json s = nlohmann::json::parse(R"({
    "geometry": {"box": {"size": [1, 0.2, 0.2]}},
    "material": {"youngs_modulus": 1e5, "poisson_ratio": 0.3, "density": 1000},
    "constraints": [
      {"region": {"box": {"center": [-0.5, 0, 0], "size": [0.1, 0.4, 0.4]}}, "motion": "fixed"},
      {"region": {"box": {"center": [0.5, 0, 0], "size": [0.1, 0.4, 0.4]}}, "motion": "keyframed",
       "pivot": [0.5, 0, 0],
       "keyframes": [{"time": 0}, {"time": 0.4, "translate": [0.1, 0, 0],
                      "rotate_axis": [1, 0, 0], "rotate_degrees": 30}]}],
    "loads": {"gravity": [0, -9.81, 0]},
    "time": {"dt": 0.1, "frames": 4},
    "solver": {"tolerance": 1e-6, "max_vcycles": 40, "precision": "double"},
    "output": {"formats": ["obj"]}})");
  s["engine"] = engine;
  s["time"]["quasistatic"] = quasistatic;
  if (engine == "grid") {
    s["grid"] = {{"resolution", 10}};
    s["material"]["model"] = model;
  } else {
    s["tet"] = {{"resolution", 5}};
    if (!quasistatic) s["time"]["substeps"] = 2;
  }
  return s;
}

using test::make;

// The engine's primary state as one vector (grid: nodal displacement; tet: vertex positions).
std::vector<double> state(const Simulation& s) {
  if (const auto* grid = s.grid()) return grid->displacement().values;
  const Eigen::VectorXd& x = s.tet()->positions();
  return {x.data(), x.data() + x.size()};
}

// The checkpoint the output observer left in `dir` is byte for byte that of `expected` with the
// observer's series.
void expect_checkpoint_file(const std::filesystem::path& dir, const Simulation& expected,
                            const OutputObserver& output) {
  std::ifstream in(checkpoint_path(dir), std::ios::binary);
  const std::vector<char> file{std::istreambuf_iterator<char>(in), {}};
  const std::vector<std::byte> bytes =
      io::serialize_checkpoint(expected.checkpoint({series_array(output.series())}));
  ASSERT_EQ(file.size(), bytes.size()) << expected.scene().file;
  EXPECT_EQ(std::memcmp(file.data(), bytes.data(), file.size()), 0) << expected.scene().file;
}

TEST(Simulation, StepAdvancesOneFrameAtTimeKPlusOneDt) {
  Simulation s(make(bar("grid", true, "linear")));
  EXPECT_EQ(s.frame(), 0);
  EXPECT_EQ(s.frames(), 4);
  const FrameStats& stats = s.step();
  EXPECT_EQ(stats.frame, 0);
  EXPECT_EQ(s.frame(), 1);
  EXPECT_NEAR(s.time(), 0.1, 1e-12);
  EXPECT_TRUE(stats.converged);
  EXPECT_GT(stats.cycles, 0);
}

TEST(Simulation, AdvanceToStopsAtTheFrameOfThatTime) {
  Simulation s(make(bar("grid", false, "linear")));
  s.advance_to(0.3);
  EXPECT_EQ(s.frame(), 3);
  EXPECT_NEAR(s.time(), 0.3, 1e-12);
  s.advance_to(0.3);  // already there
  EXPECT_EQ(s.frame(), 3);
}

TEST(Simulation, GridFieldShapes) {
  Simulation s(make(bar("grid", true, "linear")));
  s.step();
  const GridStepper& g = *s.grid();
  const Eigen::Vector3i n = g.cells();
  const std::size_t cells = static_cast<std::size_t>(n.prod());
  const std::size_t nodes = static_cast<std::size_t>((n.array() + 1).prod());
  EXPECT_EQ(g.displacement().values.size(), 3 * nodes);
  EXPECT_EQ(g.velocity().size(), 3 * nodes);
  EXPECT_EQ(g.pressure().size(), cells);
  EXPECT_EQ(g.von_mises().size(), cells);
  EXPECT_EQ(g.cell_types().size(), cells);
  EXPECT_EQ(s.surface_vertices().rows(), g.rest_surface().vertices.rows());
  EXPECT_GT(s.surface_triangles().rows(), 0);
}

TEST(Simulation, TetFieldShapes) {
  Simulation s(make(bar("tet", false, "linear")));
  s.step();
  const TetStepper& t = *s.tet();
  const Eigen::Index vertices = t.setup().mesh.vertex_count();
  EXPECT_EQ(t.positions().size(), 3 * vertices);
  EXPECT_EQ(t.velocities().size(), 3 * vertices);
  EXPECT_EQ(t.von_mises().rows(), t.setup().mesh.tet_count());
  EXPECT_EQ(s.surface_vertices().rows(), t.rest_surface().rows());
}

// Save after two frames, continue both the original and a simulation restored from the file:
// the next two frames agree bit for bit.
void expect_bit_identical_continuation(const nlohmann::json& document) {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() /
      ("mgelastic_sim_resume_" + std::to_string(::getpid()) + ".mgck");
  Simulation a(make(document));
  a.step();
  a.step();
  a.save(file);
  a.step();
  a.step();
  Simulation b = Simulation::resume(make(document), file);
  std::filesystem::remove(file);
  EXPECT_EQ(b.frame(), 2);
  b.step();
  b.step();
  EXPECT_EQ(b.time(), a.time());
  EXPECT_EQ(state(b), state(a));
  EXPECT_EQ(io::serialize_checkpoint(b.checkpoint()), io::serialize_checkpoint(a.checkpoint()));
}

TEST(Simulation, ResumeContinuesBitIdenticallyGridQuasistatic) {
  expect_bit_identical_continuation(bar("grid", true, "linear"));
}
TEST(Simulation, ResumeContinuesBitIdenticallyGridDynamic) {
  expect_bit_identical_continuation(bar("grid", false, "linear"));
}
TEST(Simulation, ResumeContinuesBitIdenticallyGridCorotated) {
  nlohmann::json document = bar("grid", true, "corotated");
  document["solver"]["tolerance"] = 1e-4;  // a few cycles per frame keep the test short
  expect_bit_identical_continuation(document);
}
// Single precision: the checkpoint's double copy of the float unknowns rounds back exactly.
TEST(Simulation, ResumeContinuesBitIdenticallyGridSinglePrecision) {
  nlohmann::json document = bar("grid", true, "linear");
  document["solver"]["precision"] = "single";
  expect_bit_identical_continuation(document);
}
TEST(Simulation, ResumeContinuesBitIdenticallyTetDynamic) {
  expect_bit_identical_continuation(bar("tet", false, "linear"));
}

TEST(Simulation, ResumeRefusesAnotherScene) {
  const std::filesystem::path file =
      std::filesystem::temp_directory_path() /
      ("mgelastic_sim_refuse_" + std::to_string(::getpid()) + ".mgck");
  Simulation a(make(bar("grid", true, "linear")));
  a.step();
  a.save(file);
  nlohmann::json other = bar("grid", true, "linear");
  other["material"]["poisson_ratio"] = 0.35;
  EXPECT_THROW(Simulation::resume(make(other), file), Error);
  std::filesystem::remove(file);
}

// The region at x = +0.5 posed 0.05 m along +x: the bar's far end follows it (quasistatic, no
// gravity, so that end moves by the pose and nothing else pulls it).
void expect_pose_moves_region(const std::string& engine) {
  nlohmann::json document = bar(engine, true, "linear");
  document["loads"]["gravity"] = {0, 0, 0};
  Simulation s(make(document));
  s.set_region_pose(1, Eigen::Vector3d(0.05, 0, 0), Eigen::Quaterniond::Identity());
  s.step();
  const io::SurfaceVertices rest = engine == "grid"
                                       ? io::SurfaceVertices(s.grid()->rest_surface().vertices)
                                       : s.tet()->rest_surface();
  const io::SurfaceVertices moved = s.surface_vertices();
  double far_end = 0, near_end = 0;
  for (Eigen::Index v = 0; v < rest.rows(); ++v) {
    if (rest(v, 0) > 0.49) far_end = std::max(far_end, moved(v, 0) - rest(v, 0));
    if (rest(v, 0) < -0.49) near_end = std::max(near_end, std::abs(moved(v, 0) - rest(v, 0)));
  }
  // The tricubic/embedded surface reproduces a rigid shift of the lattice to a few percent.
  EXPECT_NEAR(far_end, 0.05, 0.005) << engine;
  EXPECT_LT(near_end, 0.005) << engine;
}

TEST(Simulation, SetRegionPoseMovesTheRegionGrid) {
  expect_pose_moves_region("grid");
}
TEST(Simulation, SetRegionPoseMovesTheRegionTet) {
  expect_pose_moves_region("tet");
}

TEST(Simulation, SetRegionPoseRejectsAMissingRegion) {
  Simulation s(make(bar("grid", true, "linear")));
  EXPECT_THROW(s.set_region_pose(7, Eigen::Vector3d::Zero(), Eigen::Quaterniond::Identity()),
               Error);
}

// run() with the output observer (what `mgelastic run` does) leaves a checkpoint with exactly
// the state of a simulation stepped by hand, and the .obj of the last frame.
TEST(Simulation, OutputObserverRunMatchesSteppingByHand) {
  for (const auto* engine : {"grid", "tet"}) {
    const nlohmann::json document = bar(engine, false, "linear");
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                      ("mgelastic_sim_run_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    const scene::Scene scene = make(document);
    RunCheckpoints checkpoints(scene, dir, false);
    OutputObserver output(scene, dir, checkpoints);
    Simulation ran(scene);
    ran.run(output);
    EXPECT_EQ(ran.frame(), 4);
    EXPECT_TRUE(std::filesystem::exists(dir / "surface_0003.obj")) << engine;

    Simulation by_hand(make(document));
    for (int k = 0; k < 4; ++k) by_hand.step();
    expect_checkpoint_file(dir, by_hand, output);
    std::filesystem::remove_all(dir);
  }
}

// Three example scenes as they are (co-rotated quasistatic grid, FGMRES-accelerated linear grid,
// dynamic tet): the files `mgelastic run` writes come from run() with the output observer; its
// final checkpoint holds bit for bit the state of the same scene stepped by hand.
TEST(Simulation, ExampleScenesRunEqualsSteppingByHand) {
  for (const char* name : {"large_twist_bar", "cantilever_bar", "tet_twisted_bar"}) {
    const scene::Scene scene =
        scene::load_scene(std::string(MGELASTIC_SOURCE_DIR) + "/examples/scenes/" + name + ".json");
    const std::filesystem::path dir = std::filesystem::temp_directory_path() /
                                      ("mgelastic_sim_example_" + std::to_string(::getpid()));
    std::filesystem::remove_all(dir);
    RunCheckpoints checkpoints(scene, dir, false);
    OutputObserver output(scene, dir, checkpoints);
    Simulation ran(scene);
    ran.run(output);
    Simulation by_hand(scene);
    while (by_hand.frame() < by_hand.frames()) by_hand.step();
    EXPECT_EQ(state(by_hand), state(ran)) << name;
    expect_checkpoint_file(dir, by_hand, output);
    std::filesystem::remove_all(dir);
  }
}

}  // namespace
}  // namespace mgelastic::sim
