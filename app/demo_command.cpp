#include "demo_command.hpp"

#include <cstdio>

#include "bench_command.hpp"
#include "mgelastic/core/threads.hpp"
#include "mgelastic/scene/scene.hpp"
#include "run_command.hpp"

namespace mgelastic::app {
namespace {

// The default scene (examples/scenes/soft_character.json): a soft character made of capsules and
// a sphere, standing on a fixed base, sagging under gravity.
constexpr const char* kDemoScene = R"json({
  "engine": "grid",
  "geometry": {
    "union": [
      {"capsule": {"a": [0, 0.25, 0], "b": [0, 0.75, 0], "radius": 0.22}},
      {"sphere": {"center": [0, 1.02, 0], "radius": 0.17}},
      {"capsule": {"a": [-0.1, 0.25, 0], "b": [-0.14, 0.02, 0.02], "radius": 0.08}},
      {"capsule": {"a": [0.1, 0.25, 0], "b": [0.14, 0.02, 0.02], "radius": 0.08}},
      {"capsule": {"a": [-0.2, 0.68, 0], "b": [-0.48, 0.5, 0.05], "radius": 0.07}},
      {"capsule": {"a": [0.2, 0.68, 0], "b": [0.48, 0.5, 0.05], "radius": 0.07}}
    ]
  },
  "grid": {"resolution": 64, "padding": 0},
  "material": {"youngs_modulus": 5e5, "poisson_ratio": 0.45, "density": 1000},
  "constraints": [{"region": {"box": {"center": [0, -0.02, 0], "size": [1, 0.12, 1]}}, "motion": "fixed"}],
  "loads": {"gravity": [0, -9.81, 0]},
  "solver": {"tolerance": 1e-6, "max_vcycles": 40, "precision": "float"},
  "output": {"dir": "out/soft_character", "formats": ["vtk"]}
})json";

void run_demo_scene() {
  std::printf("== demo scene: soft character on a fixed base under gravity (grid engine)\n");
  const auto document = nlohmann::json::parse(kDemoScene);
  run_scene(scene::parse_scene(document, "demo scene", "."), "out/demo");
  std::printf("open out/demo/simulation.pvd in ParaView (displacement, pressure, von_mises)\n\n");
}

void print_demo_table() {
  std::printf(
      "mgelastic demo: V(1,1) multigrid on the staggered mixed (displacement/pressure)\n"
      "discretization of Zhu et al. 2010, elastic box fixed on the slab x < 1/8, traction-free\n"
      "elsewhere, under gravity-like load. Residual reduction per V-cycle (geometric mean of the\n"
      "last five of 12 cycles; paper: 0.26-0.28) and final relative residual:\n\n");
  std::printf("%8s | %-22s | %-22s | %-22s\n", "Poisson", "2D 64x64", "3D 32^3", "3D 32^3 float");
  for (double nu : {0.2, 0.3, 0.45, 0.49, 0.495}) {
    std::printf("%8.3f", nu);
    for (auto [dim, n, precision] :
         {std::tuple{2, 64, "double"}, std::tuple{3, 32, "double"}, std::tuple{3, 32, "float"}}) {
      BoxBenchOptions o;
      o.dim = dim;
      o.n = n;
      o.poisson = nu;
      o.precision = precision;
      const auto r = run_convergence(o);
      std::printf(" | rate %.3f  res %.1e", r["rate"].get<double>(),
                  r["relative_residual"].get<double>());
    }
    std::printf("\n");
  }
  std::printf("\nMore: mgelastic bench convergence --help, mgelastic bench cg --help\n");
}

}  // namespace

void register_demo_command(CLI::App& app) {
  static int threads = 0;
  CLI::App* demo = app.add_subcommand(
      "demo", "Run the default demo: an embedded scene, then the solver's convergence table");
  demo->add_option("--threads", threads, "Worker threads (default: all cores)");
  demo->callback([] {
    set_thread_count(threads);
    run_demo_scene();
    print_demo_table();
  });
}

}  // namespace mgelastic::app
