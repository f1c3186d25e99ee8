// sim::Simulation::set_traction / set_pressure / set_force: a load changed between steps acts
// from the next step on. The linear grid model is linear in its loads, so doubling the only load
// of a weightless cantilever doubles its equilibrium displacement, and the result equals a fresh
// simulation of the scene with the doubled load, both to the solver's tolerance. Every grid model
// takes the new loads into its hierarchy (Multigrid::set_loads, CorotatedMultigrid::set_loads)
// without a rebuild; for the co-rotated models the next step equals bit for bit that of a
// simulation built with the new load and restored to the same state. Setting a load to its own
// value continues bit for bit.
#include <gtest/gtest.h>

#include <Eigen/Core>
#include <cmath>
#include <limits>
#include <nlohmann/json.hpp>
#include <string>
#include <vector>

#include "mgelastic/core/error.hpp"
#include "mgelastic/sim/simulation.hpp"
#include "sim/sim_test_support.hpp"

namespace mgelastic::sim {
namespace {

// Relative agreement of two displacements solved to a relative residual of 1e-10: the error of a
// multigrid solution is the residual times the conditioning of the small lattice (well below
// 1e4), so 1e-6 of the largest displacement holds with margin and would catch a lost load share.
constexpr double kSolvedAgreement = 1e-6;

// A weightless 1 x 0.2 x 0.2 cantilever fixed at x = -0.5, loaded on its x = +0.5 face by one
// load of `kind` ("tractions", "pressures" or "forces") times `scale`.
nlohmann::json loaded_bar(const std::string& engine, const std::string& kind, double scale,
                          bool quasistatic = true, const std::string& model = "linear") {
  nlohmann::json s = nlohmann::json::parse(R"({
    "geometry": {"box": {"size": [1, 0.2, 0.2]}},
    "material": {"youngs_modulus": 1e5, "poisson_ratio": 0.3, "density": 1000},
    "constraints": [
      {"region": {"box": {"center": [-0.5, 0, 0], "size": [0.1, 0.4, 0.4]}}, "motion": "fixed"}],
    "loads": {"gravity": [0, 0, 0]},
    "time": {"dt": 0.1, "frames": 4},
    "solver": {"tolerance": 1e-10, "max_vcycles": 200, "precision": "double"},
    "output": {"formats": ["obj"]}})");
  nlohmann::json load = {
      {"region", {{"box", {{"center", {0.5, 0, 0}}, {"size", {0.1, 0.4, 0.4}}}}}},
      {"normal", {1, 0, 0}}};
  if (kind == "tractions") load["traction"] = {0, -100 * scale, 0};
  if (kind == "pressures") load["pressure"] = 100 * scale;
  if (kind == "forces") load["force"] = {0, -4 * scale, 0};
  s["loads"][kind] = {load};
  s["engine"] = engine;
  s["time"]["quasistatic"] = quasistatic;
  if (engine == "grid") {
    s["grid"] = {{"resolution", 10}};
    s["material"]["model"] = model;
  } else {
    s["tet"] = {{"resolution", 5}, {"tolerance", 1e-10}};
  }
  return s;
}

using test::make;

// Sets the load of `kind` to what loaded_bar(kind, scale) gives it.
void set_load(Simulation& s, const std::string& kind, double scale) {
  if (kind == "tractions") s.set_traction(0, Eigen::Vector3d(0, -100 * scale, 0));
  if (kind == "pressures") s.set_pressure(0, 100 * scale);
  if (kind == "forces") s.set_force(0, Eigen::Vector3d(0, -4 * scale, 0));
}

// The engine's primary state (grid: nodal displacement; tet: vertex displacement).
Eigen::VectorXd displacement(const Simulation& s) {
  if (const auto* grid = s.grid()) {
    const std::vector<double>& u = grid->displacement().values;
    return Eigen::Map<const Eigen::VectorXd>(u.data(), static_cast<Eigen::Index>(u.size()));
  }
  const Eigen::MatrixX3d& rest = s.tet()->setup().mesh.vertices;
  Eigen::VectorXd u = s.tet()->positions();
  for (Eigen::Index v = 0; v < rest.rows(); ++v) u.segment<3>(3 * v) -= rest.row(v).transpose();
  return u;
}

// max |a - b| relative to max |b|.
double relative_difference(const Eigen::VectorXd& a, const Eigen::VectorXd& b) {
  return (a - b).lpNorm<Eigen::Infinity>() / b.lpNorm<Eigen::Infinity>();
}

class LinearGridLoad : public testing::TestWithParam<std::string> {};

TEST_P(LinearGridLoad, DoublingTheLoadDoublesTheDisplacement) {
  const std::string kind = GetParam();
  Simulation s(make(loaded_bar("grid", kind, 1.0)));
  s.step();
  const Eigen::VectorXd once = displacement(s);
  ASSERT_GT(once.lpNorm<Eigen::Infinity>(), 1e-6) << kind;  // the load bends the bar
  set_load(s, kind, 2.0);
  s.step();
  EXPECT_LT(relative_difference(displacement(s), 2.0 * once), kSolvedAgreement) << kind;
}

TEST_P(LinearGridLoad, ChangedLoadEqualsAFreshSimulationWithThatLoad) {
  const std::string kind = GetParam();
  Simulation changed(make(loaded_bar("grid", kind, 1.0)));
  changed.step();
  set_load(changed, kind, 2.0);
  changed.step();
  Simulation fresh(make(loaded_bar("grid", kind, 2.0)));
  fresh.step();
  EXPECT_LT(relative_difference(displacement(changed), displacement(fresh)), kSolvedAgreement)
      << kind;
}

// A quasistatic scene with weight: the reloaded stresses get the half-cell body-force term again
// (scene::set_surface_loads), as a fresh setup gives them; the linear model does not rebuild its
// hierarchy (its build time stays that of the first build). Double and mixed precision.
TEST_P(LinearGridLoad, ChangedLoadUnderGravityEqualsAFreshSimulationWithoutARebuild) {
  const std::string kind = GetParam();
  for (const std::string precision : {"double", "float"}) {
    nlohmann::json once = loaded_bar("grid", kind, 1.0), twice = loaded_bar("grid", kind, 2.0);
    for (nlohmann::json* document : {&once, &twice}) {
      (*document)["loads"]["gravity"] = {0, 0, -9.81};
      (*document)["solver"]["precision"] = precision;
    }
    Simulation changed(make(once));
    changed.step();
    const double build_seconds = changed.grid()->hierarchy_seconds();
    set_load(changed, kind, 2.0);
    changed.step();
    EXPECT_EQ(changed.grid()->hierarchy_seconds(), build_seconds) << kind << " rebuilt";
    Simulation fresh(make(twice));
    fresh.step();
    EXPECT_LT(relative_difference(displacement(changed), displacement(fresh)), kSolvedAgreement)
        << kind << " " << precision;
  }
}

INSTANTIATE_TEST_SUITE_P(Simulation, LinearGridLoad,
                         testing::Values("tractions", "pressures", "forces"));

TEST(Simulation, SetLoadOnTheTetEngineEqualsAFreshSimulationWithThatLoad) {
  Simulation changed(make(loaded_bar("tet", "forces", 1.0)));
  changed.step();
  const Eigen::VectorXd once = displacement(changed);
  changed.set_force(0, Eigen::Vector3d(0, -8, 0));
  changed.step();
  Simulation fresh(make(loaded_bar("tet", "forces", 2.0)));
  fresh.step();
  // The load moved the bar, and both runs reach the same co-rotated equilibrium (tolerance 1e-10
  // on the linear solves, the static iteration to its own convergence).
  EXPECT_GT(relative_difference(displacement(changed), once), 0.5);
  EXPECT_LT(relative_difference(displacement(changed), displacement(fresh)), 1e-4);
}

// Replacing an unchanged load keeps every piece of state: velocities and the integrator's clock
// (dynamic), rotations and recycled corrections (co-rotated).
// A tenth of the load and 20 cycles per solve keep the co-rotated solves short (converged or
// not, a solve is deterministic).
void expect_same_load_continues_bit_identically(bool quasistatic, const std::string& model) {
  nlohmann::json document = loaded_bar("grid", "tractions", 0.1, quasistatic, model);
  document["solver"]["tolerance"] = 1e-6;
  document["solver"]["max_vcycles"] = 20;
  Simulation reloaded(make(document)), plain(make(document));
  reloaded.step();
  plain.step();
  set_load(reloaded, "tractions", 0.1);
  reloaded.step();
  plain.step();
  EXPECT_EQ(reloaded.time(), plain.time());
  EXPECT_EQ(displacement(reloaded), displacement(plain)) << model;
  EXPECT_EQ(reloaded.grid()->velocity(), plain.grid()->velocity()) << model;
}

TEST(Simulation, SettingTheSameLoadContinuesBitIdenticallyGridDynamic) {
  expect_same_load_continues_bit_identically(false, "linear");
}
TEST(Simulation, SettingTheSameLoadContinuesBitIdenticallyGridCorotated) {
  expect_same_load_continues_bit_identically(true, "corotated");
}

// The co-rotated models replace the loads in place (CorotatedMultigrid::set_loads): the step after
// the change is bit for bit that of a simulation built with the new load from the state before
// it (checkpoint and restore: what a hierarchy rebuild gives), for each kind of load, with weight
// (body force and its half-cell boundary term), and the hierarchy is not rebuilt.
void expect_corotated_change_equals_a_restored_build(bool quasistatic, const std::string& kind) {
  nlohmann::json once = loaded_bar("grid", kind, 0.1, quasistatic, "corotated");
  nlohmann::json twice = loaded_bar("grid", kind, 0.3, quasistatic, "corotated");
  for (nlohmann::json* document : {&once, &twice}) {
    (*document)["loads"]["gravity"] = {0, 0, -9.81};
    (*document)["solver"]["tolerance"] = 1e-4;
    (*document)["solver"]["max_vcycles"] = 10;
  }
  Simulation changed(make(once));
  changed.step();
  const io::Checkpoint before = changed.checkpoint();
  const Eigen::VectorXd first = displacement(changed);
  const double build_seconds = changed.grid()->hierarchy_seconds();
  set_load(changed, kind, 0.3);
  changed.step();
  EXPECT_EQ(changed.grid()->hierarchy_seconds(), build_seconds) << kind << " rebuilt";
  Simulation restored(make(twice));
  restored.restore(before);
  restored.step();
  // The load acted (the weight dominates the bending).
  EXPECT_GT(relative_difference(displacement(changed), first), 0.01) << kind;
  EXPECT_EQ(changed.stats().cycles, restored.stats().cycles) << kind;
  EXPECT_EQ(changed.time(), restored.time()) << kind;
  EXPECT_EQ(displacement(changed), displacement(restored)) << kind;
  EXPECT_EQ(changed.grid()->velocity(), restored.grid()->velocity()) << kind;
  // All carried state (rotations, cycle counter, recycled corrections) too; the scenes' documents,
  // and so their fingerprints, differ.
  const io::Checkpoint a = changed.checkpoint();
  io::Checkpoint b = restored.checkpoint();
  b.scene_fingerprint = a.scene_fingerprint;
  EXPECT_EQ(io::serialize_checkpoint(a), io::serialize_checkpoint(b)) << kind;
}

TEST(Simulation, CorotatedStaticLoadChangeEqualsARestoredBuildWithThatLoad) {
  for (const std::string kind : {"tractions", "pressures", "forces"})
    expect_corotated_change_equals_a_restored_build(true, kind);
}
TEST(Simulation, CorotatedDynamicLoadChangeEqualsARestoredBuildWithThatLoad) {
  for (const std::string kind : {"tractions", "pressures", "forces"})
    expect_corotated_change_equals_a_restored_build(false, kind);
}

TEST(Simulation, SetLoadRejectsAMissingLoadNamingIt) {
  Simulation s(make(loaded_bar("grid", "tractions", 1.0)));
  try {
    s.set_traction(1, Eigen::Vector3d::Zero());
    FAIL() << "no throw";
  } catch (const Error& e) {
    EXPECT_EQ(e.context().pointer, "/loads/tractions");
    EXPECT_NE(e.reason().find("has 1"), std::string::npos) << e.reason();
  }
  // The scene has no pressure and no total force: the other kinds are refused.
  EXPECT_THROW(s.set_pressure(0, 10.0), Error);
  EXPECT_THROW(s.set_force(0, Eigen::Vector3d::Zero()), Error);
}

TEST(Simulation, SetLoadRejectsANonFiniteValue) {
  Simulation s(make(loaded_bar("tet", "pressures", 1.0)));
  try {
    s.set_pressure(0, std::numeric_limits<double>::quiet_NaN());
    FAIL() << "no throw";
  } catch (const Error& e) {
    EXPECT_EQ(e.context().pointer, "/loads/pressures/0");
  }
  EXPECT_EQ(s.scene().pressures[0].pressure, 100.0);  // unchanged
}

}  // namespace
}  // namespace mgelastic::sim
