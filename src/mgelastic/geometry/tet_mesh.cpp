#include "mgelastic/geometry/tet_mesh.hpp"

#include <Eigen/Geometry>
#include <cmath>
#include <utility>

#include "mgelastic/core/error.hpp"

namespace mgelastic::geometry {

Eigen::Matrix<double, 3, 4> TetMesh::corners(int t) const {
  Eigen::Matrix<double, 3, 4> c;
  for (int a = 0; a < 4; ++a) c.col(a) = vertices.row(tets(t, a)).transpose();
  return c;
}

double signed_volume6(const Eigen::Vector3d& p0, const Eigen::Vector3d& p1,
                      const Eigen::Vector3d& p2, const Eigen::Vector3d& p3) {
  return (p1 - p0).dot((p2 - p0).cross(p3 - p0));
}

namespace {

ErrorContext element_context(const std::string& source, const std::vector<long>& lines, int t) {
  ErrorContext context{source, -1, "element " + std::to_string(t)};
  if (t < static_cast<int>(lines.size())) context.line = lines[t];
  return context;
}

void check_vertices(const TetMesh& mesh, const std::string& source) {
  for (int v = 0; v < mesh.vertex_count(); ++v) {
    if (!mesh.vertices.row(v).allFinite())
      throw Error("non-finite vertex coordinate",
                  ErrorContext{source, -1, "vertex " + std::to_string(v)});
  }
}

void check_indices(const TetMesh& mesh, int t, const ErrorContext& context) {
  for (int a = 0; a < 4; ++a) {
    const int v = mesh.tets(t, a);
    if (v < 0 || v >= mesh.vertex_count())
      throw Error("vertex index " + std::to_string(v) + " out of range [0, " +
                      std::to_string(mesh.vertex_count()) + ")",
                  context);
    for (int b = 0; b < a; ++b)
      if (mesh.tets(t, b) == v)
        throw Error("vertex " + std::to_string(v) + " appears twice in one tetrahedron", context);
  }
}

double longest_edge(const Eigen::Matrix<double, 3, 4>& c) {
  double longest = 0.0;
  for (int a = 0; a < 4; ++a)
    for (int b = a + 1; b < 4; ++b) longest = std::max(longest, (c.col(a) - c.col(b)).norm());
  return longest;
}

}  // namespace

int check_tet_mesh(TetMesh& mesh, const TetMeshCheckOptions& options, const std::string& source,
                   const std::vector<long>& element_lines) {
  if (mesh.tet_count() == 0)
    throw Error("mesh has no tetrahedra", ErrorContext{source, -1, std::string()});
  if (mesh.element_tags.size() != 0 && mesh.element_tags.size() != mesh.tets.rows())
    throw Error("element tag count differs from tetrahedron count",
                ErrorContext{source, -1, std::string()});
  check_vertices(mesh, source);
  int flipped = 0;
  for (int t = 0; t < mesh.tet_count(); ++t) {
    const ErrorContext context = element_context(source, element_lines, t);
    check_indices(mesh, t, context);
    const Eigen::Matrix<double, 3, 4> c = mesh.corners(t);
    const double volume6 = signed_volume6(c.col(0), c.col(1), c.col(2), c.col(3));
    const double edge = longest_edge(c);
    // Zero volume is judged relative to the element's own size so the test is unit-free.
    if (std::abs(volume6) <= options.relative_zero_volume * edge * edge * edge)
      throw Error("zero-volume (degenerate) tetrahedron", context);
    if (volume6 < 0.0) {
      if (options.inverted == InvertedTets::REJECT)
        throw Error("inverted tetrahedron (negative signed volume)", context);
      std::swap(mesh.tets(t, 2), mesh.tets(t, 3));
      ++flipped;
    }
  }
  return flipped;
}

}  // namespace mgelastic::geometry
