// Format dispatch of the tet mesh readers.
#include "mgelastic/geometry/tet_mesh_readers.hpp"

#include "mgelastic/core/error.hpp"

namespace mgelastic::geometry {

TetMesh read_tet_mesh(const std::filesystem::path& path, const TetMeshReadOptions& options) {
  const std::string extension = path.extension().string();
  if (extension == ".node" || extension == ".ele") return read_tetgen(path, options);
  if (extension == ".msh") return read_gmsh(path, options);
  if (extension == ".mesh") return read_medit(path, options);
  throw Error("unknown tetrahedral mesh format (expected .node/.ele, .msh or .mesh)",
              ErrorContext{path.string(), -1, std::string()});
}

}  // namespace mgelastic::geometry
