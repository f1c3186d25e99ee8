#pragma once
// `mgelastic run SCENE [--threads N] [--output DIR]`: quasistatic grid-engine solve of a scene,
// VTK output (grid fields + .pvd series) and a summary.
#include <CLI/CLI.hpp>

namespace mgelastic::app {

void register_run_command(CLI::App& app);

}  // namespace mgelastic::app
