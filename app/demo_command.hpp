#pragma once
// `mgelastic demo`: the README's first command. Simulates the embedded default scene (a soft
// character, written to out/demo) and prints the grid engine's convergence table on the paper's
// mixed-boundary elastic box.
#include <CLI/CLI.hpp>

namespace mgelastic::app {

void register_demo_command(CLI::App& app);

}  // namespace mgelastic::app
