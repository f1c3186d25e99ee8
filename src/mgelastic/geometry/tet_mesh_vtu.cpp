#include "mgelastic/geometry/tet_mesh_vtu.hpp"

#include <fstream>
#include <system_error>

#include "mgelastic/core/error.hpp"

namespace mgelastic::geometry {

namespace {

void write_field(std::ostream& out, const VtuField& field, long rows, const std::string& where,
                 const std::string& file) {
  if (field.values.rows() != rows || field.values.cols() == 0)
    throw Error(where + " field has " + std::to_string(field.values.rows()) + " rows, expected " +
                    std::to_string(rows),
                ErrorContext{file, -1, field.name});
  out << "        <DataArray type=\"Float64\" Name=\"" << field.name << "\" NumberOfComponents=\""
      << field.values.cols() << "\" format=\"ascii\">\n";
  for (long r = 0; r < rows; ++r) {
    out << "         ";
    for (long c = 0; c < field.values.cols(); ++c) out << ' ' << field.values(r, c);
    out << '\n';
  }
  out << "        </DataArray>\n";
}

void write_geometry(std::ostream& out, const TetMesh& mesh) {
  out << "      <Points>\n        <DataArray type=\"Float64\" NumberOfComponents=\"3\" "
         "format=\"ascii\">\n";
  for (int v = 0; v < mesh.vertex_count(); ++v)
    out << "          " << mesh.vertices(v, 0) << ' ' << mesh.vertices(v, 1) << ' '
        << mesh.vertices(v, 2) << '\n';
  out << "        </DataArray>\n      </Points>\n      <Cells>\n";
  out << "        <DataArray type=\"Int32\" Name=\"connectivity\" format=\"ascii\">\n";
  for (int t = 0; t < mesh.tet_count(); ++t)
    out << "          " << mesh.tets(t, 0) << ' ' << mesh.tets(t, 1) << ' ' << mesh.tets(t, 2)
        << ' ' << mesh.tets(t, 3) << '\n';
  out << "        </DataArray>\n        <DataArray type=\"Int32\" Name=\"offsets\" "
         "format=\"ascii\">\n";
  for (int t = 0; t < mesh.tet_count(); ++t) out << "          " << 4 * (t + 1) << '\n';
  out << "        </DataArray>\n        <DataArray type=\"UInt8\" Name=\"types\" "
         "format=\"ascii\">\n";
  // 10 = VTK_TETRA
  for (int t = 0; t < mesh.tet_count(); ++t) out << "          10\n";
  out << "        </DataArray>\n      </Cells>\n";
}

void write_document(std::ostream& out, const TetMesh& mesh, std::span<const VtuField> point_data,
                    std::span<const VtuField> cell_data, const std::string& file) {
  out.precision(17);
  out << "<?xml version=\"1.0\"?>\n<VTKFile type=\"UnstructuredGrid\" version=\"1.0\" "
         "byte_order=\"LittleEndian\">\n  <UnstructuredGrid>\n    <Piece NumberOfPoints=\""
      << mesh.vertex_count() << "\" NumberOfCells=\"" << mesh.tet_count() << "\">\n";
  write_geometry(out, mesh);
  out << "      <PointData>\n";
  for (const VtuField& field : point_data)
    write_field(out, field, mesh.vertex_count(), "point", file);
  out << "      </PointData>\n      <CellData>\n";
  for (const VtuField& field : cell_data) write_field(out, field, mesh.tet_count(), "cell", file);
  if (mesh.element_tags.size() == mesh.tet_count() && mesh.tet_count() > 0) {
    out << "        <DataArray type=\"Int32\" Name=\"tag\" format=\"ascii\">\n";
    for (int t = 0; t < mesh.tet_count(); ++t) out << "          " << mesh.element_tags(t) << '\n';
    out << "        </DataArray>\n";
  }
  out << "      </CellData>\n    </Piece>\n  </UnstructuredGrid>\n</VTKFile>\n";
}

}  // namespace

void write_vtu(const std::filesystem::path& path, const TetMesh& mesh,
               std::span<const VtuField> point_data, std::span<const VtuField> cell_data) {
  const std::filesystem::path temporary = path.string() + ".tmp";
  const std::string file = path.string();
  {
    std::ofstream out(temporary, std::ios::trunc);
    if (!out)
      throw Error("cannot open for writing", ErrorContext{temporary.string(), -1, std::string()});
    try {
      write_document(out, mesh, point_data, cell_data, file);
    } catch (...) {
      out.close();
      std::filesystem::remove(temporary);
      throw;
    }
    out.flush();
    if (!out)
      throw Error("write failed (disk full?)", ErrorContext{temporary.string(), -1, std::string()});
  }
  std::error_code ec;
  std::filesystem::rename(temporary, path, ec);
  if (ec)
    throw Error("cannot rename temporary file: " + ec.message(),
                ErrorContext{file, -1, std::string()});
}

}  // namespace mgelastic::geometry
