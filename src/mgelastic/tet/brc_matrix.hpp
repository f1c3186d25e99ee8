#pragma once
// Block-row-compressed (BRC) matrix (Georgii & Westermann 2008, Sec. 4.1): the Yale/CSR format
// with a dense 3x3 block instead of a scalar per stored (block row, block column).
//
// Layout: block row i owns the blocks k in [row_offsets[i], row_offsets[i+1]); block_columns[k]
// is the block column of block k, strictly increasing within a row; blocks[k] is its 3x3 value,
// contiguous in the same order. The scalar entry (3i + r, 3j + c) is blocks[k](r, c). The
// pattern is fixed at construction; values change (corotated re-assembly every step).
#include <Eigen/Core>
#include <Eigen/SparseCore>
#include <vector>

namespace mgelastic::tet {

template <class Scalar>
class BlockRowMatrix {
 public:
  using Block = Eigen::Matrix<Scalar, 3, 3>;
  using Vector = Eigen::Matrix<Scalar, Eigen::Dynamic, 1>;

  BlockRowMatrix() = default;
  // Takes a pattern; throws Error unless offsets are monotone and each row's columns are strictly
  // increasing, within [0, block_rows), and include the diagonal.
  BlockRowMatrix(std::vector<int> row_offsets, std::vector<int> block_columns);

  int block_rows() const { return static_cast<int>(m_row_offsets.size()) - 1; }
  int block_count() const { return static_cast<int>(m_block_columns.size()); }
  const std::vector<int>& row_offsets() const { return m_row_offsets; }
  const std::vector<int>& block_columns() const { return m_block_columns; }

  Block& block(int k) { return m_blocks[k]; }
  const Block& block(int k) const { return m_blocks[k]; }
  // Index of block (row, column) in the value array by binary search, or -1 when not stored.
  int find(int row, int column) const;
  int diagonal_index(int row) const { return m_diagonal[row]; }
  const Block& diagonal_block(int row) const { return m_blocks[m_diagonal[row]]; }

  void set_zero();
  // y = A x (parallel over block rows; x and y must not alias).
  void multiply(const Vector& x, Vector& y) const;
  Eigen::SparseMatrix<Scalar> to_sparse() const;

 private:
  std::vector<int> m_row_offsets{0};
  std::vector<int> m_block_columns;
  std::vector<int> m_diagonal;
  std::vector<Block> m_blocks;
};

extern template class BlockRowMatrix<double>;
extern template class BlockRowMatrix<float>;

// The pattern of a tetrahedral mesh's stiffness matrix: block (i, j) is stored when vertices i
// and j share a tetrahedron (and every diagonal block, so isolated vertices stay regular).
template <class Scalar>
BlockRowMatrix<Scalar> tet_block_pattern(const Eigen::MatrixX4i& tets, int vertex_count);

}  // namespace mgelastic::tet
