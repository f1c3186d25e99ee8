// mgelastic command-line tool: a thin layer over the public library.
#include <CLI/CLI.hpp>
#include <iostream>

#include "bench_command.hpp"
#include "demo_command.hpp"
#include "info_command.hpp"
#include "interruption.hpp"
#include "mgelastic/core/error.hpp"
#include "mgelastic/core/heap_policy.hpp"
#include "run_command.hpp"
#include "scene_commands.hpp"

int main(int argc, char** argv) {
  mgelastic::restore_heap_release();  // hypre's dependencies switched it off (heap_policy.hpp)
  CLI::App app{"mgelastic: multigrid simulation of elastic solids"};
  app.require_subcommand(1);
  app.add_subcommand("version", "Print the version")->callback([] {
    std::cout << "mgelastic 0.1.0\n";
  });
  mgelastic::app::register_bench_commands(app);
  mgelastic::app::register_demo_command(app);
  mgelastic::app::register_scene_commands(app);
  mgelastic::app::register_run_command(app);
  mgelastic::app::register_info_command(app);
  try {
    app.parse(argc, argv);
  } catch (const CLI::ParseError& e) {
    return app.exit(e);
  } catch (const mgelastic::Error& e) {
    std::cerr << "error: " << e.what() << "\n";
    return 2;
  }
  return mgelastic::app::interruption_requested() ? 130 : 0;
}
