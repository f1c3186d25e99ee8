#pragma once
// VTK XML writers that ParaView opens: ImageData (.vti) for lattice fields, PolyData (.vtp) for
// surfaces, and the .pvd collection tying frames together. ASCII data, written atomically.
#include <Eigen/Core>
#include <filesystem>
#include <string>
#include <vector>

namespace mgelastic::io {

// A named array: `components` values per point (or cell), tuples stored contiguously.
struct DataArray {
  std::string name;
  int components = 1;
  std::vector<double> values;
};

// Uniform grid of `cells` cells (x fastest), spacing h, origin at the min corner.
struct ImageData {
  Eigen::Vector3i cells = Eigen::Vector3i::Zero();
  double spacing = 1.0;
  Eigen::Vector3d origin = Eigen::Vector3d::Zero();
  std::vector<DataArray> point_data, cell_data;
};

void write_vti(const std::filesystem::path& path, const ImageData& image);

// Triangle surface with optional point arrays.
void write_vtp(const std::filesystem::path& path,
               const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>& vertices,
               const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>& triangles,
               const std::vector<DataArray>& point_data = {});

struct SeriesEntry {
  double time = 0;
  std::string file;  // relative to the .pvd
  int part = 0;
};

void write_pvd(const std::filesystem::path& path, const std::vector<SeriesEntry>& entries);

}  // namespace mgelastic::io
