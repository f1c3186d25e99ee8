#pragma once
// VTK XML UnstructuredGrid (.vtu) output of tetrahedral meshes: adapts a TetMesh and its fields to
// io::write_vtu (binary zlib-compressed data by default, ASCII on request; written atomically, to
// `path.tmp` then renamed, so a reader never sees a half-written frame).
//
// Field layout: a point field has one row per vertex, a cell field one row per tetrahedron;
// columns are components (1 = scalar, 3 = vector, 9 = 3x3 tensor row-major).
#include <filesystem>
#include <span>
#include <string>

#include "mgelastic/geometry/tet_mesh.hpp"
#include "mgelastic/io/vtk_array_encoder.hpp"

namespace mgelastic::geometry {

struct VtuField {
  std::string name;
  Eigen::MatrixXd values;
};

// Writes `mesh` (its current vertex positions) with optional point and cell fields; the element
// tags, when present, are written as the Int32 cell field "tag". Throws Error on I/O failure or
// when a field's row count does not match.
void write_vtu(const std::filesystem::path& path, const TetMesh& mesh,
               std::span<const VtuField> point_data = {}, std::span<const VtuField> cell_data = {},
               io::VtkEncoding encoding = io::VtkEncoding::BINARY);

}  // namespace mgelastic::geometry
