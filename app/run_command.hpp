#pragma once
// `mgelastic run SCENE [--threads N] [--output DIR] [--resume]`: the frames of a scene with the
// grid or tet engine, VTK/OBJ/PLY output, checkpoints (mgelastic/sim/run_checkpoints.hpp) and a summary.
#include <CLI/CLI.hpp>
#include <filesystem>

#include "mgelastic/scene/scene.hpp"

namespace mgelastic::app {

void register_run_command(CLI::App& app);

// Simulates a loaded scene and writes its outputs into `output` (empty: the scene's dir);
// `resume` continues from the checkpoint there.
void run_scene(const scene::Scene& scene, const std::filesystem::path& output, bool resume = false);

}  // namespace mgelastic::app
