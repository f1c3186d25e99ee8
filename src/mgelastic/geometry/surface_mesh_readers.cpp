// Format dispatch of the surface mesh readers.
#include "mgelastic/geometry/surface_mesh_readers.hpp"

#include <algorithm>
#include <cctype>
#include <string>

#include "mgelastic/core/error.hpp"

namespace mgelastic::geometry {

TriangleMesh read_surface_mesh(const std::filesystem::path& path) {
  std::string extension = path.extension().string();
  std::transform(extension.begin(), extension.end(), extension.begin(),
                 [](unsigned char c) { return static_cast<char>(std::tolower(c)); });
  if (extension == ".obj") return read_obj(path);
  if (extension == ".stl") return read_stl(path);
  if (extension == ".ply") return read_ply(path);
  if (extension == ".off") return read_off(path);
  throw Error("unknown surface mesh format '" + extension + "' (supported: .obj, .stl, .ply, .off)",
              ErrorContext{.file = path.string()});
}

}  // namespace mgelastic::geometry
