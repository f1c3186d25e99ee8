#pragma once
// `mgelastic info FILE`: facts about a surface mesh (OBJ, STL, PLY, OFF) or a tetrahedral mesh
// (TetGen, Gmsh, MEDIT): counts, bounding box, closed/manifold/orientation, volume.
#include <CLI/CLI.hpp>

namespace mgelastic::app {

void register_info_command(CLI::App& app);

}  // namespace mgelastic::app
