#include "demo_command.hpp"

#include <cstdio>

#include "bench_command.hpp"
#include "mgelastic/core/threads.hpp"

namespace mgelastic::app {
namespace {

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
  CLI::App* demo = app.add_subcommand("demo", "Run the default demo (convergence table)");
  demo->add_option("--threads", threads, "Worker threads (default: all cores)");
  demo->callback([] {
    set_thread_count(threads);
    print_demo_table();
  });
}

}  // namespace mgelastic::app
