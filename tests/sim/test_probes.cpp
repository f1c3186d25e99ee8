// Probes and reactions of a Simulation (sim/probes.hpp, sim/constraint_reactions.hpp) and the
// probes.csv that `mgelastic run` writes (sim/probe_table.hpp): interpolation against the
// engines' own fields, pressure in Pa against a column's self-weight, the reaction of a 10 N
// tip force, errors for probes outside the body, and the rows a resumed run keeps.
#include <gtest/gtest.h>

#include <filesystem>
#include <fstream>
#include <nlohmann/json.hpp>

#include "mgelastic/core/error.hpp"
#include "mgelastic/sim/constraint_reactions.hpp"
#include "mgelastic/sim/output_observer.hpp"
#include "mgelastic/sim/probe_table.hpp"
#include "mgelastic/sim/probes.hpp"
#include "mgelastic/sim/simulation.hpp"

namespace mgelastic::sim {
namespace {

// A 0.2 x 1 x 0.2 column standing on its clamped foot at y = 0, loaded by its weight and a
// 10 N force on its top face; two probes on its axis.
nlohmann::json column(const std::string& engine) {
  nlohmann::json s = nlohmann::json::parse(R"({
    "geometry": {"box": {"center": [0, 0.5, 0], "size": [0.2, 1, 0.2]}},
    "material": {"youngs_modulus": 1e6, "poisson_ratio": 0.3, "density": 1000},
    "constraints": [{"region": {"box": {"center": [0, 0, 0], "size": [0.4, 0.05, 0.4]}}}],
    "loads": {"gravity": [0, -9.81, 0],
              "forces": [{"region": {"box": {"center": [0, 1, 0], "size": [0.4, 0.1, 0.4]}},
                          "normal": [0, 1, 0], "force": [10, 0, 0]}]},
    "time": {"dt": 0.1, "frames": 2},
    "solver": {"tolerance": 1e-9, "max_vcycles": 80, "precision": "double"},
    "output": {"formats": [],
               "probes": [{"name": "mid", "point": [0.01, 0.5, 0.01]},
                          {"name": "top", "point": [0.0, 0.98, 0.0]}]}})");
  s["engine"] = engine;
  if (engine == "grid")
    s["grid"] = {{"resolution", 20}};
  else
    s["tet"] = {{"resolution", 10}, {"linear_solver", "cholesky"}};
  return s;
}

Simulation solved(const nlohmann::json& document) {
  Simulation simulation(scene::parse_scene(document, "column", "."));
  simulation.step();
  return simulation;
}

std::filesystem::path fresh_dir(const std::string& name) {
  const auto dir = std::filesystem::temp_directory_path() / ("mgelastic_probes_" + name);
  std::filesystem::remove_all(dir);
  return dir;
}

std::vector<std::string> lines_of(const std::filesystem::path& path) {
  std::ifstream in(path);
  std::vector<std::string> lines;
  for (std::string line; std::getline(in, line);) lines.push_back(line);
  return lines;
}

TEST(Probes, GridDisplacementIsTheNodalFieldsInterpolant) {
  const Simulation simulation = solved(column("grid"));
  const auto samples = sample_probes(simulation);
  ASSERT_EQ(samples.size(), 2u);
  const auto& field = simulation.grid()->displacement();
  for (std::size_t i = 0; i < samples.size(); ++i)
    EXPECT_LT((samples[i].displacement - field.sample(simulation.scene().probes[i].point)).norm(),
              1e-15);
  EXPECT_GT(samples[1].displacement.x(), 0.0);  // pushed along +x at the top
}

TEST(Probes, TetDisplacementAtAVertexIsTheVertexDisplacement) {
  nlohmann::json document = column("tet");
  Simulation simulation = solved(document);
  const tet::TetBody& body = simulation.tet()->solver().body();
  const Eigen::Vector3d vertex = body.rest_positions().segment<3>(3 * body.tets()(7, 2));
  document["output"]["probes"] = {{{"name", "v"}, {"point", {vertex.x(), vertex.y(), vertex.z()}}}};
  Simulation probed = solved(document);
  const auto samples = sample_probes(probed);
  const Eigen::VectorXd& x = probed.tet()->positions();
  const int v = body.tets()(7, 2);
  EXPECT_LT((samples[0].displacement - (x.segment<3>(3 * v) - vertex)).norm(), 1e-12);
}

// Mid-height of a column under its own weight: sigma_yy ~ -rho g (H - y), so the pressure
// -trace(sigma) / 3 ~ rho g H / 6 = 1635 Pa (the clamp and the top force change it by a few %).
// Both engines, in Pa: a scaled pressure (the grid solver's p) would be off by mu = 3.8e5.
TEST(Probes, PressureIsTheMeanStressInPascal) {
  const double expected = 1000 * 9.81 * 1.0 / 6.0;
  for (const std::string engine : {"grid", "tet"}) {
    const auto samples = sample_probes(solved(column(engine)));
    EXPECT_NEAR(samples[0].pressure, expected, 0.25 * expected) << engine;
    EXPECT_GT(samples[0].von_mises, 0.0) << engine;
  }
}

// The clamp holds the weight and the 10 N tip force: reaction = -(loads the equations carry).
TEST(Probes, ReactionsHoldTheTipForceInBothEngines) {
  for (const std::string engine : {"grid", "tet"}) {
    const auto reactions = constraint_reactions(solved(column(engine)));
    ASSERT_TRUE(reactions.has_value()) << engine;
    ASSERT_EQ(reactions->size(), 1u);
    EXPECT_NEAR((*reactions)[0].force.x(), -10.0, 1e-4) << engine;
    EXPECT_GT((*reactions)[0].force.y(), 0.0) << engine;  // holds the weight up
  }
}

// The co-rotated grid model reports reactions too (grid/constraint_reactions.hpp): its rows
// carry the same loads as the linear model's, so the clamp holds the same force. Its moment is
// larger: the weight (363 N on the free body) acts on the column bent sideways by the 10 N (top
// 25 mm, weight-weighted mean ~9 mm: ~3.3 N m more than the linear 9.25 N m), which the linear
// model ignores. A backward-Euler step reports finite ones (they include the inertia).
TEST(Probes, CorotatedGridReactionsHoldTheLinearForceAndTheBentColumnsMoment) {
  const auto linear = constraint_reactions(solved(column("grid")));
  nlohmann::json document = column("grid");
  document["material"]["model"] = "corotated";
  document["time"]["quasistatic"] = true;
  const auto corotated = constraint_reactions(solved(document));
  ASSERT_TRUE(linear.has_value() && corotated.has_value());
  ASSERT_EQ(corotated->size(), 1u);
  EXPECT_LT(((*corotated)[0].force - (*linear)[0].force).norm(), 1e-4 * (*linear)[0].force.norm())
      << (*corotated)[0].force.transpose() << " vs " << (*linear)[0].force.transpose();
  const double m_linear = (*linear)[0].moment.z(), m_corotated = (*corotated)[0].moment.z();
  EXPECT_GT(m_corotated, 1.2 * m_linear);
  EXPECT_LT(m_corotated, 1.6 * m_linear);
  document["time"]["quasistatic"] = false;
  const auto dynamic = constraint_reactions(solved(document));
  ASSERT_TRUE(dynamic.has_value());
  EXPECT_TRUE((*dynamic)[0].force.allFinite() && (*dynamic)[0].moment.allFinite());
  EXPECT_GT((*dynamic)[0].force.norm(), 0.0);
}

TEST(Probes, AProbeOutsideTheBodyIsAnErrorNamingIt) {
  for (const std::string engine : {"grid", "tet"}) {
    nlohmann::json document = column(engine);
    document["output"]["probes"][1]["point"] = {0.5, 0.5, 0.0};
    const Simulation simulation(scene::parse_scene(document, "column", "."));
    try {
      check_probes(simulation);
      ADD_FAILURE() << engine << ": no error";
    } catch (const Error& e) {
      EXPECT_NE(std::string(e.what()).find("/output/probes/1/point"), std::string::npos)
          << e.what();
      EXPECT_NE(std::string(e.what()).find("\"top\" lies outside the body"), std::string::npos);
    }
  }
}

TEST(Probes, BadProbeNamesAreSceneErrors) {
  nlohmann::json document = column("grid");
  document["output"]["probes"][1]["name"] = "mid";
  EXPECT_THROW(scene::parse_scene(document, "column", "."), Error);
  document["output"]["probes"][1]["name"] = "a,b";
  try {
    scene::parse_scene(document, "column", ".");
    ADD_FAILURE() << "no error";
  } catch (const Error& e) {
    EXPECT_NE(std::string(e.what()).find("/output/probes/1/name"), std::string::npos) << e.what();
  }
}

// probes.csv: a header and one row per frame whose values are the samples; a resumed run keeps
// the rows before its first frame and appends its own.
TEST(Probes, CsvHoldsEveryFrameAndSurvivesAResume) {
  const auto dir = fresh_dir("csv");
  const scene::Scene s = scene::parse_scene(column("grid"), "column", ".");
  {
    Simulation simulation(s);
    RunCheckpoints checkpoints(s, dir, false);
    OutputObserver output(s, dir, checkpoints);
    simulation.run(output);
    const auto lines = lines_of(dir / "probes.csv");
    ASSERT_EQ(lines.size(), 3u);
    EXPECT_EQ(lines[0].rfind("frame,time,mid.ux,mid.uy,mid.uz,mid.von_mises,mid.pressure,", 0), 0u);
    EXPECT_NE(lines[0].find("reaction0.fx,reaction0.fy,reaction0.fz,reaction0.mx"),
              std::string::npos);
    EXPECT_EQ(lines[2].rfind("1,", 0), 0u);
    EXPECT_GT(output.probes().last_samples()[1].displacement.x(), 0.0);
  }
  ProbeTable table;
  table.keep_rows_before(dir / "probes.csv", 1);
  Simulation resumed(s);
  resumed.step();
  resumed.step();
  table.add(resumed, 1, resumed.time());
  table.write(dir / "resumed.csv");
  const auto original = lines_of(dir / "probes.csv");
  const auto again = lines_of(dir / "resumed.csv");
  ASSERT_EQ(again.size(), 3u);
  EXPECT_EQ(again[1], original[1]);  // kept
  EXPECT_EQ(again[2], original[2]);  // recomputed: the solvers are deterministic
  std::filesystem::remove_all(dir);
}

}  // namespace
}  // namespace mgelastic::sim
