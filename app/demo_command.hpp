#pragma once
// `mgelastic demo`: the README's first command. Until scene files exist it prints the grid
// engine's convergence table on the paper's mixed-boundary elastic box.
#include <CLI/CLI.hpp>

namespace mgelastic::app {

void register_demo_command(CLI::App& app);

}  // namespace mgelastic::app
