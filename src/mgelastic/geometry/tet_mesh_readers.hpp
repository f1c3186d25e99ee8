#pragma once
// Readers of tetrahedral meshes. Every reader validates what it read with check_tet_mesh, so a
// returned mesh has indices in range, no degenerate tets and positive orientation; malformed files
// throw mgelastic::Error naming the file and the line (text) or byte offset (binary data) or the
// element index.
//
// Formats:
//  - TetGen `.node` + `.ele`: first index 0 or 1 (taken from the .node file, as TetGen does),
//    attributes and boundary markers ignored, 10-node tets use their 4 corners.
//  - Gmsh `.msh` 2.2 and 4.1, ASCII and binary: 4-node tetrahedra (element type 4) are kept,
//    all other element types skipped; the physical tag (2.2) or volume entity tag (4.1) becomes
//    the element tag.
//  - MEDIT `.mesh`: `Vertices` and `Tetrahedra` sections; the tetrahedron reference becomes the
//    element tag; other known sections are skipped.
#include <filesystem>

#include "mgelastic/geometry/tet_mesh.hpp"

namespace mgelastic::geometry {

using TetMeshReadOptions = TetMeshCheckOptions;

// Chooses the reader by extension: .node/.ele (TetGen), .msh (Gmsh), .mesh (MEDIT).
TetMesh read_tet_mesh(const std::filesystem::path& path, const TetMeshReadOptions& options = {});

// `path` may name the .node file, the .ele file or the common base name.
TetMesh read_tetgen(const std::filesystem::path& path, const TetMeshReadOptions& options = {});
TetMesh read_gmsh(const std::filesystem::path& path, const TetMeshReadOptions& options = {});
TetMesh read_medit(const std::filesystem::path& path, const TetMeshReadOptions& options = {});

}  // namespace mgelastic::geometry
