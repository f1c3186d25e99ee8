#pragma once
// `mgelastic run SCENE [--threads N] [--output DIR]`: quasistatic grid-engine solve of a scene,
// VTK output (grid fields + .pvd series) and a summary.
#include <CLI/CLI.hpp>
#include <filesystem>

#include "mgelastic/scene/scene.hpp"

namespace mgelastic::app {

void register_run_command(CLI::App& app);

// Simulates a loaded scene and writes its outputs into `output` (empty: the scene's dir).
void run_scene(const scene::Scene& scene, const std::filesystem::path& output);

}  // namespace mgelastic::app
