#include "mgelastic/geometry/tet_mesh_vtu.hpp"

#include "mgelastic/core/error.hpp"
#include "mgelastic/io/vtk_writers.hpp"

namespace mgelastic::geometry {
namespace {

// A field as a VTK array: rows are tuples, stored contiguously.
std::vector<io::DataArray> arrays(std::span<const VtuField> fields, long rows, const char* where,
                                  const std::filesystem::path& path) {
  std::vector<io::DataArray> result;
  for (const VtuField& field : fields) {
    if (field.values.rows() != rows || field.values.cols() == 0)
      throw Error(std::string(where) + " field has " + std::to_string(field.values.rows()) +
                      " rows, expected " + std::to_string(rows),
                  ErrorContext{path.string(), -1, field.name});
    const Eigen::Matrix<double, Eigen::Dynamic, Eigen::Dynamic, Eigen::RowMajor> tuples =
        field.values;
    result.push_back({field.name, static_cast<int>(tuples.cols()),
                      std::vector<double>(tuples.data(), tuples.data() + tuples.size())});
  }
  return result;
}

}  // namespace

void write_vtu(const std::filesystem::path& path, const TetMesh& mesh,
               std::span<const VtuField> point_data, std::span<const VtuField> cell_data,
               io::VtkEncoding encoding) {
  std::vector<io::DataArray> cells = arrays(cell_data, mesh.tet_count(), "cell", path);
  if (mesh.element_tags.size() == mesh.tet_count() && mesh.tet_count() > 0)
    cells.push_back({"tag", 1,
                     std::vector<double>(mesh.element_tags.begin(), mesh.element_tags.end()),
                     io::VtkScalar::INT32});
  io::write_vtu(path, mesh.vertices, mesh.tets,
                arrays(point_data, mesh.vertex_count(), "point", path), cells, encoding);
}

}  // namespace mgelastic::geometry
