#pragma once
// VTK XML writers that ParaView opens: ImageData (.vti) for lattice fields, PolyData (.vtp) for
// surfaces, UnstructuredGrid (.vtu) for tetrahedral meshes, and the .pvd collection tying frames
// together. Data arrays are binary, zlib-compressed appended data by default, ASCII on request
// (vtk_array_encoder.hpp); files are written atomically (atomic_file.hpp).
#include <Eigen/Core>
#include <filesystem>
#include <span>
#include <string>
#include <vector>

#include "mgelastic/io/vtk_array_encoder.hpp"

namespace mgelastic::io {

// The type an array is stored as in the file; values are converted from double when written.
enum class VtkScalar { FLOAT64, FLOAT32, INT32, UINT8 };

// A named array: `components` values per point (or cell), tuples stored contiguously, either in
// `values` or, to write a solver's field without copying it, in `borrowed` (which must outlive the
// write and is used when not empty).
struct DataArray {
  std::string name;
  int components = 1;
  std::vector<double> values;
  VtkScalar type = VtkScalar::FLOAT64;
  std::span<const double> borrowed{};

  std::span<const double> data() const {
    return borrowed.empty() ? std::span<const double>(values) : borrowed;
  }
};

// Uniform grid of `cells` cells (x fastest), spacing h, origin at the min corner.
struct ImageData {
  Eigen::Vector3i cells = Eigen::Vector3i::Zero();
  double spacing = 1.0;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  std::vector<DataArray> point_data, cell_data;
};

// Each writer throws mgelastic::Error naming the file and array when an array's size does not
// match its points/cells, or on I/O failure; the previous file at `path` then stays untouched.
void write_vti(const std::filesystem::path& path, const ImageData& image,
               VtkEncoding encoding = VtkEncoding::BINARY);

// Triangle surface with optional point arrays.
void write_vtp(const std::filesystem::path& path,
               const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>& vertices,
               const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>& triangles,
               const std::vector<DataArray>& point_data = {},
               VtkEncoding encoding = VtkEncoding::BINARY);

// Tetrahedral mesh (`vertices` N x 3, `tets` M x 4 zero-based) with point and cell arrays.
void write_vtu(const std::filesystem::path& path, const Eigen::MatrixX3d& vertices,
               const Eigen::MatrixX4i& tets, const std::vector<DataArray>& point_data = {},
               const std::vector<DataArray>& cell_data = {},
               VtkEncoding encoding = VtkEncoding::BINARY);

struct SeriesEntry {
  double time = 0;
  std::string file;  // relative to the .pvd
  int part = 0;
};

void write_pvd(const std::filesystem::path& path, const std::vector<SeriesEntry>& entries);

}  // namespace mgelastic::io
