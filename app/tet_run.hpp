#pragma once
// `mgelastic run` for the tet engine ("engine": "tet"): corotated linear tetrahedra
// (Georgii & Westermann 2008). Per frame k (time (k + 1) dt, as in the grid engine) either one
// static equilibrium at that time (quasistatic) or `substeps` implicit steps of dt / substeps
// (dynamic); keyframed regions move with the clock. After every frame it writes, atomically:
//   vtk  tet_NNNN.vtu (deformed tet mesh; point field displacement, cell field von_mises) and
//        surface_NNNN.vtp (the mesh's boundary faces, deformed), then rewrites simulation.pvd so
//        an interrupted run leaves a valid series of the finished frames;
//   obj  surface_NNNN.obj, ply surface_NNNN.ply (binary): the same boundary surface.
// One line per frame (time, steps or static rounds, solver iterations, residual, phase seconds)
// and a summary go to stdout.
#include <filesystem>

#include "mgelastic/scene/scene.hpp"
#include "run_checkpoints.hpp"

namespace mgelastic::app {

// Starts at checkpoints.first_frame() (from its resume state) and hands each frame's state to it;
// a failing step stops the run with the step, the phase and the frame's residuals so far.
void run_tet_scene(const scene::Scene& s, const std::filesystem::path& output_dir,
                   RunCheckpoints& checkpoints);

}  // namespace mgelastic::app
