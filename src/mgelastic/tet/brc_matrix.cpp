#include "mgelastic/tet/brc_matrix.hpp"
#include "mgelastic/tet/parallel.hpp"

#include <algorithm>
#include <string>

#include "mgelastic/core/error.hpp"

namespace mgelastic::tet {

template <class Scalar>
BlockRowMatrix<Scalar>::BlockRowMatrix(std::vector<int> row_offsets, std::vector<int> block_columns)
    : m_row_offsets(std::move(row_offsets)), m_block_columns(std::move(block_columns)) {
  const auto fail = [](const std::string& reason) {
    throw Error(reason, ErrorContext{std::string(), -1, "BlockRowMatrix"});
  };
  if (m_row_offsets.empty() || m_row_offsets.front() != 0 ||
      m_row_offsets.back() != static_cast<int>(m_block_columns.size()))
    fail("row offsets must start at 0 and end at the block count");
  const int rows = block_rows();
  m_diagonal.assign(rows, -1);
  for (int i = 0; i < rows; ++i) {
    if (m_row_offsets[i + 1] < m_row_offsets[i]) fail("row offsets must not decrease");
    for (int k = m_row_offsets[i]; k < m_row_offsets[i + 1]; ++k) {
      const int j = m_block_columns[k];
      if (j < 0 || j >= rows || (k > m_row_offsets[i] && m_block_columns[k - 1] >= j))
        fail("block columns of row " + std::to_string(i) + " not strictly increasing in range");
      if (j == i) m_diagonal[i] = k;
    }
    if (m_diagonal[i] < 0) fail("row " + std::to_string(i) + " has no diagonal block");
  }
  m_blocks.assign(m_block_columns.size(), Block::Zero());
}

template <class Scalar>
int BlockRowMatrix<Scalar>::find(int row, int column) const {
  const auto begin = m_block_columns.begin() + m_row_offsets[row];
  const auto end = m_block_columns.begin() + m_row_offsets[row + 1];
  const auto found = std::lower_bound(begin, end, column);
  return found != end && *found == column ? static_cast<int>(found - m_block_columns.begin()) : -1;
}

template <class Scalar>
void BlockRowMatrix<Scalar>::set_zero() {
  const int count = block_count();
#pragma omp parallel for schedule(static) if (count >= kMinParallelItems)
  for (int k = 0; k < count; ++k) m_blocks[k].setZero();
}

template <class Scalar>
void BlockRowMatrix<Scalar>::multiply(const Vector& x, Vector& y) const {
  const int rows = block_rows();
  y.resize(3 * rows);
  // Each block row writes only its own three entries of y: no races, no atomics.
#pragma omp parallel for schedule(static) if (rows >= kMinParallelItems)
  for (int i = 0; i < rows; ++i) {
    Eigen::Matrix<Scalar, 3, 1> sum = Eigen::Matrix<Scalar, 3, 1>::Zero();
    for (int k = m_row_offsets[i]; k < m_row_offsets[i + 1]; ++k)
      sum.noalias() += m_blocks[k] * x.template segment<3>(3 * m_block_columns[k]);
    y.template segment<3>(3 * i) = sum;
  }
}

template <class Scalar>
Eigen::SparseMatrix<Scalar> BlockRowMatrix<Scalar>::to_sparse() const {
  std::vector<Eigen::Triplet<Scalar>> triplets;
  triplets.reserve(9 * m_blocks.size());
  for (int i = 0; i < block_rows(); ++i)
    for (int k = m_row_offsets[i]; k < m_row_offsets[i + 1]; ++k)
      for (int r = 0; r < 3; ++r)
        for (int c = 0; c < 3; ++c)
          triplets.emplace_back(3 * i + r, 3 * m_block_columns[k] + c, m_blocks[k](r, c));
  Eigen::SparseMatrix<Scalar> sparse(3 * block_rows(), 3 * block_rows());
  sparse.setFromTriplets(triplets.begin(), triplets.end());
  return sparse;
}

template <class Scalar>
BlockRowMatrix<Scalar> tet_block_pattern(const Eigen::MatrixX4i& tets, int vertex_count) {
  // Collect each vertex's neighbours (itself included), then sort and deduplicate per row.
  std::vector<std::vector<int>> neighbours(vertex_count);
  for (int v = 0; v < vertex_count; ++v) neighbours[v].push_back(v);
  for (int e = 0; e < tets.rows(); ++e)
    for (int a = 0; a < 4; ++a)
      for (int b = 0; b < 4; ++b) neighbours[tets(e, a)].push_back(tets(e, b));
  std::vector<int> offsets{0};
  std::vector<int> columns;
  for (std::vector<int>& row : neighbours) {
    std::sort(row.begin(), row.end());
    row.erase(std::unique(row.begin(), row.end()), row.end());
    columns.insert(columns.end(), row.begin(), row.end());
    offsets.push_back(static_cast<int>(columns.size()));
    std::vector<int>().swap(row);
  }
  return BlockRowMatrix<Scalar>(std::move(offsets), std::move(columns));
}

template class BlockRowMatrix<double>;
template class BlockRowMatrix<float>;
template BlockRowMatrix<double> tet_block_pattern<double>(const Eigen::MatrixX4i&, int);
template BlockRowMatrix<float> tet_block_pattern<float>(const Eigen::MatrixX4i&, int);

}  // namespace mgelastic::tet
