#include "mgelastic/tet/tet_body.hpp"

#include <string>

#include "mgelastic/core/error.hpp"

namespace mgelastic::tet {

Eigen::Matrix3d tet_second_moment(const TetCorners& corners) {
  const Eigen::Vector3d centroid = corners.rowwise().mean();
  const Eigen::Matrix<double, 3, 4> r = corners.colwise() - centroid;
  return std::abs(tet_volume(corners)) / 20.0 * r * r.transpose();
}

TetBody::TetBody(const geometry::TetMesh& mesh, const ElementMaterials& materials)
    : m_tets(mesh.tets), m_materials(materials) {
  check_materials(materials, mesh.tet_count());
  const int n = mesh.vertex_count();
  m_rest.resize(3 * n);
  for (int v = 0; v < n; ++v) m_rest.segment<3>(3 * v) = mesh.vertices.row(v).transpose();
  const int m = mesh.tet_count();
  m_stiffness.resize(m);
  m_volume.resize(m);
  m_dm_inverse.resize(m);
  m_second_moment.resize(m);
  m_vertex_mass = Eigen::VectorXd::Zero(n);
  for (int e = 0; e < m; ++e) {
    for (int a = 0; a < 4; ++a)
      if (m_tets(e, a) < 0 || m_tets(e, a) >= n)
        throw Error("vertex index out of range",
                    ErrorContext{std::string(), -1, "element " + std::to_string(e)});
    const TetCorners rest = corners(e, m_rest);
    m_volume[e] = tet_volume(rest);
    if (!(m_volume[e] > 0.0))
      throw Error("non-positive rest volume (run geometry::check_tet_mesh first)",
                  ErrorContext{std::string(), -1, "element " + std::to_string(e)});
    m_stiffness[e] = element_stiffness(rest, materials[e]);
    m_dm_inverse[e] = tet::rest_edge_inverse(rest);
    m_second_moment[e] = tet_second_moment(rest);
    for (int a = 0; a < 4; ++a)
      m_vertex_mass[m_tets(e, a)] += materials.density[e] * m_volume[e] / 4.0;
  }
}

TetCorners TetBody::corners(int e, const Eigen::VectorXd& positions) const {
  TetCorners c;
  for (int a = 0; a < 4; ++a) c.col(a) = positions.segment<3>(3 * m_tets(e, a));
  return c;
}

}  // namespace mgelastic::tet
