#include "mgelastic/io/vtk_writers.hpp"

#include <functional>
#include <iomanip>
#include <sstream>

#include "mgelastic/core/error.hpp"
#include "mgelastic/io/atomic_file.hpp"

namespace mgelastic::io {
namespace {

void write_array(std::ostream& out, VtkArrayEncoder& encoder, const DataArray& a,
                 std::size_t tuples, const std::filesystem::path& path) {
  const std::span<const double> values = a.data();
  if (values.size() != tuples * static_cast<std::size_t>(a.components))
    throw Error("array '" + a.name + "' has " + std::to_string(values.size()) +
                    " values, expected " + std::to_string(tuples * a.components),
                ErrorContext{.file = path.string()});
  const std::string attributes =
      "Name=\"" + a.name + "\" NumberOfComponents=\"" + std::to_string(a.components) + '"';
  // Values are converted block by block as they are compressed: no converted copy of the array.
  switch (a.type) {
    case VtkScalar::FLOAT64:
      return encoder.write<double>(out, attributes, values);
    case VtkScalar::FLOAT32:
      return encoder.write<float, double>(out, attributes, values);
    case VtkScalar::INT32:
      return encoder.write<std::int32_t, double>(out, attributes, values);
    case VtkScalar::UINT8:
      return encoder.write<std::uint8_t, double>(out, attributes, values);
  }
}

// Points as Float64 tuples, whatever the storage order of `vertices`.
template <typename Matrix>
void write_points(std::ostream& out, VtkArrayEncoder& encoder, const Matrix& vertices) {
  const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor> rows = vertices;
  out << "<Points>\n";
  encoder.write<double>(out, "NumberOfComponents=\"3\"",
                        std::span<const double>(rows.data(), rows.size()));
  out << "</Points>\n";
}

// Connectivity (row-major vertex indices), offsets (end of each cell) and, when `type` > 0,
// the VTK cell type of every cell.
template <typename Matrix>
void write_cells(std::ostream& out, VtkArrayEncoder& encoder, const Matrix& cells,
                 std::uint8_t type) {
  const Eigen::Matrix<std::int32_t, Eigen::Dynamic, Matrix::ColsAtCompileTime, Eigen::RowMajor>
      connectivity = cells.template cast<std::int32_t>();
  std::vector<std::int32_t> offsets(cells.rows());
  for (std::size_t i = 0; i < offsets.size(); ++i)
    offsets[i] = static_cast<std::int32_t>((i + 1) * cells.cols());
  encoder.write<std::int32_t>(
      out, "Name=\"connectivity\"",
      std::span<const std::int32_t>(connectivity.data(), connectivity.size()));
  encoder.write<std::int32_t>(out, "Name=\"offsets\"", std::span<const std::int32_t>(offsets));
  if (type == 0) return;
  const std::vector<std::uint8_t> types(cells.rows(), type);
  encoder.write<std::uint8_t>(out, "Name=\"types\"", std::span<const std::uint8_t>(types));
}

void write_arrays(std::ostream& out, VtkArrayEncoder& encoder, const char* element,
                  const std::vector<DataArray>& arrays, std::size_t tuples,
                  const std::filesystem::path& path) {
  out << '<' << element << ">\n";
  for (const auto& a : arrays) write_array(out, encoder, a, tuples, path);
  out << "</" << element << ">\n";
}

// The XML goes to a buffer first: binary arrays are compressed while their elements are written,
// and their bytes follow the XML.
void write_document(const std::filesystem::path& path, const char* type, VtkEncoding encoding,
                    const std::function<void(std::ostream&, VtkArrayEncoder&)>& body) {
  VtkArrayEncoder encoder(encoding);
  std::ostringstream xml;
  xml << std::setprecision(17);
  body(xml, encoder);
  write_file_atomically(
      path,
      [&](std::ostream& out) {
        out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"" << type << "\" "
            << encoder.file_attributes() << ">\n"
            << xml.view();
        encoder.write_appended(out);
        out << "</VTKFile>\n";
      },
      true);
}

}  // namespace

void write_vti(const std::filesystem::path& path, const ImageData& image, VtkEncoding encoding) {
  const auto& c = image.cells;
  const std::size_t points = std::size_t(c[0] + 1) * (c[1] + 1) * (c[2] + 1);
  const std::size_t cells = std::size_t(c[0]) * c[1] * c[2];
  write_document(path, "ImageData", encoding, [&](std::ostream& out, VtkArrayEncoder& encoder) {
    const std::string extent =
        "0 " + std::to_string(c[0]) + " 0 " + std::to_string(c[1]) + " 0 " + std::to_string(c[2]);
    out << "<ImageData WholeExtent=\"" << extent << "\" Origin=\"" << image.origin[0] << ' '
        << image.origin[1] << ' ' << image.origin[2] << "\" Spacing=\"" << image.spacing << ' '
        << image.spacing << ' ' << image.spacing << "\">\n<Piece Extent=\"" << extent << "\">\n";
    write_arrays(out, encoder, "PointData", image.point_data, points, path);
    write_arrays(out, encoder, "CellData", image.cell_data, cells, path);
    out << "</Piece>\n</ImageData>\n";
  });
}

void write_vtp(const std::filesystem::path& path,
               const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>& vertices,
               const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>& triangles,
               const std::vector<DataArray>& point_data, VtkEncoding encoding) {
  write_document(path, "PolyData", encoding, [&](std::ostream& out, VtkArrayEncoder& encoder) {
    out << "<PolyData>\n<Piece NumberOfPoints=\"" << vertices.rows() << "\" NumberOfPolys=\""
        << triangles.rows() << "\">\n";
    write_arrays(out, encoder, "PointData", point_data, vertices.rows(), path);
    write_points(out, encoder, vertices);
    out << "<Polys>\n";
    write_cells(out, encoder, triangles, 0);
    out << "</Polys>\n</Piece>\n</PolyData>\n";
  });
}

void write_vtu(const std::filesystem::path& path, const Eigen::MatrixX3d& vertices,
               const Eigen::MatrixX4i& tets, const std::vector<DataArray>& point_data,
               const std::vector<DataArray>& cell_data, VtkEncoding encoding) {
  constexpr std::uint8_t kVtkTetra = 10;
  write_document(path, "UnstructuredGrid", encoding,
                 [&](std::ostream& out, VtkArrayEncoder& encoder) {
                   out << "<UnstructuredGrid>\n<Piece NumberOfPoints=\"" << vertices.rows()
                       << "\" NumberOfCells=\"" << tets.rows() << "\">\n";
                   write_points(out, encoder, vertices);
                   out << "<Cells>\n";
                   write_cells(out, encoder, tets, kVtkTetra);
                   out << "</Cells>\n";
                   write_arrays(out, encoder, "PointData", point_data, vertices.rows(), path);
                   write_arrays(out, encoder, "CellData", cell_data, tets.rows(), path);
                   out << "</Piece>\n</UnstructuredGrid>\n";
                 });
}

void write_pvd(const std::filesystem::path& path, const std::vector<SeriesEntry>& entries) {
  write_file_atomically(path, [&](std::ostream& out) {
    out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"Collection\" version=\"0.1\" "
           "byte_order=\"LittleEndian\">\n<Collection>\n";
    for (const auto& e : entries)
      out << "<DataSet timestep=\"" << e.time << "\" part=\"" << e.part << "\" file=\"" << e.file
          << "\"/>\n";
    out << "</Collection>\n</VTKFile>\n";
  });
}

}  // namespace mgelastic::io
