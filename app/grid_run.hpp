#pragma once
// `mgelastic run` for the grid engine: a quasistatic solve per frame (keyframed Dirichlet regions
// move between frames, each solve warm-started from the last), writing after every frame the
// lattice fields (.vti), the deformed embedded surface (.vtp, and .obj/.ply when asked) and the
// .pvd series, so an interrupted run leaves every finished frame readable; checkpoints and
// resume as in run_checkpoints.hpp.
#include <filesystem>

#include "mgelastic/scene/scene.hpp"
#include "run_checkpoints.hpp"

namespace mgelastic::app {

// Starts at checkpoints.first_frame() (from its resume state) and hands each frame's state to it.
void run_grid_scene(const scene::Scene& s, const std::filesystem::path& dir,
                    RunCheckpoints& checkpoints);

}  // namespace mgelastic::app
