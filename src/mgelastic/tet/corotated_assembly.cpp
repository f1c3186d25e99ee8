#include "mgelastic/tet/corotated_assembly.hpp"

#include "mgelastic/tet/parallel.hpp"

namespace mgelastic::tet {

namespace {

// Counting sort of (key, value) pairs into CSR with values in their input order per key.
void build_csr(const std::vector<int>& keys, int key_count, std::vector<int>& offsets,
               std::vector<int>& values) {
  offsets.assign(key_count + 1, 0);
  for (int key : keys) ++offsets[key + 1];
  for (int k = 0; k < key_count; ++k) offsets[k + 1] += offsets[k];
  values.resize(keys.size());
  std::vector<int> fill(offsets.begin(), offsets.end() - 1);
  for (std::size_t i = 0; i < keys.size(); ++i) values[fill[keys[i]]++] = static_cast<int>(i);
}

}  // namespace

Matrix12d rotate_stiffness(const Matrix12d& k, const Eigen::Matrix3d& q) {
  Matrix12d rotated;
  for (int a = 0; a < 4; ++a)
    for (int b = 0; b < 4; ++b)
      rotated.block<3, 3>(3 * a, 3 * b).noalias() = q * k.block<3, 3>(3 * a, 3 * b) * q.transpose();
  return rotated;
}

CorotatedAssembler::CorotatedAssembler(const TetBody& body)
    : m_body(&body),
      m_stiffness(tet_block_pattern<double>(body.tets(), body.vertex_count())),
      m_refs(body.element_count()) {
  const Eigen::MatrixX4i& tets = body.tets();
  std::vector<int> block_of_source(16 * static_cast<std::size_t>(body.element_count()));
  std::vector<int> vertex_of_corner(4 * static_cast<std::size_t>(body.element_count()));
  for (int e = 0; e < body.element_count(); ++e)
    for (int a = 0; a < 4; ++a) {
      vertex_of_corner[4 * e + a] = tets(e, a);
      for (int b = 0; b < 4; ++b) {
        m_refs[e][4 * a + b] = m_stiffness.find(tets(e, a), tets(e, b));
        block_of_source[16 * e + 4 * a + b] = m_refs[e][4 * a + b];
      }
    }
  m_gradients.resize(body.element_count());
  m_lame_volume.resize(body.element_count());
  m_rotated.resize(body.element_count());
  for (int e = 0; e < body.element_count(); ++e) {
    m_gradients[e] = shape_gradients(body.rest_edge_inverse(e));
    m_lame_volume[e] = body.volume(e) * lame_parameters(body.materials()[e]);
  }
  // Rotation-independent part of every block: sum over its sources of mu V (g_a . g_b).
  const int blocks = m_stiffness.block_count();
  m_shifts.assign(blocks, 0.0);
  for (int e = 0; e < body.element_count(); ++e)
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        m_shifts[m_refs[e][4 * a + b]] +=
            m_lame_volume[e][1] * m_gradients[e].col(a).dot(m_gradients[e].col(b));
  // Only upper blocks (row <= column) are gathered; a lower block is its mirror's transpose.
  std::vector<int> row_of_block(blocks);
  for (int i = 0; i < m_stiffness.block_rows(); ++i)
    for (int k = m_stiffness.row_offsets()[i]; k < m_stiffness.row_offsets()[i + 1]; ++k)
      row_of_block[k] = i;
  m_mirror.assign(blocks, -1);
  for (int k = 0; k < blocks; ++k) {
    const int column = m_stiffness.block_columns()[k];
    if (column < row_of_block[k]) m_mirror[k] = m_stiffness.find(column, row_of_block[k]);
  }
  for (int& block : block_of_source)
    if (m_mirror[block] >= 0) block = blocks;  // dropped: sorted past the last block
  build_csr(block_of_source, blocks + 1, m_source_offsets, m_sources);
  build_csr(vertex_of_corner, body.vertex_count(), m_corner_offsets, m_corners);
}

void CorotatedAssembler::assemble(const RotationField& rotations) {
  const int elements = m_body->element_count();
#pragma omp parallel for schedule(static) if (elements >= kMinParallelElements)
  for (int e = 0; e < elements; ++e) {
    m_rotated[e].topRows<3>().noalias() = rotations.rotation(e) * m_gradients[e];
    m_rotated[e].row(3).setZero();
  }
  const int count = m_stiffness.block_count();
#pragma omp parallel if (count >= kMinParallelItems)
  {
#pragma omp for schedule(static)
    for (int k = 0; k < count; ++k) {
      if (m_mirror[k] >= 0) continue;
      // Columns of lambda V h_a h_b^T + mu V h_b h_a^T as whole 4-vectors (padded rows).
      Eigen::Matrix<double, 4, 3> sum = Eigen::Matrix<double, 4, 3>::Zero();
      for (int s = m_source_offsets[k]; s < m_source_offsets[k + 1]; ++s) {
        const int e = m_sources[s] / 16, local = m_sources[s] % 16;
        const Eigen::Vector4d ha = m_rotated[e].col(local / 4), hb = m_rotated[e].col(local % 4);
        const Eigen::Vector4d u = m_lame_volume[e][0] * ha, v = m_lame_volume[e][1] * hb;
        for (int j = 0; j < 3; ++j) sum.col(j) += u * hb[j] + v * ha[j];
      }
      Eigen::Matrix3d& block = m_stiffness.block(k);
      block = sum.topRows<3>();
      block.diagonal().array() += m_shifts[k];
    }
    // After the barrier: a mirror block may belong to another thread's range.
#pragma omp for schedule(static)
    for (int k = 0; k < count; ++k)
      if (m_mirror[k] >= 0) m_stiffness.block(k) = m_stiffness.block(m_mirror[k]).transpose();
  }
}

void CorotatedAssembler::assemble_by_search(const RotationField& rotations) {
  const Eigen::MatrixX4i& tets = m_body->tets();
  m_stiffness.set_zero();
  for (int e = 0; e < m_body->element_count(); ++e) {
    const Eigen::Matrix3d& q = rotations.rotation(e);
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b)
        m_stiffness.block(m_stiffness.find(tets(e, a), tets(e, b))).noalias() +=
            q * m_body->stiffness(e).block<3, 3>(3 * a, 3 * b) * q.transpose();
  }
}

Eigen::VectorXd CorotatedAssembler::elastic_forces(const RotationField& rotations,
                                                   const Eigen::VectorXd& x) const {
  const Eigen::VectorXd& rest = m_body->rest_positions();
  const Eigen::MatrixX4i& tets = m_body->tets();
  const int count = m_body->element_count();
  // Element forces first (independent), then a gather per vertex (no write conflicts).
  Eigen::VectorXd element_forces(12 * static_cast<Eigen::Index>(count));
#pragma omp parallel for schedule(static) if (count >= kMinParallelElements)
  for (int e = 0; e < count; ++e) {
    const Eigen::Matrix3d& q = rotations.rotation(e);
    // Unrotate the deformed element into the rest frame, apply K (as V sigma(H) g_a), rotate the
    // forces back.
    Eigen::Matrix3d h = Eigen::Matrix3d::Zero();
    for (int a = 0; a < 4; ++a)
      h.noalias() +=
          (q.transpose() * x.segment<3>(3 * tets(e, a)) - rest.segment<3>(3 * tets(e, a))) *
          m_gradients[e].col(a).transpose();
    Eigen::Matrix3d stress = m_lame_volume[e][1] * (h + h.transpose());
    stress.diagonal().array() += m_lame_volume[e][0] * h.trace();
    const Eigen::Matrix3d rotated_stress = q * stress;
    for (int a = 0; a < 4; ++a)
      element_forces.segment<3>(12 * e + 3 * a).noalias() =
          -(rotated_stress * m_gradients[e].col(a));
  }
  const int n = m_body->vertex_count();
  Eigen::VectorXd forces(3 * static_cast<Eigen::Index>(n));
#pragma omp parallel for schedule(static) if (n >= kMinParallelItems)
  for (int v = 0; v < n; ++v) {
    Eigen::Vector3d sum = Eigen::Vector3d::Zero();
    for (int c = m_corner_offsets[v]; c < m_corner_offsets[v + 1]; ++c)
      sum += element_forces.segment<3>(3 * m_corners[c]);
    forces.segment<3>(3 * v) = sum;
  }
  return forces;
}

double CorotatedAssembler::elastic_energy(const RotationField& rotations,
                                          const Eigen::VectorXd& x) const {
  const Eigen::VectorXd& rest = m_body->rest_positions();
  const Eigen::MatrixX4i& tets = m_body->tets();
  double energy = 0.0;
  const int count = m_body->element_count();
#pragma omp parallel for schedule(static) if (count >= kMinParallelElements) reduction(+ : energy)
  for (int e = 0; e < count; ++e) {
    const Eigen::Matrix3d& q = rotations.rotation(e);
    Vector12d d;
    for (int a = 0; a < 4; ++a)
      d.segment<3>(3 * a) =
          q.transpose() * x.segment<3>(3 * tets(e, a)) - rest.segment<3>(3 * tets(e, a));
    energy += 0.5 * d.dot(m_body->stiffness(e) * d);
  }
  return energy;
}

}  // namespace mgelastic::tet
