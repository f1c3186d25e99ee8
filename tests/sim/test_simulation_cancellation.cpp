// Cancelling a step (core/cancellation.hpp) between solver cycles: step() throws Cancelled, the
// simulation is back at the last completed frame bit for bit, and the next step gives the frame
// an uninterrupted simulation computes. Checked for every solve loop the engines step with: grid
// linear (plain cycles, FGMRES, backward Euler over substeps), grid co-rotated (static and
// dynamic), tet (quasistatic and dynamic); also with a load changed just before the cancelled
// step. The grid engine returns to the frame's start without a hierarchy build.
#include <gtest/gtest.h>

#include <atomic>
#include <nlohmann/json.hpp>
#include <ostream>
#include <string>
#include <thread>
#include <vector>

#include "mgelastic/core/cancellation.hpp"
#include "mgelastic/sim/simulation.hpp"

namespace mgelastic::sim {
namespace {

struct Case {
  std::string name, engine, model = "linear";
  bool quasistatic = true, accelerate = true;
  bool change_load = false;  // a traction on the top face, changed before the cancelled step
  std::string precision = "double";
};
void PrintTo(const Case& c, std::ostream* out) {
  *out << c.name;
}

// A 1 x 0.2 x 0.2 bar under gravity, fixed at x = -0.5, its other end keyframed (pulled), so
// that every frame needs a solve of many cycles.
scene::Scene bar(const Case& c) {
  nlohmann::json s = nlohmann::json::parse(R"({
    "geometry": {"box": {"size": [1, 0.2, 0.2]}},
    "material": {"youngs_modulus": 1e5, "poisson_ratio": 0.3, "density": 1000},
    "constraints": [
      {"region": {"box": {"center": [-0.5, 0, 0], "size": [0.1, 0.4, 0.4]}}, "motion": "fixed"},
      {"region": {"box": {"center": [0.5, 0, 0], "size": [0.1, 0.4, 0.4]}}, "motion": "keyframed",
       "pivot": [0.5, 0, 0],
       "keyframes": [{"time": 0}, {"time": 0.4, "translate": [0.1, 0, 0]}]}],
    "loads": {"gravity": [0, -9.81, 0]},
    "time": {"dt": 0.1, "frames": 4, "substeps": 3, "vcycles_per_step": 0},
    "solver": {"tolerance": 1e-8, "max_vcycles": 60, "precision": "double"},
    "output": {"formats": ["obj"]}})");
  if (c.change_load)
    s["loads"]["tractions"] = {
        {{"region", {{"box", {{"center", {0, 0.1, 0}}, {"size", {0.4, 0.05, 0.4}}}}}},
         {"normal", {0, 1, 0}},
         {"traction", {0, -50, 0}}}};
  s["engine"] = c.engine;
  s["time"]["quasistatic"] = c.quasistatic;
  s["solver"]["accelerate"] = c.accelerate;
  s["solver"]["precision"] = c.precision;
  // Plain cycles that a local correction shortens (solver.local_corrections) might end before
  // the cancellation point: each case keeps its full cycle count.
  s["solver"]["local_corrections"] = 0;
  if (c.engine == "grid") {
    s["grid"] = {{"resolution", 10}};
    s["material"]["model"] = c.model;
  } else {
    s["tet"] = {{"resolution", 4}, {"tolerance", 1e-10}};
  }
  return scene::parse_scene(s, c.name, ".");
}

// The engine's state as one vector (grid: nodal displacement and velocity; tet: positions and
// velocities).
std::vector<double> full_state(const Simulation& s) {
  std::vector<double> out;
  if (const auto* grid = s.grid()) {
    out = grid->displacement().values;
    out.insert(out.end(), grid->velocity().begin(), grid->velocity().end());
    return out;
  }
  const Eigen::VectorXd& x = s.tet()->positions();
  const Eigen::VectorXd& v = s.tet()->velocities();
  out.assign(x.data(), x.data() + x.size());
  out.insert(out.end(), v.data(), v.data() + v.size());
  return out;
}

// Checks (solver cycles or iterations) one step of `s` runs.
std::uint64_t checks_of_step(Simulation& s) {
  const std::uint64_t before = cancellation_checks();
  s.step();
  return cancellation_checks() - before;
}

class CancelledStep : public testing::TestWithParam<Case> {};

TEST_P(CancelledStep, ReturnsToTheLastFrameAndContinuesAsUninterrupted) {
  const Case c = GetParam();
  Simulation interrupted(bar(c)), plain(bar(c));
  interrupted.step();
  plain.step();
  const std::vector<double> before = full_state(interrupted);
  const FrameStats stats_before = interrupted.stats();
  const double build_seconds = interrupted.grid() ? interrupted.grid()->hierarchy_seconds() : 0;
  const Eigen::Vector3d traction(0, -200, 0);
  if (c.change_load) {
    interrupted.set_traction(0, traction);
    plain.set_traction(0, traction);
  }
  {
    Simulation probe(bar(c));  // how many checks frame 1 takes, uninterrupted
    probe.step();
    if (c.change_load) probe.set_traction(0, traction);
    const std::uint64_t whole = checks_of_step(probe);
    ASSERT_GT(whole, 4u) << c.name << ": too few cycles to stop in the middle";
    CancellationScope scope;
    request_cancellation_at_check(whole / 2);  // half-way through frame 1
    EXPECT_THROW(interrupted.step(), Cancelled) << c.name;
  }
  EXPECT_EQ(interrupted.frame(), 1) << c.name;
  EXPECT_EQ(interrupted.time(), plain.time()) << c.name;
  EXPECT_EQ(interrupted.stats().cycles, stats_before.cycles) << c.name;
  // A changed load went into the solver before the cancelled solve (the linear model
  // back-substitutes its traction values then), so the state is the last frame's under it.
  if (!c.change_load) {
    EXPECT_EQ(full_state(interrupted), before) << c.name;
  }
  if (interrupted.grid()) {
    EXPECT_EQ(interrupted.grid()->hierarchy_seconds(), build_seconds) << c.name << " rebuilt";
  }
  // The next step is frame 1 as the uninterrupted simulation computes it, bit for bit.
  interrupted.step();
  plain.step();
  EXPECT_EQ(interrupted.frame(), 2) << c.name;
  EXPECT_EQ(interrupted.stats().cycles, plain.stats().cycles) << c.name;
  EXPECT_EQ(full_state(interrupted), full_state(plain)) << c.name;
}

INSTANTIATE_TEST_SUITE_P(
    Simulation, CancelledStep,
    testing::Values(Case{.name = "grid_static_cycles", .engine = "grid", .accelerate = false},
                    Case{.name = "grid_static_fgmres", .engine = "grid"},
                    // Single precision keeps b on the float finest level (no double level).
                    Case{.name = "grid_static_single",
                         .engine = "grid",
                         .accelerate = false,
                         .precision = "single"},
                    Case{.name = "grid_static_single_load_change",
                         .engine = "grid",
                         .accelerate = false,
                         .change_load = true,
                         .precision = "single"},
                    Case{.name = "grid_dynamic", .engine = "grid", .quasistatic = false},
                    Case{.name = "grid_corotated_static", .engine = "grid", .model = "corotated"},
                    Case{.name = "grid_corotated_dynamic",
                         .engine = "grid",
                         .model = "corotated",
                         .quasistatic = false},
                    Case{.name = "grid_static_load_change", .engine = "grid", .change_load = true},
                    Case{.name = "grid_corotated_static_load_change",
                         .engine = "grid",
                         .model = "corotated",
                         .change_load = true},
                    Case{.name = "grid_corotated_dynamic_load_change",
                         .engine = "grid",
                         .model = "corotated",
                         .quasistatic = false,
                         .change_load = true},
                    Case{.name = "tet_static", .engine = "tet"},
                    Case{.name = "tet_dynamic", .engine = "tet", .quasistatic = false}),
    [](const testing::TestParamInfo<Case>& info) { return info.param.name; });

// A request from another thread (as a signal handler's) stops a long solve within a cycle: the
// step throws before it ran all the cycles it would have.
TEST(Simulation, CancellationFromAnotherThreadStopsTheSolve) {
  scene::Scene s =
      bar({.name = "long", .engine = "grid", .quasistatic = false, .accelerate = false});
  // A frame of exactly 100 cycles: fixed cycle counts run every cycle (a tolerance below the
  // round-off floor would stop at the floor).
  s.time.substeps = 25;
  s.time.vcycles_per_step = 4;
  Simulation simulation(s);
  const std::uint64_t start = cancellation_checks();
  std::uint64_t used = 0;
  {
    CancellationScope scope;
    std::atomic<bool> stop{false};
    std::thread requester([&] {
      while (!stop && cancellation_checks() < start + 3) std::this_thread::yield();
      request_cancellation();
    });
    try {
      simulation.step();
    } catch (const Cancelled&) {
      used = cancellation_checks() - start;
    }
    stop = true;
    requester.join();
  }
  EXPECT_GE(used, 3u);
  EXPECT_LT(used, 100u);
  EXPECT_EQ(simulation.frame(), 0);
  // Outside the scope the request is gone: the step runs all its cycles.
  EXPECT_EQ(simulation.step().cycles, 100);
}

}  // namespace
}  // namespace mgelastic::sim
