#include "mgelastic/io/vtk_writers.hpp"

#include <iomanip>

#include "mgelastic/core/error.hpp"
#include "mgelastic/io/atomic_file.hpp"

namespace mgelastic::io {
namespace {

void write_array(std::ostream& out, const DataArray& a, std::size_t tuples,
                 const std::string& where) {
  if (a.values.size() != tuples * static_cast<std::size_t>(a.components))
    throw Error("array '" + a.name + "' has " + std::to_string(a.values.size()) +
                    " values, expected " + std::to_string(tuples * a.components),
                ErrorContext{.file = where});
  out << "<DataArray type=\"Float64\" Name=\"" << a.name << "\" NumberOfComponents=\""
      << a.components << "\" format=\"ascii\">\n";
  out << std::setprecision(9);
  for (std::size_t i = 0; i < a.values.size(); ++i)
    out << a.values[i] << ((i + 1) % 9 ? ' ' : '\n');
  out << "\n</DataArray>\n";
}

}  // namespace

void write_vti(const std::filesystem::path& path, const ImageData& image) {
  const auto& c = image.cells;
  const std::size_t points = std::size_t(c[0] + 1) * (c[1] + 1) * (c[2] + 1);
  const std::size_t cells = std::size_t(c[0]) * c[1] * c[2];
  write_file_atomically(path, [&](std::ostream& out) {
    out << std::setprecision(12)
        << "<?xml version=\"1.0\"?>\n<VTKFile type=\"ImageData\" version=\"0.1\" "
           "byte_order=\"LittleEndian\">\n<ImageData WholeExtent=\"0 "
        << c[0] << " 0 " << c[1] << " 0 " << c[2] << "\" Origin=\"" << image.origin[0] << ' '
        << image.origin[1] << ' ' << image.origin[2] << "\" Spacing=\"" << image.spacing << ' '
        << image.spacing << ' ' << image.spacing << "\">\n<Piece Extent=\"0 " << c[0] << " 0 "
        << c[1] << " 0 " << c[2] << "\">\n<PointData>\n";
    for (const auto& a : image.point_data) write_array(out, a, points, path.string());
    out << "</PointData>\n<CellData>\n";
    for (const auto& a : image.cell_data) write_array(out, a, cells, path.string());
    out << "</CellData>\n</Piece>\n</ImageData>\n</VTKFile>\n";
  });
}

void write_vtp(const std::filesystem::path& path,
               const Eigen::Matrix<double, Eigen::Dynamic, 3, Eigen::RowMajor>& vertices,
               const Eigen::Matrix<int, Eigen::Dynamic, 3, Eigen::RowMajor>& triangles,
               const std::vector<DataArray>& point_data) {
  write_file_atomically(path, [&](std::ostream& out) {
    out << std::setprecision(12)
        << "<?xml version=\"1.0\"?>\n<VTKFile type=\"PolyData\" version=\"0.1\" "
           "byte_order=\"LittleEndian\">\n<PolyData>\n<Piece NumberOfPoints=\""
        << vertices.rows() << "\" NumberOfPolys=\"" << triangles.rows() << "\">\n<PointData>\n";
    for (const auto& a : point_data) write_array(out, a, vertices.rows(), path.string());
    out << "</PointData>\n<Points>\n<DataArray type=\"Float64\" NumberOfComponents=\"3\" "
           "format=\"ascii\">\n";
    for (Eigen::Index i = 0; i < vertices.rows(); ++i)
      out << vertices(i, 0) << ' ' << vertices(i, 1) << ' ' << vertices(i, 2) << '\n';
    out << "</DataArray>\n</Points>\n<Polys>\n<DataArray type=\"Int64\" Name=\"connectivity\" "
           "format=\"ascii\">\n";
    for (Eigen::Index i = 0; i < triangles.rows(); ++i)
      out << triangles(i, 0) << ' ' << triangles(i, 1) << ' ' << triangles(i, 2) << '\n';
    out << "</DataArray>\n<DataArray type=\"Int64\" Name=\"offsets\" format=\"ascii\">\n";
    for (Eigen::Index i = 0; i < triangles.rows(); ++i) out << 3 * (i + 1) << '\n';
    out << "</DataArray>\n</Polys>\n</Piece>\n</PolyData>\n</VTKFile>\n";
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
